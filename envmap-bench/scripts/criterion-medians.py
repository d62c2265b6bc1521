#!/usr/bin/env python3
"""Medians of the last criterion run, per benchmark.

Criterion prints each benchmark's *typical* time: the slope of its linear
fit when it sampled linearly, the mean when it sampled flat (the slow jobs
of `files`). One slow iteration moves a mean; the median does not. This
prints the median of the last run's samples (time per iteration), beside the
mean, the fastest and slowest sample and the sample count, read from
`target/criterion/**/new/sample.json` (or the baseline a run saved with
`--save-baseline NAME`: `--baseline NAME`).

    python3 envmap-bench/scripts/criterion-medians.py [REGEX] [--dir target/criterion] [--baseline NAME]

REGEX (Python syntax, searched in the benchmark's id, e.g. 'files/bake')
picks benchmarks; all by default.
"""

import argparse
import json
import pathlib
import re
import statistics
import sys


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("regex", nargs="?", default="", help="benchmark ids to show")
    p.add_argument("--dir", default="target/criterion", help="criterion's output folder")
    p.add_argument("--baseline", default="new", help="the run's folder: new, or a saved baseline")
    a = p.parse_args()
    root = pathlib.Path(a.dir)
    if not root.is_dir():
        print(f"{root}: no criterion output here (run cargo bench first)", file=sys.stderr)
        return 1
    pick = re.compile(a.regex)
    rows = []
    for bench in sorted(root.glob(f"**/{a.baseline}/benchmark.json")):
        try:
            meta = json.loads(bench.read_text())
            sample = json.loads((bench.parent / "sample.json").read_text())
        except (OSError, ValueError) as e:
            print(f"{bench.parent}: {e}", file=sys.stderr)
            continue
        name = meta.get("full_id", str(bench.parent))
        if not pick.search(name):
            continue
        per_iter = [t / n for t, n in zip(sample["times"], sample["iters"]) if n > 0]
        if not per_iter:
            continue
        rows.append(
            (
                name,
                statistics.median(per_iter),
                statistics.fmean(per_iter),
                min(per_iter),
                max(per_iter),
                len(per_iter),
                sample.get("sampling_mode", "?"),
            )
        )
    if not rows:
        print(f"no benchmark matches {a.regex!r} under {root}", file=sys.stderr)
        return 1

    def ms(ns: float) -> str:
        return f"{ns / 1e6:.2f}"

    print("| benchmark | median ms | mean ms | fastest | slowest | samples |")
    print("| --- | ---: | ---: | ---: | ---: | ---: |")
    for name, med, mean, lo, hi, n, mode in rows:
        print(f"| {name} | {ms(med)} | {ms(mean)} | {ms(lo)} | {ms(hi)} | {n} ({mode.lower()}) |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
