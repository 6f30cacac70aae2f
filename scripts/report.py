#!/usr/bin/python3
"""calibench report: plots and paired tests of `calibench run` output directories.

Usage: calibench report DIR... [--out REPORT_DIR]   (or: report.py --out REPORT_DIR DIR...)

Reads runs.csv, summary.csv, curves.csv and timings.csv of each DIR and writes REPORT_DIR/report.md
with PNG plots:
  * per sweep kind (noise, points, gain; oracle and rendered side by side): |error of f*ku| per
    method instance against the swept value, median line and 95% band (2.5-97.5 percentiles over
    the Monte Carlo trials, seed 001's percentile method), with the Cramer-Rao bound where runs.csv
    has one;
  * oracle vs rendered on one axis: error against the measured corner error;
  * convergence ||theta~||(t) of trial 0 at every sweep point, for every method that reports it;
  * per sweep point, paired Wilcoxon signed-rank tests (seed 001) of |error| between each method
    and the point's best one (smallest median), trials paired by seed; the p-values are in the
    tables.
The methods are the `method` column's instances, in the order they first appear; the report knows
none by name. An instance whose f*ku error equals an earlier one's in every row (zhang_handeye
shares zhang's intrinsics) is drawn once.
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

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import report_dynamic  # noqa: E402

METRIC = "err_fku"  # The focal length error, px: every method estimates it.
METRIC_LABEL = "|f·ku error| (px)"
STYLE = {}  # method -> colour, assigned in order of first appearance (distinct_methods).


def distinct_methods(runs):
    """Methods in order of appearance, without those whose METRIC column repeats an earlier one's."""
    kept, series = [], {}
    for method in dict.fromkeys(runs.method):
        rows = runs[runs.method == method]
        values = rows.set_index(["scenario", "trial"])[METRIC].to_numpy()
        if any(len(v) == len(values) and np.array_equal(v, values, equal_nan=True)
               for v in series.values()):
            continue
        series[method] = values
        kept.append(method)
        STYLE.setdefault(method, f"C{len(STYLE) % 10}")
    return kept


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
    crlb = {}
    methods = distinct_methods(rows)
    for (point, method), g in rows[rows.method.isin(methods)].groupby(["point", "method"], sort=False):
        x, xlabel = x_of(g, field)
        ok = g[g.status == "ok"]
        lines.setdefault(method, []).append((x, *band(ok[METRIC])))
        if np.isfinite(g["crlb_fku"]).any():
            crlb.setdefault(method, []).append((x, np.nanmedian(g["crlb_fku"])))
    for method, pts in lines.items():
        pts.sort()
        x = [p[0] for p in pts]
        ax.plot(x, [p[1] for p in pts], "o-", color=STYLE.get(method), label=method)
        ax.fill_between(x, [p[2] for p in pts], [p[3] for p in pts], alpha=0.15,
                        color=STYLE.get(method))
    drawn = []
    for method, pts in crlb.items():
        pts.sort()
        if any(np.allclose([p[1] for p in pts], d) for d in drawn):
            continue  # The same bound as one already drawn (the same parametrisation).
        drawn.append([p[1] for p in pts])
        # The bound on the standard deviation; |error| of an efficient estimator has median 0.67 of it.
        ax.plot([c[0] for c in pts], [c[1] for c in pts], "--", color=STYLE.get(method),
                label=f"CRLB (std) of {method}'s model")
    ax.set_yscale("log")
    xs = [p[0] for pts in lines.values() for p in pts if isinstance(p[0], (int, float))]
    if xs and min(xs) > 0 and max(xs) / min(xs) >= 20:  # Values spanning decades: a log axis.
        ax.set_xscale("log")
    ax.set_xlabel(xlabel)
    ax.set_ylabel(METRIC_LABEL)
    ax.set_title(sweep)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)


def wilcoxon_table(runs, sweep):
    """Per point: each method's median |error| and, paired by seed, its Wilcoxon p-value against
    the point's best method (smallest median)."""
    rows = runs[runs.sweep == sweep]
    methods = distinct_methods(rows)
    head = ["point", "n"] + [f"{m}: median, p vs best" for m in methods]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for point, g in rows.groupby("point"):
        errors = {}
        for m in methods:
            h = g[(g.method == m) & (g.status == "ok")].set_index("seed")
            errors[m] = h[METRIC].abs()
        medians = {m: np.median(e) if len(e) else math.inf for m, e in errors.items()}
        best = min(methods, key=lambda m: medians[m])
        cells = [g["params"].iloc[0], str(g["trial"].nunique())]
        for m in methods:
            if not len(errors[m]):
                cells.append("–")
                continue
            text = f"{medians[m]:.4g}"
            if m == best:
                cells.append(text + " (best)")
                continue
            common = errors[m].index.intersection(errors[best].index)
            d = (errors[m][common] - errors[best][common]).to_numpy()
            d = d[np.isfinite(d)]
            if len(d) < 5 or np.all(d == 0):
                cells.append(text + (", n/a (n<5)" if len(d) < 5 else ", n/a (identical)"))
            else:
                cells.append(f"{text}, p {stats.wilcoxon(d).pvalue:.2g}")
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


def convergence_plot(curves, sweeps, path):
    shown = [s for s in sweeps if len(curves) and curves.scenario.str.startswith(s + "[").any()]
    if not shown:
        return False
    cols = min(3, len(shown))
    nrows = math.ceil(len(shown) / cols)
    fig, axes = plt.subplots(nrows, cols, figsize=(5 * cols, 3.6 * nrows), squeeze=False)
    for ax, sweep in zip(axes.flat, shown):
        sub = curves[curves.scenario.str.startswith(sweep + "[") & (curves.trial == 0)]
        several = sub.method.nunique() > 1
        for (scenario, method), g in sub.groupby(["scenario", "method"], sort=False):
            label = scenario[len(sweep) + 1 : -1].split("=")[-1]
            ax.plot(g.t_s, g.theta_err_norm, label=f"{method} {label}" if several else label)
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
        methods = distinct_methods(rows)
        for method, g in rows[rows.method.isin(methods)].groupby("method", sort=False):
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
                    color=STYLE.get(method), label=f"{method} ({sweep.split('_')[1]})")
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
    swept = [s for s in dict.fromkeys(runs.sweep)
             if axis_value(runs[runs.sweep == s].params.iloc[0])[0]]
    md = ["# calibench report", "",
          f"Run directories: {', '.join(args.dirs)}. Error metric: {METRIC_LABEL} (every method "
          "estimates f·ku). Lines are medians over the Monte Carlo trials, bands the 2.5–97.5 "
          "percentiles (seed 001's percentile method); dashed lines are the Cramer-Rao standard "
          "deviation of a method's parametrisation where runs.csv has one. Tables: each method's "
          "median |error| and the paired Wilcoxon signed-rank p-value of its |error| against the "
          "point's best method on the same trials (same frames, same noise).", ""]
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
    md += report_dynamic.section(args.dirs, args.out)
    with open(os.path.join(args.out, "report.md.tmp"), "w") as f:
        f.write("\n".join(md) + "\n")
    os.replace(os.path.join(args.out, "report.md.tmp"), os.path.join(args.out, "report.md"))
    print(f"calibench report: wrote {os.path.join(args.out, 'report.md')}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
