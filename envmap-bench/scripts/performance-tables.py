#!/usr/bin/env python3
"""Regenerate the tables of docs/performance.md.

    nice -n 10 python3 envmap-bench/scripts/performance-tables.py [options]

Builds the `envmap` command (release; `-p envmap-cli`, or `-p envmap-render
--bin envmap` in a tree from before the command had its own crate) unless
--envmap gives one, makes the test inputs from a committed HDRI, times every
job as whole processes, each command alternated with its peers run by run
after one warm-up each (none for the bake), and writes the tables between the markers
`<!-- tables:begin -->` and `<!-- tables:end -->` of the page. Nothing between
the markers is kept: edit this script, not the tables.

Peers, each skipped with a note when missing:
  OpenCV + OpenEXR   pip install "opencv-python-headless<4.11" numpy
  py360convert       pip install py360convert
  cmgen (Filament)   apt-get install libfilament-tools

Options:
  --envmap PATH   the default build of `envmap` to time (no build)
  --native        also build with RUSTFLAGS="-C target-cpu=native" (into
                  target/native) and time it beside the default build
  --native-envmap PATH   a native build to time (no build)
  --runs N        counted runs per command (default 5; the bake, lit render
                  and file tables at most 3)
  --quick         one counted run, no warm-up (to try the script)
  --page FILE     the page to write (default docs/performance.md)
  --work DIR      scratch directory (default target/performance-tables)
  --stdout        print the tables instead of writing the page

Each figure is the median over the counted runs: wall time, CPU time (user +
system, from the kernel's accounting of the finished process) and peak
resident memory; "vs first" is the median of the run-by-run ratios of the
row's wall time to the table's first row.
"""

import argparse
import os
import platform
import re
import shutil
import statistics
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
SCRIPTS = Path(__file__).resolve().parent
BEGIN, END = "<!-- tables:begin -->", "<!-- tables:end -->"
HDRI = ROOT / "test-data" / "hdri" / "park.exr"


def log(msg):
    print(f"performance-tables: {msg}", file=sys.stderr, flush=True)


def sh(cmd, **kw):
    """Run a setup command; fail loudly."""
    r = subprocess.run(cmd, capture_output=True, text=True, **kw)
    if r.returncode != 0:
        sys.exit(f"performance-tables: {' '.join(map(str, cmd))} failed ({r.returncode}):\n{r.stderr}")
    return r.stdout


def build(native):
    """Build the envmap command; returns its path."""
    env = dict(os.environ)
    target = ROOT / "target"
    if native:
        env["RUSTFLAGS"] = (env.get("RUSTFLAGS", "") + " -C target-cpu=native").strip()
        env["CARGO_TARGET_DIR"] = str(ROOT / "target" / "native")
        target = ROOT / "target" / "native"
    for args in (["-p", "envmap-cli"], ["-p", "envmap-render", "--bin", "envmap"]):
        log(f"cargo build --release {' '.join(args)}{' (native)' if native else ''}")
        r = subprocess.run(["cargo", "build", "--release", "-q", *args], cwd=ROOT, env=env)
        if r.returncode == 0:
            return target / "release" / "envmap"
    sys.exit("performance-tables: could not build envmap")


def have_python(*modules):
    code = "import os; os.environ['OPENCV_IO_ENABLE_OPENEXR']='1'; " + "; ".join(f"import {m}" for m in modules)
    return subprocess.run([sys.executable, "-c", code], capture_output=True).returncode == 0


def py_version(expr, *modules):
    code = "import os; os.environ['OPENCV_IO_ENABLE_OPENEXR']='1'; " + "; ".join(f"import {m}" for m in modules)
    r = subprocess.run([sys.executable, "-c", f"{code}; print({expr})"], capture_output=True, text=True)
    return r.stdout.strip() if r.returncode == 0 else None


def dpkg_version(pkg):
    r = subprocess.run(["dpkg-query", "-W", "-f=${Version}", pkg], capture_output=True, text=True)
    return r.stdout.strip() if r.returncode == 0 else None


class Row:
    def __init__(self, label, cmd, clean=()):
        self.label, self.cmd, self.clean = label, [str(c) for c in cmd], [Path(c) for c in clean]
        self.wall, self.cpu, self.rss, self.failed = [], [], [], None
        self.size = None  # bytes written, from the last run


def run_once(row, work):
    for p in row.clean:
        if p.is_dir():
            shutil.rmtree(p)
        elif p.exists():
            p.unlink()
    err = open(work / "last-stderr.txt", "w+b")
    t0 = time.perf_counter()
    proc = subprocess.Popen(row.cmd, stdout=subprocess.DEVNULL, stderr=err, cwd=work)
    _, status, ru = os.wait4(proc.pid, 0)
    wall = time.perf_counter() - t0
    proc.returncode = os.waitstatus_to_exitcode(status)
    if proc.returncode != 0:
        err.seek(0)
        row.failed = f"exit {proc.returncode}: {err.read().decode(errors='replace').strip()[-300:]}"
        log(f"{row.label}: {row.failed}")
        return None
    return wall, ru.ru_utime + ru.ru_stime, ru.ru_maxrss / 1024.0


def measure(rows, runs, warmup, work):
    """Alternate the rows run by run: warm-up round(s), then `runs` counted rounds."""
    for r in range(warmup + runs):
        for row in rows:
            if row.failed:
                continue
            got = run_once(row, work)
            if got and r >= warmup:
                row.wall.append(got[0])
                row.cpu.append(got[1])
                row.rss.append(got[2])
                row.size = written(row.clean)


def written(paths):
    total = 0
    for p in paths:
        if p.is_file():
            total += p.stat().st_size
        elif p.is_dir():
            total += sum(f.stat().st_size for f in p.rglob("*") if f.is_file())
    return total if paths else None


def mb(n):
    if n is None:
        return ""
    if n < 100e3:
        return f"{n / 1e3:.1f} kB"
    return f"{n / 1e6:.1f} MB" if n < 10e6 else f"{n / 1e6:.0f} MB"


def fmt_s(x):
    return f"{x * 1000:.0f} ms" if x < 1 else f"{x:.2f} s" if x < 10 else f"{x:.1f} s"


def table(rows):
    base = rows[0]
    out = ["| command | wall | CPU | peak memory | written | vs first |", "| --- | ---: | ---: | ---: | ---: | ---: |"]
    for i, row in enumerate(rows):
        if row.failed or not row.wall:
            out.append(f"| {row.label} | failed | | | | |")
            continue
        n = min(len(row.wall), len(base.wall))
        ratio = statistics.median(row.wall[k] / base.wall[k] for k in range(n)) if n and not base.failed else None
        vs = "1" if i == 0 else (f"{ratio:.2f}×" if ratio is not None else "")
        wall = fmt_s(statistics.median(row.wall))
        if i == 0:
            wall = f"**{wall}**"
        out.append(
            f"| {row.label} | {wall} | {fmt_s(statistics.median(row.cpu))} | "
            f"{statistics.median(row.rss):.0f} MiB | {mb(row.size)} | {vs} |"
        )
    return out


def machine():
    cpu = "unknown"
    flags = set()
    try:
        for line in open("/proc/cpuinfo"):
            if line.startswith("model name") and cpu == "unknown":
                cpu = line.split(":", 1)[1].strip()
            if line.startswith("flags") and not flags:
                flags = set(line.split(":", 1)[1].split())
    except OSError:
        pass
    simd = "AVX-512" if "avx512f" in flags else "AVX2" if "avx2" in flags else "SSE2"
    mem = 0
    try:
        for line in open("/proc/meminfo"):
            if line.startswith("MemTotal"):
                mem = int(line.split()[1]) / 1024 / 1024
    except OSError:
        pass
    osname = platform.platform()
    try:
        for line in open("/etc/os-release"):
            if line.startswith("PRETTY_NAME="):
                osname = line.split("=", 1)[1].strip().strip('"')
    except OSError:
        pass
    return cpu, simd, os.cpu_count(), mem, osname


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--envmap")
    ap.add_argument("--native", action="store_true")
    ap.add_argument("--native-envmap")
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--page", default=str(ROOT / "docs" / "performance.md"))
    ap.add_argument("--work", default=str(ROOT / "target" / "performance-tables"))
    ap.add_argument("--stdout", action="store_true")
    a = ap.parse_args()
    started = time.perf_counter()
    runs, warmup = (1, 0) if a.quick else (a.runs, 1)
    slow_runs = 1 if a.quick else max(1, min(a.runs, 3))

    envmap = Path(a.envmap).resolve() if a.envmap else build(False)
    native = None
    if a.native_envmap:
        native = Path(a.native_envmap).resolve()
    elif a.native:
        native = build(True)

    started = time.perf_counter()  # the builds are not counted
    work = Path(a.work).resolve()
    work.mkdir(parents=True, exist_ok=True)
    out = work / "out"
    out.mkdir(exist_ok=True)

    # Inputs: a 4096 x 2048 float EXR latlong (a committed 512 x 256 HDRI with a
    # sun, upsampled), its 6 x 1024^2 cube, a bake of it, a KTX2 chain of it.
    inp, cube, bake, ktx2 = work / "in.exr", work / "cube.exr", work / "bake", work / "chain.ktx2"
    if not inp.exists():
        log("making the inputs")
        sh([envmap, "convert", HDRI, inp, "--to", "latlong", "--size", "4096", "-q"])
    for p in (cube, ktx2):
        if p.exists():
            p.unlink()
    shutil.rmtree(bake, ignore_errors=True)
    sh([envmap, "convert", inp, cube, "--to", "cube", "--size", "1024", "-q"])
    sh([envmap, "bake", inp, "--out", bake, "-q"])
    sh([envmap, "convert", inp, ktx2, "--to", "cube", "--size", "1024", "--mips", "--format", "rgb9e5", "--zstd", "-q"])

    opencv = have_python("cv2", "numpy")
    py360 = opencv and have_python("py360convert")
    cmgen = shutil.which("cmgen")
    notes = []
    if not opencv:
        notes.append('OpenCV rows left out: `pip install "opencv-python-headless<4.11" numpy`.')
    if not py360:
        notes.append("py360convert rows left out: `pip install py360convert`.")
    if not cmgen:
        notes.append("cmgen rows left out: `apt-get install libfilament-tools`.")

    def em(label, *args, clean=(), builds=False):
        """envmap rows: the default build, and with builds=True the native one beside it."""
        rows = [Row(f"{label}", [envmap, *args], clean)]
        if native and builds:
            rows.append(Row("the same, native build", [native, *args], clean))
        return rows

    py = sys.executable
    cv_copy = (
        "import os,sys; os.environ['OPENCV_IO_ENABLE_OPENEXR']='1'; import cv2; "
        "i=cv2.imread(sys.argv[1], cv2.IMREAD_UNCHANGED); "
        "cv2.imwrite(sys.argv[2], i, [cv2.IMWRITE_EXR_TYPE, cv2.IMWRITE_EXR_TYPE_FLOAT, "
        "cv2.IMWRITE_EXR_COMPRESSION, int(sys.argv[3])])"
    )
    sections = []

    # 1. Convert a 4K latlong to a cube, with files.
    rows = em("`envmap convert in.exr cube.exr --to cube --size 1024`", "convert", inp, out / "cube.exr",
              "--to", "cube", "--size", "1024", "-q", clean=[out / "cube.exr"], builds=True)
    rows += em("the same, `--exr-compression none`", "convert", inp, out / "cube-none.exr", "--to", "cube",
               "--size", "1024", "--exr-compression", "none", "-q", clean=[out / "cube-none.exr"])
    if opencv:
        rows.append(Row("OpenCV: `opencv-convert.py in.exr cube.exr 1024 none`",
                        [py, SCRIPTS / "opencv-convert.py", inp, out / "cv.exr", "1024", "none"], [out / "cv.exr"]))
    if py360:
        rows.append(Row("py360convert: `py360-convert.py in.exr cube.exr 1024 none`",
                        [py, SCRIPTS / "py360-convert.py", inp, out / "p360.exr", "1024", "none"], [out / "p360.exr"]))
    if cmgen:
        rows.append(Row("cmgen: `cmgen -q --no-mirror --format=exr --compression=RAW --size=1024 --extract=DIR in.exr` (six files)",
                        [cmgen, "-q", "--no-mirror", "--format=exr", "--compression=RAW", "--size=1024",
                         f"--extract={out / 'cmgen-faces'}", inp], [out / "cmgen-faces"]))
    sections.append(("Convert a 4K latlong to a cube, with its files", [
        "`in.exr` (4096×2048, f32) to a horizontal cross of 1024² faces, f32 EXR, bilinear. envmap's "
        "default EXR compression for f32 writes the cross's empty cells compressed (76 MB); `none`, "
        "OpenCV and py360convert write 151 MB, cmgen six half-float face files. The peers' scripts "
        "are in `envmap-bench/scripts/`."], rows, runs, warmup))

    # 2. Bake a 4K map to a 512^2 chain.
    rows = em("`envmap bake in.exr --out DIR` (9 levels, SH9, 32² irradiance, DFG, 14 EXR files)",
              "bake", inp, "--out", out / "bake", "-q", clean=[out / "bake"], builds=True)
    rows += em("`envmap bake in.exr --out DIR --target filament --size 512 --no-mirror` (cmgen's files)",
               "bake", inp, "--out", out / "fil", "--target", "filament", "--size", "512", "--no-mirror", "-q",
               clean=[out / "fil"], builds=True)
    rows += em("the Filament bake (default build), `--quality draft`", "bake", inp, "--out", out / "draft", "--target", "filament",
               "--size", "512", "--no-mirror", "--quality", "draft", "-q", clean=[out / "draft"])
    if cmgen:
        rows.append(Row("cmgen: `cmgen -q --no-mirror --size=512 --format=ktx --deploy=DIR in.exr`",
                        [cmgen, "-q", "--no-mirror", "--size=512", "--format=ktx", f"--deploy={out / 'cmgen'}", inp],
                        [out / "cmgen"]))
    sections.append(("Bake a 4K map to a 512² chain", [
        "From `in.exr`: envmap's default bake (GGX chain 512² → 2² at 9 levels, the linear rule), and "
        "Filament's files (`_ibl.ktx` with a 512² → 16² chain of 6 levels, `_skybox.ktx`, `sh.txt`) made "
        "by envmap and by cmgen with its default 1024 samples."], rows, slow_runs, 0))

    # 3. SH9.
    rows = em("`envmap bake in.exr --out DIR --sh-only` (`sh.json`)", "bake", inp, "--out", out / "sh",
              "--sh-only", "-q", clean=[out / "sh"], builds=True)
    if cmgen:
        rows.append(Row("cmgen: `cmgen -q --no-mirror --sh=3 --sh-output=sh.txt in.exr`",
                        [cmgen, "-q", "--no-mirror", "--sh=3", f"--sh-output={out / 'sh.txt'}", inp],
                        [out / "sh.txt"]))
    sections.append(("SH9 of a 4K map", [
        "Nine spherical-harmonic coefficients per channel of `in.exr`, written as text; envmap projects "
        "the latlong's texels with their exact solid angles, cmgen resamples a cube first."], rows, runs, warmup))

    # 4. 1080p mirror render.
    common = ["--env", cube, "--width", "1920", "--height", "1080"]
    rows = em("`envmap render out.png --env cube.exr --width 1920 --height 1080 --samples 1`",
              "render", out / "m.png", *common, "--samples", "1", clean=[out / "m.png"], builds=True)
    rows += em("the same, `--no-mip`", "render", out / "nomip.png", *common, "--samples", "1", "--no-mip",
               clean=[out / "nomip.png"])
    rows += em("the same, `--mode per-vertex`", "render", out / "pv.png", *common, "--samples", "1",
               "--mode", "per-vertex", clean=[out / "pv.png"])
    rows += em("the same, `--samples 2` (the default: 2×2 per pixel)", "render", out / "s2.png", *common,
               "--samples", "2", clean=[out / "s2.png"])
    sections.append(("A 1080p mirror render", [
        "A mirror teapot (6320 triangles) at 1920×1080 in `cube.exr` (6×1024², the cube made above), "
        "written as PNG; the load of the 76 MB cube is part of each figure. No outside tool renders "
        "this scene, so the rows are envmap's own variants: mip-aware lookups (the default), plain "
        "bilinear ones, per-vertex lookups, and 2×2 supersampling."], rows, runs, warmup))

    # 5. Lit render.
    lit = ["--material", "plastic", "--roughness", "0.5", "--width", "1920", "--height", "1080", "--samples", "1"]
    rows = em("`envmap render out.png --env BAKE_DIR --material plastic --roughness 0.5` (1080p, 1 sample)",
              "render", out / "lit.png", "--env", bake, *lit, clean=[out / "lit.png"], builds=True)
    rows += em("the same from `cube.exr`, baking envmap's chain first", "render", out / "litc.png", "--env", cube,
               *lit, clean=[out / "litc.png"], builds=True)
    rows += em("the same from `cube.exr`, `--engine gltf` (a glTF mip chain)", "render", out / "litg.png",
               "--env", cube, *lit, "--engine", "gltf", clean=[out / "litg.png"])
    rows += em("the mirror from `cube.exr` (the first row of the table above)", "render", out / "mir.png",
               "--env", cube, "--width", "1920", "--height", "1080", "--samples", "1", clean=[out / "mir.png"])
    sections.append(("A lit render", [
        "The same teapot as glossy plastic (roughness 0.5) by the split sum: from the directory that "
        "`envmap bake in.exr` wrote (its chain, irradiance map and DFG table read from files), or "
        "baking the maps from `cube.exr` in the same process."], rows, slow_runs, warmup))

    # 6. EXR and KTX2 files.
    rows = em("`envmap convert in.exr copy.exr --to latlong --size 4096 --filter nearest --samples 1` (EXR in, EXR out)",
              "convert", inp, out / "copy.exr", "--to", "latlong", "--size", "4096", "--filter", "nearest",
              "--samples", "1", "-q", clean=[out / "copy.exr"])
    if opencv:
        rows.append(Row("OpenCV: `cv2.imread` then `cv2.imwrite`, the same file, no compression",
                        [py, "-c", cv_copy, inp, out / "cvcopy.exr", "0"], [out / "cvcopy.exr"]))
    rows += em("envmap, the same with `--exr-compression zip`", "convert", inp, out / "copyz.exr", "--to", "latlong",
               "--size", "4096", "--filter", "nearest", "--samples", "1", "--exr-compression", "zip", "-q",
               clean=[out / "copyz.exr"])
    if opencv:
        rows.append(Row("OpenCV, the same with ZIP (OpenCV's default)",
                        [py, "-c", cv_copy, inp, out / "cvcopyz.exr", "3"], [out / "cvcopyz.exr"]))
    rows += em("envmap, the same with `--exr-compression piz`", "convert", inp, out / "copyp.exr", "--to", "latlong",
               "--size", "4096", "--filter", "nearest", "--samples", "1", "--exr-compression", "piz", "-q",
               clean=[out / "copyp.exr"])
    rows += em("envmap, the same with `--half` (f16, RLE)", "convert", inp, out / "copyh.exr", "--to", "latlong",
               "--size", "4096", "--filter", "nearest", "--samples", "1", "--half", "-q",
               clean=[out / "copyh.exr"])
    rows += em("`envmap convert in.exr cube.ktx2 --to cube --size 1024 --mips` (KTX2 out: RGBA16F, 11 levels)",
               "convert", inp, out / "c16.ktx2", "--to", "cube", "--size", "1024", "--mips", "-q",
               clean=[out / "c16.ktx2"])
    rows += em("the same, `--format rgb9e5 --zstd` (Bevy's texel format)", "convert", inp, out / "c9.ktx2", "--to",
               "cube", "--size", "1024", "--mips", "--format", "rgb9e5", "--zstd", "-q",
               clean=[out / "c9.ktx2"])
    rows += em("the same, `--format rgb9e5 --zstd 19` (smallest files)", "convert", inp, out / "c19.ktx2", "--to",
               "cube", "--size", "1024", "--mips", "--format", "rgb9e5", "--zstd", "19", "-q",
               clean=[out / "c19.ktx2"])
    rows += em("`envmap convert chain.ktx2 cube.exr --to cube --size 1024` (KTX2 in: RGB9E5 + zstd, level 0)",
               "convert", ktx2, out / "fromktx.exr", "--to", "cube", "--size", "1024", "-q",
               clean=[out / "fromktx.exr"])
    rows += em("`envmap info chain.ktx2` (reads the file, prints its levels and statistics)", "info", ktx2)
    sections.append(("EXR and KTX2 files", [
        "Reading and writing the 4096×2048 float map and a 6×1024² cube with its mip chain. The EXR rows "
        "copy `in.exr` texel for texel (nearest, same size), so they are its read and its write; "
        "KTX2 is written with every level of the cube's box-filtered chain. The KTX2 rows have no outside "
        "peer: none installs from PyPI or Debian here (`pyktx`, KTX-Software's binding, has no wheel)."],
        rows, slow_runs, warmup))

    loads_before = os.getloadavg()
    for title, _, rows, n, w in sections:
        log(f"timing: {title} ({n} runs)")
        measure(rows, n, w, work)
    loads_after = os.getloadavg()

    cpu, simd, ncpu, mem, osname = machine()
    rustc = " ".join(sh(["rustc", "--version"]).split()[:2])  # no commit hash, no date
    version = re.search(r'^version = "([^"]+)"', (ROOT / "Cargo.toml").read_text(), re.M)
    peers = []
    if opencv:
        cvv = py_version("cv2.__version__", "cv2")
        exrv = re.search(r"OpenEXR:\s+build \(ver ([0-9.]+)\)",
                         py_version("cv2.getBuildInformation()", "cv2") or "")
        peers.append(f"OpenCV {cvv} (opencv-python-headless, OpenEXR {exrv.group(1) if exrv else '?'}), "
                     f"NumPy {py_version('numpy.__version__', 'numpy')}")
    if py360:
        p360v = py_version("importlib.metadata.version('py360convert')", "importlib.metadata")
        peers.append(f"py360convert {p360v}")
    if cmgen:
        peers.append(f"cmgen {dpkg_version('libfilament-tools') or '?'} (Debian's libfilament-tools)")
    elapsed = time.perf_counter() - started

    lines = [BEGIN, "",
             "<!-- Written by envmap-bench/scripts/performance-tables.py: edit the script, not these lines. -->", "",
             f"- **Machine**: {cpu} ({simd}), {ncpu} cores, {mem:.0f} GiB, {osname}; a shared virtual machine "
             f"(load average {loads_before[0]:.1f} before the timings, {loads_after[0]:.1f} after).",
             f"- **envmap** {version.group(1) if version else '?'}, {rustc}, "
             + ("the default build (x86-64 baseline: SSE2) and, in the rows so marked, the native build "
                "(`RUSTFLAGS=\"-C target-cpu=native\"`)." if native else
                "the default build (`cargo build --release`, x86-64 baseline: SSE2)."),
             f"- **Peers**: {'; '.join(peers) if peers else 'none installed'}; Python {platform.python_version()}.",
             f"- **Method**: whole processes, each command alternated with the others of its table run by run, "
             f"{'no warm-up' if not warmup else 'after one warm-up run each (none for the bake, whose input is cached by then)'}; "
             f"medians of {runs} runs ({slow_runs} for the bake, the lit render and the files); "
             f"the inputs and timings took {elapsed / 60:.0f} min.", ""]
    for note in notes:
        lines += [f"*{note}*", ""]
    for title, intro, rows, n, w in sections:
        lines += [f"### {title}", ""] + intro + [""] + table(rows) + [""]
    lines.append(END)
    block = "\n".join(lines)

    if a.stdout:
        print(block)
        return 0
    page = Path(a.page)
    text = page.read_text()
    if BEGIN not in text or END not in text:
        sys.exit(f"performance-tables: {page} has no {BEGIN} … {END} markers")
    pre, rest = text.split(BEGIN, 1)
    _, post = rest.split(END, 1)
    page.write_text(pre + block + post)
    log(f"wrote {page} ({elapsed:.0f} s)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
