#!/usr/bin/python3
"""Rendered ceres f.ku error against the oracle's at the same corner RMS, with intervals.

Usage: noise_matched.py RUNS_CSV   (runs.csv of configs/diagnostics/noise_matched.yaml)
The oracle sweep (rows swept over noise.pixel_sigma_px) gives |f.ku error| against the Euclidean
corner RMS sigma * sqrt 2; each rendered point (rows swept over rendering.noise_sigma_gray) is set
against it at its median measured corner_rms_px by log-log interpolation, as the report's
"Rendered against oracle at equal corner RMS" table does. Printed per rendered point: detection
rate, corner RMS, the median |error| and the RMSE, RMSE / CRLB (ceres' per-trial bound), mean
error, and both ratios to the oracle with 90% bootstrap intervals (trials resampled in both
sweeps, 2000 draws, seed 1).
"""
import sys

import numpy as np
import pandas as pd

METHOD = "ceres"
ORACLE_AXIS = "noise.pixel_sigma_px"
RENDERED_AXIS = "rendering.noise_sigma_gray"


def rmse(a):
    return float(np.sqrt(np.mean(np.square(a))))


def at(stat, oracle, x):
    """stat of the oracle's |errors| interpolated log-log at corner RMS x."""
    levels = sorted(oracle)
    ys = [np.log(max(stat(oracle[lv]), 1e-12)) for lv in levels]
    return float(np.exp(np.interp(np.log(x), np.log(levels), ys)))


def main(path):
    runs = pd.read_csv(path)
    runs = runs[(runs.method == METHOD) & (runs.status == "ok")]
    oracle_rows = runs[runs.params.str.startswith(ORACLE_AXIS + "=")]
    oracle = {}
    for params, g in oracle_rows.groupby("params"):
        oracle[float(params.split("=")[1]) * np.sqrt(2)] = np.abs(g.err_fku_px.values)
    if len(oracle) < 2:
        sys.exit(f"{path}: no oracle sweep over {ORACLE_AXIS} with 2 points or more")
    rng = np.random.default_rng(1)
    lo, hi = min(oracle), max(oracle)
    for sweep, rows in runs[runs.params.str.startswith(RENDERED_AXIS + "=")].groupby("sweep"):
        print(sweep)
        for params, g in rows.groupby("params", sort=False):
            e = np.abs(g.err_fku_px.values)
            x = float(np.median(g.corner_rms_px))
            note = "" if lo <= x <= hi else f" (below the oracle's {lo:.4f} px: compared there)"
            x = min(max(x, lo), hi)
            ratios = {"median": [], "rmse": []}
            for _ in range(2000):
                eb = rng.choice(e, len(e))
                ob = {k: rng.choice(v, len(v)) for k, v in oracle.items()}
                ratios["median"].append(np.median(eb) / at(np.median, ob, x))
                ratios["rmse"].append(rmse(eb) / at(rmse, ob, x))
            crlb = np.sqrt(np.mean(np.square(g.crlb_fku_px)))
            line = (f"  {params}: {len(e)} trials, detection rate {g.detect_rate.mean():.3f}, "
                    f"corner RMS {np.median(g.corner_rms_px):.4f} px{note}; median |err| "
                    f"{np.median(e):.4f}, RMSE {rmse(e):.4f} ({rmse(e) / crlb:.2f} CRLB), mean "
                    f"{g.err_fku_px.mean():+.4f} px")
            for name, stat in (("median", np.median), ("rmse", rmse)):
                r = stat(e) / at(stat, oracle, x)
                p5, p95 = np.percentile(ratios[name], [5, 95])
                line += f"; {name} / oracle {r:.2f} [{p5:.2f}, {p95:.2f}]"
            print(line)


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])
