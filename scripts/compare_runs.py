#!/usr/bin/python3
"""Compare the runs.csv and summary.csv of two calibench run directories.

Usage: compare_runs.py REF_DIR NEW_DIR [--approx [SWEEP:]METHOD[=REL] ...] [--rel 1e-5]

Every row of REF must be in NEW, in the same order, with the same bytes in every column REF has;
NEW may append columns (after REF's last). Rows of an --approx method (or of a method within one
sweep, SWEEP:METHOD) may differ in their last digits: numbers must agree to |a - b| <= rel *
max(1, |a|, |b|), text exactly; rel is --rel, or the entry's own after '='. (cv::calibrateCamera is not bit-reproducible: README,
"Reproducibility of zhang".) Files may be gzipped (runs.csv.gz). Exit 0 when they agree, 1 with
the differences listed otherwise.
"""
import argparse
import csv
import gzip
import io
import math
import os
import sys


def read(directory, name):
    for path, opener in ((os.path.join(directory, name), open),
                         (os.path.join(directory, name + ".gz"), gzip.open)):
        if os.path.exists(path):
            with opener(path, "rt", newline="") as f:
                return list(csv.reader(io.StringIO(f.read())))
    raise SystemExit(f"compare_runs: {directory}: no {name} (or {name}.gz)")


def number(text):
    try:
        return float(text)
    except ValueError:
        return None


def compare(name, ref, new, approx, rel, problems):
    ref_header, new_header = ref[0], new[0]
    if new_header[: len(ref_header)] != ref_header:
        problems.append(f"{name}: the header does not start with the reference's columns")
        return 0
    if len(ref) != len(new):
        problems.append(f"{name}: {len(new) - 1} rows, the reference has {len(ref) - 1}")
    method = ref_header.index("method")
    sweep = ref_header.index("sweep")
    loose = 0
    for k, (a, b) in enumerate(zip(ref[1:], new[1:]), start=2):
        tol = approx.get(f"{a[sweep]}:{a[method]}", approx.get(a[method]))
        is_approx = tol is not None
        tol = rel if tol is None or tol < 0 else tol
        for c, column in enumerate(ref_header):
            if a[c] == b[c]:
                continue
            x, y = number(a[c]), number(b[c])
            if is_approx and x is not None and y is not None and (
                    abs(x - y) <= tol * max(1.0, abs(x), abs(y)) or
                    (math.isnan(x) and math.isnan(y))):
                loose += 1
                continue
            problems.append(f"{name}:{k}: {a[sweep]} {a[method]} {column}: {a[c]} -> {b[c]}")
    return loose


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("ref")
    parser.add_argument("new")
    parser.add_argument("--approx", action="append", default=[])
    parser.add_argument("--rel", type=float, default=1e-5)
    args = parser.parse_args()
    problems = []
    approx = {}  # [SWEEP:]METHOD -> its tolerance, -1: --rel.
    for entry in args.approx:
        key, _, tol = entry.partition("=")
        approx[key] = float(tol) if tol else -1.0
    for name in ("runs.csv", "summary.csv"):
        ref, new = read(args.ref, name), read(args.new, name)
        loose = compare(name, ref, new, approx, args.rel, problems)
        print(f"compare_runs: {name}: {len(ref) - 1} reference rows; {loose} fields of "
              f"{', '.join(args.approx) or 'no method'} within {args.rel:g} relative (or their own), every "
              f"other "
              f"field identical" if not problems else f"compare_runs: {name}: checked")
    for p in problems[:50]:
        print("  " + p)
    if len(problems) > 50:
        print(f"  ... {len(problems) - 50} more")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
