#!/usr/bin/python3
"""Per-method RMSE of the intrinsics against the Cramer-Rao bound, and extrinsic errors, from a
calibench runs.csv.

Usage: tools/rmse_vs_crlb.py out/crlb50/runs.csv [BOUND_METHOD]
The bound is the median crlb_* of BOUND_METHOD's rows (default: the first method whose rows carry
one; the same for every trial: it depends on the geometry and sigma only). Also prints, for every
method that reports standard deviations, their mean over its empirical RMSE.
Run with Debian's /usr/bin/python3 (pandas, numpy).
"""
import os
import sys

import numpy as np
import pandas as pd

PARAMS = ["fku_px", "fkv_px", "phi_deg", "u0_px", "v0_px"]


def main(path, bound_method=None):
    df = pd.read_csv(path)
    timings = os.path.join(os.path.dirname(path), "timings.csv")  # wall_ms lives there.
    if os.path.exists(timings):
        df = df.merge(pd.read_csv(timings)[["scenario", "trial", "method", "wall_ms"]],
                      on=["scenario", "trial", "method"], how="left")
    else:
        df["wall_ms"] = np.nan
    if bound_method is None:
        with_bound = df[df.crlb_fku_px.notna()]
        bound_method = with_bound.method.iloc[0] if len(with_bound) else df.method.iloc[0]
    bounded = df[df.method == bound_method]
    crlb = {p: bounded["crlb_" + p].median() for p in PARAMS}
    ok = df[df.status == "ok"]
    print(f"{path}: trials per method {ok.groupby('method').size().to_dict()}, "
          f"failed rows {(df.status != 'ok').sum()}")
    print("| method | " + " | ".join(f"{p} RMSE (×CRLB)" for p in PARAMS) +
          " | rot_err_deg median | xc_err_m median | median wall_ms |")
    print("|---" * (len(PARAMS) + 4) + "|")
    for method, g in ok.groupby("method"):
        cells = []
        for p in PARAMS:
            rmse = float(np.sqrt(np.nanmean(g["err_" + p].to_numpy() ** 2)))
            cells.append(f"{rmse:.4f} ({rmse / crlb[p]:.2f})")
        print(f"| {method} | " + " | ".join(cells) + f" | {g.rot_err_deg.median():.4f} | "
              f"{g.xc_err_m.median():.5f} | {g.wall_ms.median():.1f} |")
    print("| CRLB std | " + " | ".join(f"{crlb[p]:.4f}" for p in PARAMS) + " | | | |")
    for method, g in ok.groupby("method", sort=False):
        if not g.std_fku_px.notna().any():
            continue
        ratios = {p: g["std_" + p].mean() / np.sqrt(np.mean(g["err_" + p] ** 2)) for p in PARAMS}
        print(f"{method} reported std / empirical RMSE: " +
              ", ".join(f"{p} {r:.3f}" for p, r in ratios.items()))


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "out/crlb50/runs.csv",
         sys.argv[2] if len(sys.argv) > 2 else None)
