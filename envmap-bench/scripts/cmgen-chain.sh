#!/usr/bin/env bash
# cmgen-chain.sh IN SIZE OUTDIR
#
# Filament's cmgen prefiltered specular chain (GGX, its importance sampling),
# as files envmap reads, in envmap's default GL cube world, so that it can be
# measured against envmap's exact reference of the same input.
#
#   IN      a latlong (2:1) environment map envmap reads (.exr of any
#           compression, .hdr, .png ...), read in its own convention (what
#           the file says, else envmap's default, as `envmap convert` does)
#   SIZE    cmgen's base face size, a power of two (e.g. 128)
#   OUTDIR  created if missing; gets
#             level<k>.exr  level k as an envmap cube: horizontal strip
#                           (6·s × s; faces +x −x +y −y +z −z), float32,
#                           GL face table on the GL world (y up)
#             levels.txt    "k size roughness" per line (perceptual roughness
#                           of cmgen's rule: r = 1 − sqrt(1 − k/(n − 1)), the
#                           inverse of Filament's lod = r(2 − r)(n − 1))
#             cmgen.log     cmgen's command line and messages
#
# Orientation (measured with cmgen 1.9.25): cmgen --no-mirror's faces,
# m<k>_px.exr ... m<k>_nz.exr, loaded as an envmap six-file cube ('px' names,
# no face transform) equal `envmap convert IN --to cube` in the default
# convention; cmgen's default mirroring (x → −x) would need the latlong read
# with `--convention cmgen` instead, so this script always passes --no-mirror.
#
# Steps: envmap copies IN texel for texel (nearest, 1 sample, same size: a
# bit-exact copy for a latlong) into an RLE scan-line EXR, which cmgen 1.9.25
# reads (it reads no DWAA/DWAB EXR and misreads tiled ones); cmgen writes its
# chain as six half-float PIZ EXR faces per level; envmap packs each level
# into a strip (lossless: cube to cube at the same size, nearest).
#
# Environment: ENVMAP (envmap binary; default target/release/envmap, built
# if missing), CMGEN (default: cmgen on PATH), CMGEN_SAMPLES (--ibl-samples,
# cmgen's default 1024), CMGEN_MIN_LOD_SIZE (--ibl-min-lod-size, default 16),
# KEEP_FACES=1 (keep cmgen's own face files in OUTDIR/cmgen-faces).
#
# Prints cmgen's wall time for the prefilter step (from its "IBL
# prefiltering..." message to its exit, so it includes writing the level
# files) and for the whole cmgen run.
set -euo pipefail

die() { echo "cmgen-chain.sh: $*" >&2; exit 1; }

[ $# -eq 3 ] || { sed -n '2,40p' "$0" | sed 's/^# \{0,1\}//' >&2; exit 2; }
IN=$1 SIZE=$2 OUTDIR=$3

CMGEN=${CMGEN:-cmgen}
command -v "$CMGEN" >/dev/null 2>&1 || die "cmgen not found ('$CMGEN'): install it, e.g. \
'apt-get install -y libfilament-tools' (Debian: cmgen 1.9.25), or set CMGEN=/path/to/cmgen"

[[ $SIZE =~ ^[0-9]+$ ]] && [ "$SIZE" -ge 1 ] && [ $((SIZE & (SIZE - 1))) -eq 0 ] \
    || die "SIZE must be a power of two (cmgen's --size), got '$SIZE'"
[ -f "$IN" ] || die "no such input file: $IN"

ROOT=$(cd "$(dirname "$0")/../.." && pwd)
ENVMAP=${ENVMAP:-$ROOT/target/release/envmap}
if [ ! -x "$ENVMAP" ]; then
    echo "cmgen-chain.sh: building envmap ($ENVMAP)" >&2
    (cd "$ROOT" && cargo build --release -q -p envmap-cli) \
        || die "could not build envmap"
fi

now() { echo "${EPOCHREALTIME:-$(date +%s.%N)}"; }

WORK=$(mktemp -d "${TMPDIR:-/tmp}/cmgen-chain.XXXXXX")
trap 'rm -rf "$WORK"' EXIT

# 1. IN -> a latlong cmgen reads, texel for texel.
INFO=$("$ENVMAP" info "$IN") || die "envmap cannot read $IN"
MAPPING=$(awk '$1 == "mapping" {print $2}' <<<"$INFO")
WIDTH=$(awk '$1 == "dimensions" {print $2}' <<<"$INFO")
[ "$MAPPING" = latlong ] || die "$IN is a '$MAPPING' map; give a latlong (2:1), or convert it first \
(envmap convert IN in.exr --to latlong)"
SRC=$WORK/in.exr
"$ENVMAP" convert "$IN" "$SRC" --to latlong --size "$WIDTH" --to-convention envmap \
    --filter nearest --samples 1 -q || die "envmap could not copy $IN to $SRC"

# 2. cmgen's chain, unmirrored, as EXR faces per level.
ARGS=(--no-mirror --format=exr --size="$SIZE" --ibl-ld="$WORK/ld")
[ -n "${CMGEN_SAMPLES:-}" ] && ARGS+=(--ibl-samples="$CMGEN_SAMPLES")
[ -n "${CMGEN_MIN_LOD_SIZE:-}" ] && ARGS+=(--ibl-min-lod-size="$CMGEN_MIN_LOD_SIZE")
mkdir -p "$WORK/ld" "$OUTDIR"
LOG=$OUTDIR/cmgen.log
echo "$CMGEN ${ARGS[*]} $SRC   (SRC: texel copy of $IN)" >"$LOG"
T0=$(now)
TPRE=
set +e
while IFS= read -r line; do
    line=$(sed 's/\x1b\[[0-9;?]*[A-Za-z]//g' <<<"$line")
    case $line in
        *%*|'') continue ;;                               # progress bar
        *"IBL prefiltering"*) TPRE=$(now) ;;
    esac
    echo "$line" >>"$LOG"
done < <("$CMGEN" "${ARGS[@]}" "$SRC" 2>&1 | stdbuf -o0 tr '\r' '\n'; echo "__rc=${PIPESTATUS[0]}")
set -e
T1=$(now)
RC=$(sed -n 's/^__rc=//p' "$LOG"); sed -i '/^__rc=/d' "$LOG"
[ "$RC" = 0 ] || { cat "$LOG" >&2; die "cmgen failed (exit $RC); its messages are in $LOG"; }

FACES=$WORK/ld/in
[ -f "$FACES/m0_px.exr" ] || die "cmgen wrote no $FACES/m0_px.exr (see $LOG)"
N=$(find "$FACES" -name 'm*_px.exr' | wc -l)

# 3. Each level -> an envmap strip; levels.txt.
: >"$OUTDIR/levels.txt"
for ((k = 0; k < N; k++)); do
    for f in px nx py ny pz nz; do
        [ -f "$FACES/m${k}_$f.exr" ] || die "cmgen level $k lacks its $f face"
    done
    s=$((SIZE >> k))
    "$ENVMAP" convert "$FACES/m${k}_px.exr" "$OUTDIR/level$k.exr" --to cube --layout strip \
        --size "$s" --filter nearest --samples 1 -q || die "envmap could not read cmgen's level $k"
    r=$(awk -v k="$k" -v n="$N" 'BEGIN { t = (n > 1) ? k / (n - 1) : 0; printf "%.6f", 1 - sqrt(1 - t) }')
    # cmgen prints its own: "Level k, roughness = a, roughness (perceptual) = r"
    rc=$(sed -n "s/^Level $k, .*roughness (perceptual) = \([0-9.e+-]*\).*/\1/p" "$LOG" | head -1)
    if [ -n "$rc" ] && awk -v a="$r" -v b="$rc" 'BEGIN { d = a - b; exit !(d > 0.001 || d < -0.001) }'; then
        echo "cmgen-chain.sh: warning: level $k: rule gives r = $r, cmgen printed $rc" >&2
    fi
    echo "$k $s $r" >>"$OUTDIR/levels.txt"
done
if [ "${KEEP_FACES:-0}" = 1 ]; then
    rm -rf "$OUTDIR/cmgen-faces"; cp -r "$FACES" "$OUTDIR/cmgen-faces"
fi

TOTAL=$(awk -v a="$T0" -v b="$T1" 'BEGIN { printf "%.3f", b - a }')
if [ -n "$TPRE" ]; then
    PRE=$(awk -v a="$TPRE" -v b="$T1" 'BEGIN { printf "%.3f", b - a }')
else
    PRE="$TOTAL (no 'IBL prefiltering' message seen: whole run)"
fi
echo "cmgen $(dpkg-query -W -f='${Version}' libfilament-tools 2>/dev/null || echo '(version unknown)'): $N levels from $SIZE², samples ${CMGEN_SAMPLES:-1024 (default)}"
echo "cmgen prefilter wall time: ${PRE} s (whole cmgen run ${TOTAL} s)"
echo "wrote $OUTDIR/level{0..$((N - 1))}.exr and $OUTDIR/levels.txt:"
sed 's/^/  /' "$OUTDIR/levels.txt"
