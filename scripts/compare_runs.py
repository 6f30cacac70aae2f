#!/usr/bin/python3
"""Compare the runs.csv and summary.csv of two calibench run directories.

Usage: compare_runs.py REF_DIR NEW_DIR [--rename MAP] [--approx [SWEEP:]METHOD[=REL] ...]
                       [--except [SWEEP:]METHOD=COLUMN[,COLUMN...] ...] [--rel 1e-5]

Every row of REF must be in NEW with the same bytes in every column REF has; NEW may append
columns (after REF's last).
  * runs.csv: the same rows in the same order.
  * summary.csv: each REF row is found in NEW by its (scenario, method, metric); NEW may summarise
    metrics REF does not have (their rows are not compared), and must have every REF row once.
--rename MAP: REF was written with older column names. MAP is a CSV file `old,new` (one renamed
column a line; '#' starts a comment) applied to REF's header and to the values of its `metric`
column (summary.csv names a metric by its runs.csv column) before comparing; a column not in MAP
keeps its name.
Rows of an --approx method (or of a method within one sweep, SWEEP:METHOD) may differ in their
last digits: numbers must agree to |a - b| <= rel * max(1, |a|, |b|), text exactly; rel is --rel,
or the entry's own after '='. (cv::calibrateCamera is not bit-reproducible: README,
"Reproducibility of zhang".)
--except: the listed columns of a method's rows (or of a method within one sweep) are not compared,
for a method whose estimates a bug fix changed since REF (the script calling this names the fix):
in runs.csv those fields of its rows may hold anything, while every other field of the rows is
compared as above; in summary.csv its rows summarising one of those columns (metric = COLUMN) need
only exist. Columns are named as today (after --rename); a name REF's runs.csv lacks is an error.
Files may be gzipped (runs.csv.gz). Exit 0 when they agree, 1 with the differences listed
otherwise.
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


def read_rename(path):
    """{old column name: new column name} from a MAP file (see the module doc)."""
    renamed = {}
    with open(path, newline="") as f:
        for k, row in enumerate(csv.reader(f), start=1):
            if not row or row[0].lstrip().startswith("#") or row == ["old", "new"]:
                continue
            if len(row) != 2 or not row[0] or not row[1]:
                raise SystemExit(f"compare_runs: {path}:{k}: expected 'old,new'")
            renamed[row[0].strip()] = row[1].strip()
    return renamed


def renamed_reference(table, rename):
    """REF's rows with its header renamed and its metric values renamed."""
    header = [rename.get(c, c) for c in table[0]]
    rows = [list(r) for r in table[1:]]
    if "metric" in header:
        m = header.index("metric")
        for r in rows:
            r[m] = rename.get(r[m], r[m])
    return [header] + rows


def number(text):
    try:
        return float(text)
    except ValueError:
        return None


class Comparison:
    def __init__(self, approx, rel, excepted=None):
        self.approx, self.rel = approx, rel
        self.excepted = excepted or {}  # [SWEEP:]METHOD -> the set of columns not compared.
        self.problems, self.loose, self.skipped = [], 0, 0

    def excepted_columns(self, ref_header, a):
        method, sweep = ref_header.index("method"), ref_header.index("sweep")
        return self.excepted.get(f"{a[sweep]}:{a[method]}", self.excepted.get(a[method], set()))

    def row(self, name, line, ref_header, a, b, columns):
        """Compares REF row a with NEW row b (b's fields at `columns`, REF's order)."""
        method, sweep = ref_header.index("method"), ref_header.index("sweep")
        tol = self.approx.get(f"{a[sweep]}:{a[method]}", self.approx.get(a[method]))
        is_approx = tol is not None
        tol = self.rel if tol is None or tol < 0 else tol
        excepted = self.excepted_columns(ref_header, a)
        if "metric" in ref_header and a[ref_header.index("metric")] in excepted:
            self.skipped += 1  # summary.csv: a row summarising an excepted column.
            return
        for c, column in enumerate(ref_header):
            x_text, y_text = a[c], b[columns[c]]
            if x_text == y_text:
                continue
            if column in excepted:
                self.skipped += 1
                continue
            x, y = number(x_text), number(y_text)
            if is_approx and x is not None and y is not None and (
                    abs(x - y) <= tol * max(1.0, abs(x), abs(y)) or
                    (math.isnan(x) and math.isnan(y))):
                self.loose += 1
                continue
            self.problems.append(f"{name}:{line}: {a[sweep]} {a[method]} {column}: "
                                 f"{x_text} -> {y_text}")

    def positional(self, name, ref, new):
        """runs.csv: the same rows in the same order."""
        if len(ref) != len(new):
            self.problems.append(f"{name}: {len(new) - 1} rows, the reference has {len(ref) - 1}")
        columns = list(range(len(ref[0])))
        for k, (a, b) in enumerate(zip(ref[1:], new[1:]), start=2):
            self.row(name, k, ref[0], a, b, columns)

    def keyed(self, name, ref, new, key=("scenario", "method", "metric")):
        """summary.csv: each REF row found in NEW by its key; NEW's other metrics ignored."""
        ref_key = [ref[0].index(k) for k in key]
        new_key = [new[0].index(k) for k in key]
        found = {}
        for k, b in enumerate(new[1:], start=2):
            found.setdefault(tuple(b[i] for i in new_key), []).append((k, b))
        columns = list(range(len(ref[0])))
        for a in ref[1:]:
            rows = found.get(tuple(a[i] for i in ref_key), [])
            if len(rows) != 1:
                self.problems.append(f"{name}: {len(rows)} rows for "
                                     f"{', '.join(a[i] for i in ref_key)} (1 expected)")
                continue
            line, b = rows[0]
            self.row(name, line, ref[0], a, b, columns)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("ref")
    parser.add_argument("new")
    parser.add_argument("--rename", help="CSV file old,new of the columns renamed since REF")
    parser.add_argument("--approx", action="append", default=[])
    parser.add_argument("--except", dest="excepted", action="append", default=[],
                        help="[SWEEP:]METHOD=COLUMN[,COLUMN...]: columns not compared")
    parser.add_argument("--rel", type=float, default=1e-5)
    args = parser.parse_args()
    approx = {}  # [SWEEP:]METHOD -> its tolerance, -1: --rel.
    for entry in args.approx:
        key, _, tol = entry.partition("=")
        approx[key] = float(tol) if tol else -1.0
    rename = read_rename(args.rename) if args.rename else {}
    ref_runs_header = renamed_reference(read(args.ref, "runs.csv"), rename)[0]
    excepted = {}  # [SWEEP:]METHOD -> the set of columns not compared.
    for entry in args.excepted:
        key, _, columns = entry.partition("=")
        names = {c.strip() for c in columns.split(",") if c.strip()}
        if not key or not names:
            raise SystemExit(f"compare_runs: --except {entry}: expected [SWEEP:]METHOD=COLUMN,...")
        unknown = sorted(names - set(ref_runs_header))
        if unknown:
            raise SystemExit(f"compare_runs: --except {entry}: no column {', '.join(unknown)} in "
                             "the reference's runs.csv")
        excepted.setdefault(key, set()).update(names)
    comparison = Comparison(approx, args.rel, excepted)
    for name in ("runs.csv", "summary.csv"):
        ref = renamed_reference(read(args.ref, name), rename)
        new = read(args.new, name)
        before = len(comparison.problems)
        loose_before, skipped_before = comparison.loose, comparison.skipped
        if new[0][: len(ref[0])] != ref[0]:
            missing = [c for c in ref[0] if c not in new[0]]
            comparison.problems.append(
                f"{name}: the header does not start with the reference's columns"
                + (f" (missing: {', '.join(missing)})" if missing else ""))
        elif name == "runs.csv":
            comparison.positional(name, ref, new)
        else:
            comparison.keyed(name, ref, new)
        original = read(args.ref, name)
        renamed = sum(1 for c in original[0] if c in rename)
        if "metric" in original[0]:
            m = original[0].index("metric")
            renamed += len({r[m] for r in original[1:] if r[m] in rename})
        if len(comparison.problems) == before:
            skipped = comparison.skipped - skipped_before
            print(f"compare_runs: {name}: {len(ref) - 1} reference rows, {len(ref[0])} columns "
                  f"({renamed} names renamed); {comparison.loose - loose_before} fields of "
                  f"{', '.join(args.approx) or 'no method'} within {args.rel:g} relative (or "
                  "their own)"
                  + (f"; {skipped} {'rows' if name == 'summary.csv' else 'differing fields'} "
                     f"of the excepted columns ({'; '.join(args.excepted)}) not compared"
                     if args.excepted else "")
                  + ", every other field identical")
        else:
            print(f"compare_runs: {name}: checked")
    for p in comparison.problems[:50]:
        print("  " + p)
    if len(comparison.problems) > 50:
        print(f"  ... {len(comparison.problems) - 50} more")
    return 1 if comparison.problems else 0


if __name__ == "__main__":
    sys.exit(main())
