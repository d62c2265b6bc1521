#!/usr/bin/env bash
# fetch-hdris.sh [DIR] — fetch 18 small CC0 HDRIs (512 × 256 OpenEXR) into DIR
# (default: target/hdri) for tests, benchmarks and docs.
#
# Source: the npm package @pmndrs/assets 1.7.0 (https://github.com/pmndrs/assets,
# licence CC0-1.0). Its package/hdri/NAME.exr.js files are JavaScript modules
# whose default export is a `data:application/exr;base64,...` URL; the images
# are Poly Haven HDRIs (https://polyhaven.com), CC0 1.0
# (https://creativecommons.org/publicdomain/zero/1.0/). This script runs
# `npm pack @pmndrs/assets@1.7.0` (the tarball is kept in DIR and reused),
# extracts package/hdri/*.exr.js, decodes each URL's base64 payload with
# coreutils `base64 -d` to DIR/NAME.exr, and checks each file starts with the
# OpenEXR magic number 76 2f 31 01.
#
# Idempotent: when all 18 files exist, are non-empty and start with the magic,
# it says so and exits 0 without touching the network.
# Needs: bash, npm (only when a file is missing and no tarball is cached), tar,
# base64 and coreutils (od, wc, paste, ...), grep, sed.
set -euo pipefail

VERSION=1.7.0
PKG="@pmndrs/assets@${VERSION}"
TARBALL="pmndrs-assets-${VERSION}.tgz"
NAMES=(apartment bridge city dawn esplanade forest hall lab lobby night park
       sky studio sunrise sunset venice warehouse workshop)
EXR_MAGIC="762f3101"

DIR="${1:-target/hdri}"

die() { echo "fetch-hdris: $*" >&2; exit 1; }

# npm's error output, trimmed to its first few meaningful lines, on one line.
npm_summary() {
    printf '%s\n' "$1" \
        | grep -v -e '^npm error *at ' -e "^npm error   [a-z]*: " -e '^npm error }$' \
                  -e '^npm error *$' -e 'complete log of this run' \
        | sed 's/^npm \(error\|ERR!\) //' | head -n 4 | paste -sd ';' - | sed 's/;/; /g'
}

# The first four bytes of a file, as hex ("" for a missing or short file).
magic() { od -An -tx1 -N4 "$1" 2>/dev/null | tr -d ' \n'; }

licence() {
    echo "Licence: CC0 1.0 (https://creativecommons.org/publicdomain/zero/1.0/);"
    echo "         HDRIs from Poly Haven (https://polyhaven.com), via npm ${PKG}."
}

all_present() {
    local n f
    for n in "${NAMES[@]}"; do
        f="$DIR/$n.exr"
        [[ -s "$f" && "$(magic "$f")" == "$EXR_MAGIC" ]] || return 1
    done
}

mkdir -p "$DIR"

if all_present; then
    echo "fetch-hdris: all ${#NAMES[@]} HDRIs already in $DIR (valid EXR magic); nothing to do."
    licence
    exit 0
fi

for tool in tar base64 od; do
    command -v "$tool" >/dev/null 2>&1 || die "'$tool' is required but not installed"
done

TMP="$(mktemp -d)"
trap 'rm -rf "$TMP"; rm -f "$DIR"/*.exr.tmp' EXIT

if [[ -s "$DIR/$TARBALL" ]] && tar -tzf "$DIR/$TARBALL" >/dev/null 2>&1; then
    echo "fetch-hdris: reusing cached $DIR/$TARBALL"
else
    command -v npm >/dev/null 2>&1 \
        || die "npm is required to fetch ${PKG} but is not installed (install Node.js/npm, or put $TARBALL in $DIR)"
    echo "fetch-hdris: npm pack ${PKG} ..."
    if ! out="$(cd "$TMP" && npm pack --loglevel=error "$PKG" 2>&1)"; then
        die "npm pack ${PKG} failed: $(npm_summary "$out")"
    fi
    [[ -s "$TMP/$TARBALL" ]] \
        || die "npm pack ${PKG} failed: no $TARBALL was written (npm said: $(npm_summary "$out"))"
    mv "$TMP/$TARBALL" "$DIR/$TARBALL"
fi

tar -xzf "$DIR/$TARBALL" -C "$TMP" --wildcards 'package/hdri/*.exr.js' \
    || die "could not extract package/hdri/*.exr.js from $DIR/$TARBALL"

PREFIX="export default 'data:application/exr;base64,"
total=0
for n in "${NAMES[@]}"; do
    js="$TMP/package/hdri/$n.exr.js"
    out="$DIR/$n.exr"
    [[ -s "$js" ]] || die "package/hdri/$n.exr.js is missing from $TARBALL"
    body="$(<"$js")"
    [[ "$body" == "$PREFIX"* ]] \
        || die "package/hdri/$n.exr.js does not start with: $PREFIX"
    b64="${body#"$PREFIX"}"
    b64="${b64%%\'*}"
    printf '%s' "$b64" | base64 -d >"$out.tmp" \
        || { rm -f "$out.tmp"; die "package/hdri/$n.exr.js: base64 payload does not decode"; }
    m="$(magic "$out.tmp")"
    if [[ "$m" != "$EXR_MAGIC" ]]; then
        rm -f "$out.tmp"
        die "$n.exr: decoded file does not start with the EXR magic 76 2f 31 01 (got '${m:-nothing}')"
    fi
    mv "$out.tmp" "$out"
    size=$(wc -c <"$out")
    total=$((total + size))
    printf '  %-10s %8d bytes  %s\n' "$n" "$size" "$out"
done

echo "fetch-hdris: ${#NAMES[@]} HDRIs (512 × 256 EXR, $total bytes in all) in $DIR from ${PKG}"
licence
