#!/usr/bin/env bash
# same-outputs.sh — run a fixed list of `envmap` commands and check that two runs
# (two builds of the command) wrote the same outputs.
#
#   scripts/same-outputs.sh run ENVMAP_BINARY OUTDIR
#       Runs every command of the list below with ENVMAP_BINARY. Each command gets
#       its own folder OUTDIR/NAME holding what it wrote, plus:
#         command.txt   the command line, as written in this script (see "Paths");
#         stdout.txt    for `info`, `map` and `unmap`: standard output, which IS
#                       their output (compared byte for byte);
#         stdout.log, stderr.log
#                       everything else printed (progress, timings, warnings): kept
#                       for reading, never compared.
#       OUTDIR/commands.txt lists every command in order. OUTDIR must be missing or
#       empty. Stops at the first command that fails.
#
#   scripts/same-outputs.sh compare DIR_A DIR_B
#       Compares two OUTDIRs: the same file list; every file byte for byte (cmp),
#       except
#         *.json       compared after normalisation: keys holding timings (names
#                      mentioning seconds / ms / time / timing / duration / elapsed)
#                      and the writer's own name and version (the manifest's
#                      top-level "envmap": "envmap 0.1.0") are removed;
#         *.exr        byte for byte once the header's attributes are put in name
#                      order (envmap writes its own attributes in a fixed order, a
#                      build of another writer may not: see compare);
#         report.md    (the demo's report) compared with its timing columns blanked;
#         *.log        only required to exist on both sides.
#       Prints one line per difference and a final line "N same, M different";
#       exits 1 if anything differs.
#
# Inputs are only files in this repository (test-data/hdri/*.exr: four 512 × 256
# latlong OpenEXR files), the built-in environments (sky, room), or files written
# by an earlier command of the list. Sizes are kept small: the whole run takes
# well under a minute on two cores.
#
# Paths. Every command runs from the repository root, so repository inputs are
# written relative to it (test-data/...). In the list, `@/` stands for the
# command's own folder (OUTDIR/NAME/) and `@@/` for OUTDIR/. A command that reads
# an earlier command's output (`@@/` in its arguments) runs from OUTDIR instead,
# with OUTDIR-relative paths: what it records of its inputs (`info` prints the
# file name; a bake's manifest.json records its input's path) is then the same
# whatever OUTDIR is. Such a command must not also read repository files.
#
# Needs: bash, coreutils (realpath, cmp, comm, find, sort), awk, python3.
set -euo pipefail

die() { echo "same-outputs: $*" >&2; exit 2; }

usage() {
    sed -n '2,30p' "$0" | sed 's/^# \{0,1\}//' >&2
    exit 2
}

# ---------------------------------------------------------------------------
# run
# ---------------------------------------------------------------------------

# step NAME SUBCOMMAND ARGS...
# Runs `envmap SUBCOMMAND ARGS...` with its outputs in OUTDIR/NAME (see "Paths"
# above for `@/` and `@@/`). `map` and `unmap` read this function's standard
# input; every other command reads /dev/null.
step() {
    local name=$1
    shift
    local sub=$1
    local dir="$OUT/$name"
    [[ -e $dir ]] && die "step name used twice: $name"
    mkdir -p "$dir"

    # Where to run, and what the placeholders become there.
    local cwd=$ROOT here="$OUT/$name/" top="$OUT/" a
    for a in "$@"; do
        if [[ $a == *@@/* ]]; then
            cwd=$OUT here="$name/" top=""
        fi
    done
    local args=()
    for a in "$@"; do
        if [[ $cwd == "$OUT" && $a == *test-data/* ]]; then
            die "$name: reads both a repository file and an earlier output"
        fi
        a=${a//@@\//$top}
        a=${a//@\//$here}
        args+=("$a")
    done

    # Which stream is the output.
    local out_file=stdout.log
    case $sub in info | map | unmap) out_file=stdout.txt ;; esac

    printf 'envmap %s\n' "$*" >"$dir/command.txt"
    printf '%s: envmap %s\n' "$name" "$*" >>"$OUT/commands.txt"

    local t0 t1 rc=0
    t0=$(date +%s.%N)
    case $sub in
        map | unmap)
            (cd "$cwd" && "$BIN" "${args[@]}") >"$dir/$out_file" 2>"$dir/stderr.log" || rc=$? ;;
        *)
            (cd "$cwd" && "$BIN" "${args[@]}") >"$dir/$out_file" 2>"$dir/stderr.log" </dev/null || rc=$? ;;
    esac
    t1=$(date +%s.%N)
    if ((rc != 0)); then
        echo "FAILED (exit $rc): $name: envmap $*" >&2
        tail -n 5 "$dir/stderr.log" >&2
        exit 1
    fi
    awk -v n="$name" -v a="$t0" -v b="$t1" 'BEGIN { printf "%-40s %6.2f s\n", n, b - a }'
}

# Directions for `map`: the axes, diagonals, the seams and poles of the mappings
# (latlong's -z seam, the paraboloids' equator, the sphere maps' back point),
# unnormalised and negative-zero inputs, and a few generic ones.
DIRECTIONS='x,y,z
1 0 0
-1 0 0
0 1 0
0 -1 0
0 0 1
0 0 -1
1 1 1
-1 -1 -1
0.3 -0.5 0.8
-0.3,0.5,-0.8
2 0 -2
1 0 0.0000001
-0 1 0
0.001 0.999 0.002
0.57735 -0.57735 -0.57735
-0.7071 0 0.7071
0 0.7071 -0.7071
# a comment line, skipped
12.5 -3.25 0.125
-0.2 -0.9 0.1'

MAPPINGS=(latlong cube sphere sphere-gl paraboloid tennisball octahedral octahedral-equal-area angular)

cmd_run() {
    (($# == 2)) || usage
    [[ -f $1 && -x $1 ]] || die "not an executable file: $1"
    BIN=$(realpath "$1")
    mkdir -p "$2"
    OUT=$(realpath "$2")
    [[ -z $(ls -A "$OUT") ]] || die "$OUT is not empty"
    cd "$(dirname "$0")/.."
    ROOT=$PWD

    local start=$SECONDS m f

    # --- convert: every mapping (--to), from a real latlong HDRI ---------------
    # Sizes: a cube's face edge, any other atlas's width (a tennisball needs a
    # width divisible by 3).
    for m in "${MAPPINGS[@]}"; do
        case $m in
            cube) step "convert_to_$m" convert test-data/hdri/park.exr "@/park_$m.exr" --to "$m" --size 64 ;;
            tennisball) step "convert_to_$m" convert test-data/hdri/park.exr "@/park_$m.exr" --to "$m" --size 192 ;;
            *) step "convert_to_$m" convert test-data/hdri/park.exr "@/park_$m.exr" --to "$m" --size 128 ;;
        esac
    done
    # Aliases of the names.
    step convert_alias_dual_paraboloid convert test-data/hdri/venice.exr @/venice.exr --to dual-paraboloid --size 96
    step convert_alias_mirror_ball convert test-data/hdri/venice.exr @/venice.exr --to mirror-ball --size 96
    step convert_alias_lightprobe convert test-data/hdri/venice.exr @/venice.exr --to light-probe --size 96

    # --- convert: every cube layout --------------------------------------------
    for f in cross vcross strip vstrip; do
        step "convert_cube_$f" convert test-data/hdri/sky.exr "@/sky_$f.exr" --to cube --layout "$f" --size 48
    done
    step convert_cube_faces convert test-data/hdri/sky.exr @/sky.exr --to cube --layout faces --size 48
    step convert_cube_faces_pattern convert test-data/hdri/sky.exr '@/{face}.png' --to cube --size 32 --face-names px --exposure -2
    step convert_cube_faces_words convert test-data/hdri/studio.exr @/studio.hdr --to cube --layout faces --size 32 --face-names words

    # --- convert: every container and texel format -----------------------------
    step convert_exr_f32 convert test-data/hdri/studio.exr @/studio.exr --to latlong --size 256
    step convert_exr_half convert test-data/hdri/studio.exr @/studio.exr --to latlong --size 256 --half
    step convert_exr_none convert test-data/hdri/studio.exr @/studio.exr --to cube --size 32 --exr-compression none
    step convert_exr_rle convert test-data/hdri/studio.exr @/studio.exr --to cube --size 32 --exr-compression rle
    step convert_exr_zip convert test-data/hdri/studio.exr @/studio.exr --to cube --size 32 --exr-compression zip
    step convert_exr_piz convert test-data/hdri/studio.exr @/studio.exr --to cube --size 32 --exr-compression piz
    step convert_exr_pxr24 convert test-data/hdri/studio.exr @/studio.exr --to cube --size 32 --exr-compression pxr24
    step convert_exr_half_b44 convert test-data/hdri/studio.exr @/studio.exr --to cube --size 32 --half --exr-compression b44
    step convert_png convert test-data/hdri/studio.exr @/studio.png --to latlong --size 256 --exposure -1
    step convert_hdr convert test-data/hdri/studio.exr @/studio.hdr --to latlong --size 256
    step convert_jpg convert test-data/hdri/studio.exr @/studio.jpg --to latlong --size 256 --exposure 1
    for f in rgba16f rgba32f rg11b10f rgb9e5; do
        step "convert_ktx2_$f" convert test-data/hdri/venice.exr "@/venice_$f.ktx2" --to cube --size 32 --format "$f"
    done
    step convert_ktx2_zstd convert test-data/hdri/venice.exr @/venice.ktx2 --to cube --size 32 --zstd
    step convert_ktx2_zstd19_mips convert test-data/hdri/venice.exr @/venice.ktx2 --to cube --size 32 --zstd 19 --mips
    step convert_ktx2_mips_rgb9e5 convert test-data/hdri/venice.exr @/venice.ktx2 --to cube --size 32 --mips --format rgb9e5
    step convert_ktx2_latlong_mips convert test-data/hdri/venice.exr @/venice.ktx2 --to latlong --size 64 --mips --format rgba32f
    step convert_dds convert test-data/hdri/venice.exr @/venice.dds --to cube --size 32
    step convert_dds_mips_rg11b10f convert test-data/hdri/venice.exr @/venice.dds --to cube --size 32 --mips --format rg11b10f
    step convert_ktx convert test-data/hdri/venice.exr @/venice.ktx --to cube --size 32
    step convert_ktx_mips convert test-data/hdri/venice.exr @/venice.ktx --to cube --size 32 --mips --format rgb9e5

    # --- convert: options -------------------------------------------------------
    step convert_rotate_nearest convert test-data/hdri/park.exr @/park.exr --to octahedral --size 64 --rotate 90,10,-5 --filter nearest
    step convert_samples_threads1 convert test-data/hdri/park.exr @/park.exr --to cube --size 32 --samples 3 --threads 1
    step convert_frames convert test-data/hdri/park.exr @/park.exr --to sphere --size 64 --from-frame z-up --to-frame y-up-lh
    step convert_convention_blender convert test-data/hdri/park.exr @/park.exr --to cube --size 32 --convention blender
    step convert_convention_to_cmgen convert test-data/hdri/park.exr @/park.exr --to latlong --size 128 --to-convention cmgen
    step convert_face_transform convert test-data/hdri/park.exr @/park.exr --to cube --size 32 --face-transform '+x:rot90,-z:flipx,+y:transpose'

    # --- convert: reading what convert wrote (other readers and layouts) --------
    step convert_from_sphere convert @@/convert_to_sphere/park_sphere.exr @/park.exr --to latlong --size 128 --from sphere
    step convert_from_paraboloid convert @@/convert_to_paraboloid/park_paraboloid.exr @/park.exr --to cube --size 32 --from paraboloid
    step convert_from_tennisball convert @@/convert_to_tennisball/park_tennisball.exr @/park.exr --to octahedral-equal-area --size 64
    step convert_from_vcross convert @@/convert_cube_vcross/sky_vcross.exr @/sky.exr --to angular --size 64
    step convert_from_six_exr convert '@@/convert_cube_faces/sky_+y.exr' @/sky.exr --to latlong --size 128
    step convert_from_six_png convert @@/convert_cube_faces_pattern/px.png @/sky.exr --to tennisball --size 96
    step convert_from_png convert @@/convert_png/studio.png @/studio.exr --to cube --size 32
    step convert_from_hdr convert @@/convert_hdr/studio.hdr @/studio.png --to paraboloid --size 128
    step convert_from_jpg convert @@/convert_jpg/studio.jpg @/studio.exr --to sphere-gl --size 64
    step convert_from_half convert @@/convert_exr_half/studio.exr @/studio.exr --to octahedral --size 64
    step convert_from_ktx2_zstd convert @@/convert_ktx2_zstd/venice.ktx2 @/venice.exr --to latlong --size 128
    step convert_from_ktx2_rgb9e5 convert @@/convert_ktx2_rgb9e5/venice_rgb9e5.ktx2 @/venice.exr --to latlong --size 128
    step convert_from_dds convert @@/convert_dds_mips_rg11b10f/venice.dds @/venice.exr --to latlong --size 128

    # --- bake: the default, every --target, every --container -------------------
    step bake_default bake test-data/hdri/studio.exr --out @/bake --size 64
    step bake_target_bevy bake test-data/hdri/studio.exr --out @/bake --target bevy --size 64
    step bake_target_gltf bake test-data/hdri/studio.exr --out @/bake --target gltf --size 64
    step bake_target_filament bake test-data/hdri/studio.exr --out @/bake --target filament --size 64
    step bake_target_filament_no_mirror bake test-data/hdri/studio.exr --out @/bake --target filament --no-mirror --size 32
    step bake_target_bevy_no_zstd bake test-data/hdri/park.exr --out @/bake --target bevy --no-zstd --size 32 --samples 16
    for f in exr ktx2 dds ktx; do
        step "bake_container_$f" bake sky --env-size 64 --out @/bake --container "$f" --size 32
    done
    step bake_ktx2_rgb9e5_zstd bake room --env-size 64 --out @/bake --container ktx2 --format rgb9e5 --zstd 5 --size 32
    step bake_dds_rgba32f bake room --env-size 64 --out @/bake --container dds --format rgba32f --size 32
    # --- bake: options ----------------------------------------------------------
    step bake_check_exact_irradiance bake test-data/hdri/venice.exr --out @/bake --size 32 --check 64 --exact-irradiance --clamp 50 --dfg-grid edges --dfg-size 32 --irradiance-scale e
    step bake_exact_faces bake test-data/hdri/park.exr --out @/bake --size 32 --exact --roughness-rule 0,0.3,0.6,1 --layout faces --irradiance-size 8 --split 0
    step bake_unity_draft bake test-data/hdri/sky.exr --out @/bake --size 64 --roughness-rule unity --quality draft --to-frame z-up --sh-window auto
    step bake_filament_rule_high bake room --env-size 64 --out @/bake --size 64 --roughness-rule filament --quality high --layout vcross --convention blender --sh-window cmgen
    step bake_levels bake test-data/hdri/venice.exr --out @/bake --size 64 --levels 4 --min-size 8 --dfg-size 0 --irradiance-size 0
    step bake_sh_only bake test-data/hdri/park.exr --out @/bake --sh-only
    step bake_from_cube_cross bake @@/convert_cube_cross/sky_cross.exr --out @/bake --size 32

    # --- render: mirror objects ----------------------------------------------------
    step render_mirror_latlong_per_vertex render @/teapot.png --env sky --mapping latlong --mode per-vertex --env-size 128 --width 160 --height 120 --exposure -1
    step render_mirror_octahedral_torus render @/torus.exr --env room --mapping octahedral --object torus --env-size 128 --width 160 --height 120 --samples 1
    step render_mirror_cube_sphere render @/sphere.hdr --env room --mapping cube --object sphere --env-size 64 --width 128 --height 96 --fresnel 0.04 --filter nearest
    step render_mirror_paraboloid_no_mip render @/teapot.png --env sky --mapping paraboloid --env-size 128 --width 160 --height 120 --no-mip
    step render_mirror_analytic render @/teapot.png --env sky --analytic --width 160 --height 120
    step render_mirror_file render @/teapot.png --env test-data/hdri/venice.exr --width 160 --height 120 --fov 50 --eye 3,3,8 --target 0,1,0
    step render_mirror_z_up render @/teapot.png --env sky --mapping tennisball --env-size 129 --frame z-up --width 128 --height 96
    step render_mirror_from_sphere render @/teapot.png --env @@/convert_to_sphere/park_sphere.exr --from sphere --width 128 --height 96
    # --- render: lit materials (maps baked on the fly, small) ---------------------
    step render_lit_gold render @/teapot.png --env test-data/hdri/studio.exr --material gold --bake-size 32 --width 160 --height 120
    step render_lit_plastic_multiscatter render @/sphere.exr --env sky --env-size 64 --object sphere --material plastic --roughness 0.5 --multiscatter --bake-size 32 --width 128 --height 96
    step render_lit_custom render @/torus.png --env room --env-size 64 --object torus --material plastic --base-color 0.2,0.6,0.9 --roughness 0.3 --metallic 0.5 --no-dominant-direction --bake-size 32 --width 128 --height 96
    step render_lit_engine_filament render @/teapot.png --env sky --env-size 64 --material chrome --engine filament --bake-size 32 --width 128 --height 96
    step render_lit_reference render @/teapot.png --env sky --env-size 64 --material plastic --reference --reference-samples 4 --width 80 --height 60
    step render_lit_exact_split_sum render @/teapot.png --env sky --env-size 32 --mapping latlong --material gold --exact-split-sum --width 40 --height 30
    # --- render: from what bake wrote ---------------------------------------------
    step render_bake_dir_exr render @/teapot.png --env @@/bake_default/bake --material chrome --width 160 --height 120
    step render_bake_dir_gltf render @/teapot.png --env @@/bake_target_gltf/bake --material rubber --engine gltf --width 160 --height 120
    step render_bake_ktx2_chain render @/teapot.png --env @@/bake_target_bevy/bake/specular.ktx2 --material diffuse --width 160 --height 120
    step render_bake_dds_dir render @/sphere.png --env @@/bake_container_dds/bake --object sphere --material gold --width 128 --height 96
    step render_chain_alone render @/teapot.hdr --env @@/convert_ktx2_zstd19_mips/venice.ktx2 --material plastic --width 128 --height 96

    # --- info: repository input and outputs of every container ----------------------
    # (`info` takes one image file, not a bake directory or its manifest.json, and
    # does not read KTX 1.)
    step info_input info test-data/hdri/park.exr
    step info_exr_cube info @@/convert_cube_cross/sky_cross.exr
    step info_exr_half info @@/convert_exr_half/studio.exr
    step info_exr_sphere info @@/convert_to_sphere/park_sphere.exr --from sphere
    step info_six_files info @@/convert_cube_faces/sky_-z.exr
    step info_png info @@/convert_png/studio.png
    step info_hdr info @@/convert_hdr/studio.hdr
    step info_jpg info @@/convert_jpg/studio.jpg
    step info_ktx2_zstd_mips info @@/convert_ktx2_zstd19_mips/venice.ktx2
    step info_ktx2_rg11b10f info @@/convert_ktx2_rg11b10f/venice_rg11b10f.ktx2
    step info_dds_mips info @@/convert_dds_mips_rg11b10f/venice.dds
    step info_bake_irradiance info @@/bake_default/bake/irradiance.exr
    step info_bake_specular_exr info @@/bake_default/bake/specular_1.exr
    step info_bake_bevy_ktx2 info @@/bake_target_bevy/bake/specular.ktx2
    step info_bake_gltf_diffuse info @@/bake_target_gltf/bake/diffuse.ktx2
    step info_bake_dds info @@/bake_container_dds/bake/specular.dds

    # --- map and unmap: every mapping, directions on standard input ------------
    # map's output (chart,u,v) goes back through unmap; --size adds texel columns,
    # which unmap ignores.
    for m in "${MAPPINGS[@]}"; do
        step "map_$m" map --mapping "$m" <<<"$DIRECTIONS"
        step "unmap_$m" unmap --mapping "$m" <"$OUT/map_$m/stdout.txt"
    done
    step map_cube_size map --mapping cube --size 1024 <<<"$DIRECTIONS"
    step map_cube_size_strip map --mapping cube --size 64 --layout strip <<<"$DIRECTIONS"
    step map_tennisball_size map --mapping tennisball --size 96 <<<"$DIRECTIONS"
    step map_latlong_size map --mapping latlong --size 512 <<<"$DIRECTIONS"
    step map_octahedral_z_up map --mapping octahedral --frame z-up --size 64 <<<"$DIRECTIONS"
    step map_latlong_blender map --mapping latlong --convention blender --frame y-up-lh <<<"$DIRECTIONS"
    step unmap_latlong_blender unmap --mapping latlong --convention blender --frame y-up-lh <"$OUT/map_latlong_blender/stdout.txt"
    step unmap_cube_from_file unmap --mapping cube @@/map_cube_size/stdout.txt </dev/null

    # --- demo -------------------------------------------------------------------------
    # The smallest demo: about 4000 texels per representation, 32 × 24 renders,
    # one reference sample. Its lit section still bakes from 256² cubes (fixed
    # sizes), 10 to 12 s on two cores; its report.md holds timing columns (see
    # compare).
    step demo demo --out @/demo --ktexels 4 --width 32 --samples 1 --reference-samples 1 -q
    step demo_no_lit demo --out @/demo --ktexels 8 --width 48 --samples 2 --no-lit -q

    echo "done: $(find "$OUT" -type f | wc -l) files in $OUT, $((SECONDS - start)) s"
}

# ---------------------------------------------------------------------------
# compare
# ---------------------------------------------------------------------------

# compare_normalised DIR_A DIR_B: reads "KIND<tab>PATH" lines on standard input
# (KIND json, md or exr; PATH relative to both directories), compares each pair
# in its normal form, and prints "differs<tab>KIND<tab>PATH" for every pair that
# differs. One python3 process for all of them.
compare_normalised() {
    # The program is given with -c: standard input carries the list.
    local program
    program=$(cat <<'PY'
import json, os, re, sys

dir_a, dir_b = sys.argv[1], sys.argv[2]  # python3 -c PROGRAM A B

# Keys that hold wall-clock timings (they differ from run to run): "seconds",
# "preparation_seconds" and "stages_seconds" (lists of {stage, seconds}) in a
# bake's manifest.json, "seconds" inside a level's "measured" (--check).
TIMING = re.compile(r"second|time|timing|duration|elapsed|millis|(^|_)ms($|_)", re.I)
# The writer's own name and version: "envmap": "envmap 0.1.0" in manifest.json.
TOOL_KEYS = {"envmap", "tool", "generator", "writer", "version"}


def clean(o):
    if isinstance(o, dict):
        return {
            k: clean(v)
            for k, v in o.items()
            if not TIMING.search(k)
            and not (k.lower() in TOOL_KEYS and isinstance(v, str) and "envmap" in v.lower())
        }
    if isinstance(o, list):
        return [clean(v) for v in o]
    return o


def norm_json(path):
    with open(path, encoding="utf-8") as f:
        data = json.load(f)
    # Numbers are read as f64 and printed by repr, which round-trips: every
    # value left is still compared exactly.
    return json.dumps(clean(data), indent=1, sort_keys=True, ensure_ascii=False).encode()


def norm_md(path):
    # The demo's report.md: in every Markdown table, blank the cells of the
    # columns whose header is a time ("time (s)", "split sum (ms)",
    # "reference (ms)"); everything else, PSNRs included, stays.
    timed = re.compile(r"time|\(m?s\)|second", re.I)
    lines, cols = [], None
    with open(path, encoding="utf-8") as f:
        for line in f:
            line = line.rstrip("\n")
            if not line.startswith("|"):
                cols = None
                lines.append(line)
                continue
            cells = line.split("|")
            if cols is None:  # a table's header row
                cols = {i for i, c in enumerate(cells) if timed.search(c)}
            else:
                cells = ["<time>" if i in cols and not set(c.strip()) <= set("-:") else c
                         for i, c in enumerate(cells)]
            lines.append("|".join(cells))
    return "\n".join(lines).encode()


def norm_exr(path):
    # OpenEXR (single part): the header's attributes put in name order; every
    # attribute's bytes and everything after the header (offset table, pixel
    # chunks) unchanged. See the *.exr case in cmd_compare for why.
    with open(path, "rb") as f:
        b = f.read()
    flags = int.from_bytes(b[5:8], "little") if len(b) >= 8 else 0
    if b[:4] != b"\x76\x2f\x31\x01" or flags & 0x1000:  # not single part: as is
        return b
    i, attrs = 8, []
    while b[i] != 0:
        j = b.index(b"\0", i)      # end of the name
        k = b.index(b"\0", j + 1)  # end of the type
        n = int.from_bytes(b[k + 1:k + 5], "little", signed=True)
        attrs.append(b[i:k + 5 + n])
        i = k + 5 + n
    attrs.sort(key=lambda a: a[:a.index(b"\0")])
    return b[:8] + b"".join(attrs) + b[i:]


NORM = {"json": norm_json, "md": norm_md, "exr": norm_exr}
checked = 0
for line in sys.stdin:
    kind, rel = line.rstrip("\n").split("\t", 1)
    try:
        same = NORM[kind](os.path.join(dir_a, rel)) == NORM[kind](os.path.join(dir_b, rel))
    except Exception as e:  # unreadable or malformed: a difference
        print(f"note: {rel}: {e}", file=sys.stderr)
        same = False
    if not same:
        print(f"differs\t{kind}\t{rel}")
    checked += 1
print(f"checked\t{checked}")
PY
    )
    python3 -c "$program" "$1" "$2"
}

cmd_compare() {
    (($# == 2)) || usage
    local a=$1 b=$2
    [[ -d $a ]] || die "not a directory: $a"
    [[ -d $b ]] || die "not a directory: $b"

    local same=0 different=0 logs=0 f kind rel
    local list_a list_b both
    list_a=$(cd "$a" && find . -type f | sed 's|^\./||' | LC_ALL=C sort)
    list_b=$(cd "$b" && find . -type f | sed 's|^\./||' | LC_ALL=C sort)
    both=$(LC_ALL=C comm -12 <(printf '%s\n' "$list_a") <(printf '%s\n' "$list_b"))

    # Files on one side only.
    while IFS= read -r f; do
        [[ -n $f ]] || continue
        echo "only in $a: $f"
        different=$((different + 1))
    done < <(LC_ALL=C comm -23 <(printf '%s\n' "$list_a") <(printf '%s\n' "$list_b"))
    while IFS= read -r f; do
        [[ -n $f ]] || continue
        echo "only in $b: $f"
        different=$((different + 1))
    done < <(LC_ALL=C comm -13 <(printf '%s\n' "$list_a") <(printf '%s\n' "$list_b"))

    # Files on both sides. Those that need a normal form are listed in
    # $normalised (KIND<tab>PATH) and compared afterwards by one python3 process.
    local normalised=""
    while IFS= read -r f; do
        [[ -n $f ]] || continue
        case $f in
            *.log)
                # Progress, timings and warnings: present on both sides is all
                # that is asked of them.
                logs=$((logs + 1))
                same=$((same + 1))
                ;;
            *.json)
                # Timing keys and the writer's version removed (compare_normalised).
                normalised+="json	$f"$'\n'
                ;;
            report.md | */report.md)
                # The demo's report: its timing columns blanked (compare_normalised).
                normalised+="md	$f"$'\n'
                ;;
            *.exr)
                # Byte for byte, but for the order of the header's attributes.
                # envmap's own attributes (envmap.mapping, envmap.layout,
                # envmap.axes) go through the exr crate's LayerAttributes::other,
                # a std HashMap seeded at random in every process; envmap writes
                # them back in its own order, but a build that does not gives
                # the same file with the attributes in another order. The
                # header's length does not depend on the order, so the offset
                # table and pixel data after it are still compared byte for
                # byte, as is every attribute's name, type and value.
                if cmp -s "$a/$f" "$b/$f"; then
                    same=$((same + 1))
                else
                    normalised+="exr	$f"$'\n'
                fi
                ;;
            *)
                # Images, textures and text outputs (PNG, HDR, JPEG, KTX2, DDS,
                # KTX, sh.txt, the stdout.txt of info/map/unmap, command.txt,
                # commands.txt): byte for byte.
                if cmp -s "$a/$f" "$b/$f"; then
                    same=$((same + 1))
                else
                    echo "differs: $f"
                    different=$((different + 1))
                fi
                ;;
        esac
    done <<<"$both"

    if [[ -n $normalised ]]; then
        local total differing=0 result checked
        total=$(printf '%s' "$normalised" | wc -l)
        result=$(printf '%s' "$normalised" | compare_normalised "$a" "$b") ||
            die "the python3 comparison failed"
        checked=$(printf '%s\n' "$result" | sed -n 's/^checked\t//p')
        [[ $checked == "$total" ]] || die "python3 checked ${checked:-no} files of $total"
        while IFS=$'\t' read -r _ kind rel; do
            case $kind in
                json) echo "differs (json, timings and writer version ignored): $rel" ;;
                md) echo "differs (report, timing columns ignored): $rel" ;;
                exr) echo "differs (exr, header attribute order ignored): $rel" ;;
            esac
            differing=$((differing + 1))
        done < <(printf '%s\n' "$result" | grep '^differs' || true)
        same=$((same + total - differing))
        different=$((different + differing))
    fi

    echo "($logs .log files of progress and timings: present on both sides, contents not compared)"
    echo "$same same, $different different"
    ((different == 0))
}

case ${1:-} in
    run) shift; cmd_run "$@" ;;
    compare) shift; cmd_compare "$@" ;;
    *) usage ;;
esac
