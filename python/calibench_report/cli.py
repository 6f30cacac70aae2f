"""calibench report DIR... [--out REPORT_DIR]: plots, scoreboards and paired tests of `calibench
run` output directories (and of `calibench corner-bias`'s), written to REPORT_DIR/report.md, its
appendix pages and PNG figures. `calibench report` runs this (python3 -m calibench_report; or the
installed command calibench-report), with the interpreter and package it finds (docs/cli.md)."""
import argparse
import os
import sys

from calibench_report import document, io


def main(argv=None):
    parser = argparse.ArgumentParser(prog="calibench report", description=__doc__.split("\n")[0])
    parser.add_argument("--out", required=True, help="report directory")
    parser.add_argument("dirs", nargs="+", help="run output directories")
    args = parser.parse_args(argv)
    os.makedirs(args.out, exist_ok=True)
    try:
        data = io.read(args.dirs)
    except ValueError as e:
        print(f"calibench report: {e}", file=sys.stderr)
        return 2
    pages = document.build(data, args.out)
    for name, text in pages.items():
        path = os.path.join(args.out, name)
        os.makedirs(os.path.dirname(path), exist_ok=True)
        io.write_text(path, text)
    print(f"calibench report: wrote {os.path.join(args.out, 'report.md')} and "
          f"{len(pages) - 1} appendix pages", file=sys.stderr)
    return 0
