#!/usr/bin/python3
"""calibench report: plots and paired tests of `calibench run` output directories.

Usage: calibench report DIR... [--out REPORT_DIR]   (or: report.py --out REPORT_DIR DIR...)

Reads runs.csv, summary.csv, curves.csv and timings.csv of each DIR and writes REPORT_DIR/report.md
with PNG plots:
  * per sweep kind (noise, points, gain; oracle and rendered side by side): |error of f*ku| per
    method against the swept value, median line and 95% band (2.5-97.5 percentiles over the Monte
    Carlo trials, seed 001's percentile method), with the Cramer-Rao bound where runs.csv has one;
  * oracle vs rendered on one axis: error against the measured corner error;
  * adaptive convergence ||theta~||(t) of trial 0 at every sweep point;
  * per sweep point, paired Wilcoxon signed-rank tests (seed 001) of |error| between the adaptive
    estimator and each batch method, trials paired by seed; the p-values are in the tables.
Needs Debian's python3-pandas, python3-scipy and python3-matplotlib.
"""
import argparse
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402
from scipy import stats  # noqa: E402

METRIC = "err_fku"  # The focal length error, px: every method estimates it.
METRIC_LABEL = "|f·ku error| (px)"
METHOD_STYLE = {"adaptive": "C0", "dlt": "C1", "zhang": "C2", "zhang_handeye": "C4", "ceres": "C3"}
PAIRS = [("adaptive", "dlt"), ("adaptive", "zhang"), ("adaptive", "ceres"), ("zhang", "ceres")]


def read_dir(d):
    runs = pd.read_csv(os.path.join(d, "runs.csv"), keep_default_na=False, na_values=["nan"])
    runs["params"] = runs["params"].astype(str)
    curves_path = os.path.join(d, "curves.csv")
    curves = pd.read_csv(curves_path) if os.path.exists(curves_path) else pd.DataFrame()
    timings = pd.read_csv(os.path.join(d, "timings.csv"))
    return runs, curves, timings


def axis_value(params):
    """The (field, value) of a one-axis sweep point 'field=value'."""
    if not params or params == "nan" or ";" in params:
        return None, None
    field, value = params.split("=", 1)
    try:
        return field, float(value)
    except ValueError:
        return field, value


def kind_of(sweep):
    """noise_oracle -> (noise, oracle)."""
    for detections in ("oracle", "rendered"):
        if sweep.endswith("_" + detections):
            return sweep[: -len(detections) - 1], detections
    return sweep, ""


def band(values):
    v = np.abs(np.asarray(values, dtype=float))
    v = v[np.isfinite(v)]
    if v.size == 0:
        return math.nan, math.nan, math.nan
    return np.median(v), np.quantile(v, 0.025), np.quantile(v, 0.975)


def x_of(group, field):
    if field and field.startswith("points."):
        return group["n_points"].iloc[0], "feature points"
    _, value = axis_value(group["params"].iloc[0])
    return value, field


def plot_sweep(ax, runs, sweep):
    rows = runs[runs.sweep == sweep]
    field, _ = axis_value(rows["params"].iloc[0])
    xlabel = field
    lines = {}
    crlb = []
    for (point, method), g in rows[rows.method != "zhang_handeye"].groupby(["point", "method"]):
        x, xlabel = x_of(g, field)
        ok = g[g.status == "ok"]
        lines.setdefault(method, []).append((x, *band(ok[METRIC])))
        if method == "ceres" and np.isfinite(g["crlb_fku"]).any():
            crlb.append((x, np.nanmedian(g["crlb_fku"])))
    for method, pts in lines.items():
        pts.sort()
        x = [p[0] for p in pts]
        ax.plot(x, [p[1] for p in pts], "o-", color=METHOD_STYLE.get(method), label=method)
        ax.fill_between(x, [p[2] for p in pts], [p[3] for p in pts], alpha=0.15,
                        color=METHOD_STYLE.get(method))
    if crlb:
        crlb.sort()
        # The bound on the standard deviation; |error| of an efficient estimator has median 0.67 of it.
        ax.plot([c[0] for c in crlb], [c[1] for c in crlb], "k--", label="CRLB (std)")
    ax.set_yscale("log")
    if field and (field.startswith("methods.adaptive.alpha") or "sigma" in field):
        ax.set_xscale("log" if min(p[0] for p in lines[next(iter(lines))]) > 0 else "linear")
    ax.set_xlabel(xlabel)
    ax.set_ylabel(METRIC_LABEL)
    ax.set_title(sweep)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)


def wilcoxon_table(runs, sweep):
    rows = runs[runs.sweep == sweep]
    methods = [m for m in ["adaptive", "dlt", "zhang", "ceres"] if m in set(rows.method)]
    pairs = [p for p in PAIRS if p[0] in methods and p[1] in methods]
    head = ["point", "n"] + [f"median {m}" for m in methods] + [f"p {a} vs {b}" for a, b in pairs]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for point, g in rows.groupby("point"):
        by_method = {m: g[g.method == m].set_index("seed") for m in methods}
        cells = [g["params"].iloc[0], str(g["trial"].nunique())]
        for m in methods:
            ok = by_method[m][by_method[m].status == "ok"]
            cells.append(f"{np.median(np.abs(ok[METRIC])):.4g}" if len(ok) else "–")
        for a, b in pairs:
            ja = by_method[a][by_method[a].status == "ok"][METRIC].abs()
            jb = by_method[b][by_method[b].status == "ok"][METRIC].abs()
            common = ja.index.intersection(jb.index)
            d = (ja[common] - jb[common]).to_numpy()
            d = d[np.isfinite(d)]
            if len(d) < 5 or np.all(d == 0):
                cells.append("n/a (n<5)" if len(d) < 5 else "n/a (identical)")
                continue
            p = stats.wilcoxon(d).pvalue
            winner = a if np.median(d) < 0 else b
            cells.append(f"{p:.2g} ({winner})")
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


def convergence_plot(curves, sweeps, path):
    adaptive = curves[curves.method == "adaptive"] if len(curves) else curves
    shown = [s for s in sweeps if len(adaptive) and adaptive.scenario.str.startswith(s + "[").any()]
    if not shown:
        return False
    cols = min(3, len(shown))
    nrows = math.ceil(len(shown) / cols)
    fig, axes = plt.subplots(nrows, cols, figsize=(5 * cols, 3.6 * nrows), squeeze=False)
    for ax, sweep in zip(axes.flat, shown):
        sub = adaptive[adaptive.scenario.str.startswith(sweep + "[") & (adaptive.trial == 0)]
        for scenario, g in sub.groupby("scenario", sort=False):
            label = scenario[len(sweep) + 1 : -1].split("=")[-1]
            ax.plot(g.t_s, g.theta_err_norm, label=label)
        ax.set_yscale("log")
        ax.set_xlabel("t (s)")
        ax.set_ylabel("‖θ̃‖")
        ax.set_title(sweep + " (trial 0)")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=6)
    for ax in list(axes.flat)[len(shown):]:
        ax.axis("off")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return True


def oracle_vs_rendered(runs, path):
    """Error against the measured Euclidean corner error: oracle sigma*sqrt(2), rendered measured."""
    fig, ax = plt.subplots(figsize=(6.5, 4.2))
    drawn = False
    for sweep, style in (("noise_oracle", "o-"), ("noise_rendered", "s--")):
        rows = runs[runs.sweep == sweep]
        if rows.empty:
            continue
        for method, g in rows.groupby("method"):
            if method == "zhang_handeye":
                continue
            pts = []
            for point, h in g.groupby("point"):
                if sweep.endswith("oracle"):
                    _, sigma = axis_value(h["params"].iloc[0])
                    x = float(sigma) * math.sqrt(2)
                else:
                    x = float(np.nanmedian(h["corner_rms_px"]))
                pts.append((x, band(h[h.status == "ok"][METRIC])[0]))
            pts.sort()
            ax.plot([p[0] for p in pts], [p[1] for p in pts], style,
                    color=METHOD_STYLE.get(method), label=f"{method} ({sweep.split('_')[1]})")
            drawn = True
    if not drawn:
        plt.close(fig)
        return False
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("corner error, RMS (px): oracle σ·√2, rendered measured")
    ax.set_ylabel("median " + METRIC_LABEL)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=6, ncol=2)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return True


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--out", required=True)
    parser.add_argument("dirs", nargs="+")
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    all_runs, all_curves, notes = [], [], []
    for d in args.dirs:
        try:
            runs, curves, timings = read_dir(d)
        except (OSError, pd.errors.ParserError) as e:
            print(f"calibench report: {d}: {e}", file=sys.stderr)
            return 2
        all_runs.append(runs)
        all_curves.append(curves)
        cost = os.path.join(d, "gain_cost.txt")
        if os.path.exists(cost):
            notes.append(open(cost).read().strip())
    runs = pd.concat(all_runs, ignore_index=True)
    curves = pd.concat(all_curves, ignore_index=True) if all_curves else pd.DataFrame()
    swept = [s for s in dict.fromkeys(runs.sweep) if axis_value(runs[runs.sweep == s].params.iloc[0])[0]]
    md = ["# calibench report", "",
          f"Run directories: {', '.join(args.dirs)}. Error metric: {METRIC_LABEL} (every method "
          "estimates f·ku). Lines are medians over the Monte Carlo trials, bands the 2.5–97.5 "
          "percentiles (seed 001's percentile method); the dashed line is the Cramer-Rao standard "
          "deviation where runs.csv has one. p-values: paired Wilcoxon signed-rank tests of "
          "|error| between two methods on the same trials (same frames, same noise); the method in "
          "parentheses has the smaller median error.", ""]
    kinds = {}
    for s in swept:
        kinds.setdefault(kind_of(s)[0], []).append(s)
    for kind, sweeps in kinds.items():
        fig, axes = plt.subplots(1, len(sweeps), figsize=(6 * len(sweeps), 4.2), squeeze=False)
        for ax, sweep in zip(axes.flat, sweeps):
            plot_sweep(ax, runs, sweep)
        fig.tight_layout()
        name = f"error_vs_{kind}.png"
        fig.savefig(os.path.join(args.out, name), dpi=110)
        plt.close(fig)
        md += [f"## {kind}", "", f"![error vs {kind}]({name})", ""]
        for sweep in sweeps:
            trials = runs[runs.sweep == sweep].trial.nunique()
            md += [f"### {sweep} ({trials} trials per point)", "", wilcoxon_table(runs, sweep), ""]
    if oracle_vs_rendered(runs, os.path.join(args.out, "oracle_vs_rendered.png")):
        md += ["## Oracle vs rendered detections", "",
               "The noise sweeps on one axis: the error against the corner error the estimators "
               "actually saw.", "", "![oracle vs rendered](oracle_vs_rendered.png)", ""]
    if convergence_plot(curves, swept, os.path.join(args.out, "convergence.png")):
        md += ["## Adaptive convergence", "", "‖θ̃‖(t) of trial 0 at every sweep point.", "",
               "![convergence](convergence.png)", ""]
    if notes:
        md += ["## Cost of a method-only sweep", ""] + notes + [""]
    with open(os.path.join(args.out, "report.md.tmp"), "w") as f:
        f.write("\n".join(md) + "\n")
    os.replace(os.path.join(args.out, "report.md.tmp"), os.path.join(args.out, "report.md"))
    print(f"calibench report: wrote {os.path.join(args.out, 'report.md')}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
