#!/usr/bin/python3
"""Thesis sim 3 on an AprilTag rig: the rendered run's final ||theta~|| beside its oracle twins.

Usage: rendered_vs_oracle.py RUNS_CSV [METHOD]   (runs.csv of configs/rendered/all.yaml; METHOD:
the instance to compare, default the first in the file)
Prints, per scenario, ||theta~|| as median and 2.5-97.5% percentile interval over its trials
(the Monte Carlo percentile method of Algers 2018, Umeå University, §3.6), the detection columns
of the rendered run, and where the rendered value falls against the oracle twins' intervals.
"""
import os
import sys

import pandas as pd


def main(path, method=None):
    runs = pd.read_csv(path)
    timings = os.path.join(os.path.dirname(path), "timings.csv")  # measure_ms lives there.
    if os.path.exists(timings):
        runs = runs.merge(pd.read_csv(timings)[["scenario", "trial", "method", "measure_ms"]],
                          on=["scenario", "trial", "method"], how="left")
    else:
        runs["measure_ms"] = float("nan")
    runs = runs[runs.method == (method or runs.method.iloc[0])]
    print(f"{'scenario':26s} {'n':>3s} {'theta~ median':>14s} {'95% interval':>26s}")
    intervals = {}
    for name, g in runs.groupby("scenario", sort=False):
        t = g.theta_err_norm
        lo, med, hi = t.quantile(0.025), t.median(), t.quantile(0.975)
        intervals[name] = (lo, hi)
        print(f"{name:26s} {len(g):3d} {med:14.4g} [{lo:11.4g}, {hi:11.4g}]")
    rendered = runs[runs.scenario.str.endswith("rendered")]
    for _, r in rendered.iterrows():
        print(f"\n{r.scenario}: detection rate {r.detect_rate:.4f}, corner RMS {r.corner_rms_px:.4f} px"
              f" ({r.corner_rms_px / 2 ** 0.5:.4f} px per axis), frames without detections "
              f"{int(r.frames_no_detection)}, render+detect {r.measure_ms / 1000:.1f} s")
        for name, (lo, hi) in intervals.items():
            if name == r.scenario or name.endswith("exact"):
                continue
            inside = "inside" if lo <= r.theta_err_norm <= hi else "outside"
            print(f"  ||theta~|| = {r.theta_err_norm:.4g} is {inside} {name}'s 95% interval")


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2] if len(sys.argv) > 2 else None)
