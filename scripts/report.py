#!/usr/bin/python3
"""calibench report: plots, scoreboards and paired tests of `calibench run` output directories.

Usage: calibench report DIR... [--out REPORT_DIR]   (or: report.py --out REPORT_DIR DIR...)

Reads runs.csv, curves.csv and timings.csv (and the tracking files, report_dynamic.py) of each DIR
and writes REPORT_DIR/report.md (atomically: report.md.tmp, then rename) with PNG plots. Quantities
(QUANTITIES): the errors of f*ku, f*kv, u0, v0, phi (only for methods that estimate the skew: an
all-zero or NaN column is skipped), roll, pitch, yaw and the geodesic rotation angle, the
translation error ||x_C error|| and the reprojection RMS. For the swept scenarios (one axis):
  * per sweep kind (noise, points, gain; oracle and rendered side by side): a grid with one panel
    per quantity and detection: median |value| per method against the swept value, its 95% band
    (2.5-97.5 percentiles over the Monte Carlo trials, seed 001's percentile method), log y, the
    Cramer-Rao bound where runs.csv has one, the 0.1 deg target on the angle panels;
  * per sweep: the best method of each quantity at each point, with its adjusted p-value against
    the runner-up;
  * per sweep point a scoreboard (methods as rows): the trials and the data each method used
    (median n_frames_used, n_obs_used where runs.csv has them), per quantity the median |error| and
    the 2.5-97.5 percentiles of |error|, RMSE/CRLB where a crlb_ column is finite, whether the
    0.1 deg target holds (97.5th percentile of |error| <= 0.1 deg on roll and on pitch), the best
    method per quantity; and a table of paired comparisons against the best method: median paired
    difference of |error| with a bootstrap 95% interval, Lilliefors -> paired t-test or Wilcoxon
    signed-rank (seed 001), p-values Holm-adjusted within the table (report_stats.py);
    A point whose trials all gave the same values (nothing random in it) is marked as such;
  * per sweep, the methods that report standard deviations (std_ columns): median reported std
    against the Monte Carlo spread of the error, their ratio, the bias (mean error) and the
    coverage of the 95% intervals (|error| <= 1.96 std), flagged outside the binomial 95% band for
    the number of trials;
  * the gain trade-off (sweeps named gain*, axis methods.<instance>.<gain>), figure and table:
    RMSE and RMSE/CRLB of f*ku, RMSE of roll and pitch, median convergence time and share
    converged against the gain; the CRLB is the instance's own, else that of a method that used
    the same frames and observations, else the first method's with one, and the text says which;
  * oracle vs rendered on one axis: |f*ku error| against the measured corner error;
  * convergence ||theta~||(t) of trial 0 at every sweep point, for every method that reports it;
  * the gain sweep's cost note (gain_cost.txt) and the dynamic section (report_dynamic.py).
The methods are the `method` column's instances, in the order they first appear; the report knows
none by name. An instance whose values of a quantity equal an earlier one's in every row (a method
sharing another's intrinsics) is drawn once and marked "= <that method>" in the tables.
Needs Debian's python3-pandas, python3-scipy, python3-matplotlib and python3-statsmodels.
"""
import argparse
import dataclasses
import gc
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import report_dynamic  # noqa: E402
import report_stats as rs  # noqa: E402

METRIC = "err_fku"  # The focal length error, px: every method estimates it (oracle vs rendered).
METRIC_LABEL = "|f·ku error| (px)"
TARGET_DEG = 0.1  # Seed 001: roll and pitch accurate to 0.1 deg.
TARGET_COLUMNS = ("err_roll_deg", "err_pitch_deg")
DATA_USED = (("n_frames_used", "frames"), ("n_obs_used", "observations"))
STYLE = {}  # method -> colour, assigned in order of first appearance (method_order).


@dataclasses.dataclass(frozen=True)
class Quantity:
    column: str  # runs.csv column: signed error (err_*), or a non-negative value.
    label: str
    unit: str
    angle: bool = False  # Drawn with the 0.1 deg target line.
    optional: bool = False  # Only for methods with a non-zero finite value (phi: fixed skew).

    def side(self, prefix):
        """The column of its reported std or its CRLB: err_fku -> std_fku, crlb_fku."""
        return prefix + self.column[4:] if self.column.startswith("err_") else None

    @property
    def title(self):
        return f"{self.label} ({self.unit})"


QUANTITIES = (
    Quantity("err_fku", "f·ku", "px"),
    Quantity("err_fkv", "f·kv", "px"),
    Quantity("err_u0", "u0", "px"),
    Quantity("err_v0", "v0", "px"),
    Quantity("err_phi_deg", "φ", "°", optional=True),
    Quantity("err_roll_deg", "roll", "°", angle=True),
    Quantity("err_pitch_deg", "pitch", "°", angle=True),
    Quantity("err_yaw_deg", "yaw", "°", angle=True),
    Quantity("rot_err_deg", "geodesic rotation", "°", angle=True),
    Quantity("err_xc_norm", "‖x_C error‖", "m"),
    Quantity("rms_reproj_px", "reprojection RMS", "px"),
)


# ---------------------------------------------------------------------------------------------
# Reading and selecting rows


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


def method_order(rows):
    methods = list(dict.fromkeys(rows.method))
    for m in methods:
        STYLE.setdefault(m, f"C{len(STYLE) % 10}")
    return methods


def ok_rows(rows):
    return rows[rows.status == "ok"]


def present(quantities, rows):
    """The quantities with a finite value in some row (optional ones: a non-zero one)."""
    return [q for q in quantities if q.column in rows and estimates(rows[q.column], q)]


def estimates(values, q):
    v = values.to_numpy(dtype=float)
    finite = np.isfinite(v)
    return finite.any() and (not q.optional or (v[finite] != 0).any())


def by_seed(rows):
    """{method: its ok rows indexed by seed} (trials are paired across methods by seed)."""
    return {m: h.set_index("seed") for m, h in ok_rows(rows).groupby("method", sort=False)}


def twins(series):
    """{method: the earlier method whose series is equal in every row}."""
    out, kept = {}, []
    for m, s in series.items():
        twin = next((k for k in kept if s.index.equals(series[k].index)
                     and np.array_equal(s.to_numpy(), series[k].to_numpy(), equal_nan=True)), None)
        if twin:
            out[m] = twin
        else:
            kept.append(m)
    return out


def distinct_methods(runs, column=METRIC):
    """Methods in order of appearance, without those whose column repeats an earlier one's."""
    method_order(runs)
    series = {m: h.set_index(["scenario", "trial"])[column]
              for m, h in runs.groupby("method", sort=False)}
    same = twins(series)
    return [m for m in series if m not in same]


def quantity_series(frames, q):
    """{method: |q| by seed} of the methods in `frames` (by_seed) that estimate q, twins removed;
    and the twins {method: earlier method with equal values}."""
    series = {m: h[q.column].abs() for m, h in frames.items()
              if q.column in h and estimates(h[q.column], q)}
    same = twins(series)
    return {m: s for m, s in series.items() if m not in same}, same


# ---------------------------------------------------------------------------------------------
# Formatting


def num(x, digits=3):
    return f"{x:.{digits}g}" if x is not None and np.isfinite(x) else "–"


def signed(x):
    return f"{x:+.2g}" if np.isfinite(x) else "–"


def table(head, rows):
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    return "\n".join(lines + ["| " + " | ".join(r) + " |" for r in rows])


def p_text(c):
    if c is None:
        return "–"
    if not c.tested:
        return f"n/a ({c.reason})"
    return f"p {c.p_adjusted:.2g} ({c.test})"


def effect_text(c):
    lo, hi = c.effect_ci
    return f"Δ {signed(c.effect)} [{signed(lo)}, {signed(hi)}]"


# ---------------------------------------------------------------------------------------------
# Sweep figures


def point_axis(rows):
    """({point: swept value}, axis label) of one sweep's rows (points sweeps: feature points)."""
    field, _ = axis_value(rows["params"].iloc[0])
    firsts = rows.drop_duplicates("point")
    if field and field.startswith("points."):
        return dict(zip(firsts.point, firsts.n_points)), "feature points"
    return {p: axis_value(v)[1] for p, v in zip(firsts.point, firsts.params)}, field


def band_line(h, xs, column):
    """[(x, median, p2.5, p97.5) of |column|] over the points of one method's rows h, sorted."""
    return sorted((xs[p], *rs.abs_band(v)) for p, v in ok_rows(h).groupby("point")[column])


def crlb_lines(rows, q, methods, xs):
    """{method: [(x, median crlb)]} for the methods with a finite bound, one per distinct bound."""
    col = q.side("crlb_")
    if not col or col not in rows:
        return {}
    out = {}
    for m in methods:
        b = rows.loc[rows.method == m, ["point", col]].dropna()
        if b.empty:
            continue
        pts = sorted((xs[p], float(np.median(v))) for p, v in b.groupby("point")[col])
        if not any(len(p) == len(pts) and np.allclose([v for _, v in p], [v for _, v in pts])
                   for p in out.values()):
            out[m] = pts
    return out


def plot_quantity(ax, rows, q):
    """One panel: median |q| and 95% band per method against the swept value."""
    xs, xlabel = point_axis(rows)
    method_order(rows)
    series, _ = quantity_series(by_seed(rows), q)
    for m in series:
        pts = band_line(rows[rows.method == m], xs, q.column)
        x = [p[0] for p in pts]
        ax.plot(x, [p[1] for p in pts], "o-", ms=3, color=STYLE[m], label=m)
        ax.fill_between(x, [p[2] for p in pts], [p[3] for p in pts], alpha=0.12, color=STYLE[m])
    for m, pts in crlb_lines(rows, q, list(series), xs).items():
        ax.plot([p[0] for p in pts], [p[1] for p in pts], "--", color=STYLE[m],
                label=f"CRLB (std), {m}'s model")
    if q.angle:
        ax.axhline(TARGET_DEG, color="k", ls=":", lw=1, label=f"{TARGET_DEG}° target")
    ax.set_yscale("log")
    numeric = sorted({x for x in xs.values() if isinstance(x, (int, float, np.integer,
                                                                np.floating))})
    if numeric and min(numeric) > 0 and max(numeric) / min(numeric) >= 20:
        ax.set_xscale("log")
    ax.minorticks_off()  # Minor log ticks on 20+ panels make the layout slow.
    if numeric:  # Ticks at the swept values.
        ax.set_xticks(numeric, [f"{x:g}" for x in numeric])
    ax.set_xlabel(xlabel, fontsize=7)
    ax.set_ylabel(f"|{q.label}| ({q.unit})" if q.column.startswith("err_") else q.title,
                  fontsize=7)
    ax.set_title(f"{q.label} — {rows.sweep.iloc[0]}", fontsize=8)
    ax.tick_params(labelsize=6)
    ax.grid(True, alpha=0.3)


def sweep_grid(runs, sweeps, path):
    """Per quantity one panel per sweep (oracle and rendered side by side), two quantities per row,
    the panels of a quantity on one y scale; one legend for the figure."""
    quantities = present(QUANTITIES, runs[runs.sweep.isin(sweeps)])
    per_row = 2
    nrows = math.ceil(len(quantities) / per_row)
    ncols = per_row * len(sweeps)
    fig, axes = plt.subplots(nrows, ncols, figsize=(3.6 * ncols, 2.7 * nrows), squeeze=False)
    legend = {}
    for i, q in enumerate(quantities):
        r, block = divmod(i, per_row)
        block_axes = [axes[r][block * len(sweeps) + j] for j in range(len(sweeps))]
        for ax, sweep in zip(block_axes, sweeps):
            plot_quantity(ax, runs[runs.sweep == sweep], q)
            legend.update(zip(*reversed(ax.get_legend_handles_labels())))
        lims = [ax.get_ylim() for ax in block_axes]
        for ax in block_axes:
            ax.set_ylim(min(lo for lo, _ in lims), max(hi for _, hi in lims))
    for ax in list(axes.flat)[len(quantities) * len(sweeps):]:
        ax.axis("off")
    fig.legend(list(legend.values()), list(legend.keys()), loc="upper center",
               ncol=min(6, len(legend)), fontsize=8, frameon=False)
    height = 2.7 * nrows  # Fixed margins: tight_layout costs seconds on this many panels.
    fig.subplots_adjust(left=0.04, right=0.99, bottom=0.5 / height, top=1 - 0.7 / height,
                        wspace=0.3, hspace=0.55)
    fig.savefig(path, dpi=80)
    plt.close(fig)


# ---------------------------------------------------------------------------------------------
# Scoreboards


@dataclasses.dataclass
class QuantityScore:
    """One quantity at one sweep point."""
    quantity: Quantity
    bands: dict  # method -> (median, p2.5, p97.5) of |value|
    same: dict  # method -> earlier method with equal values (not scored)
    rmse_crlb: dict  # method -> RMSE / median CRLB
    best: str = None
    runner_up: str = None
    comparisons: dict = dataclasses.field(default_factory=dict)  # method -> Comparison vs best


def rmse_over_crlb(h, q):
    """RMSE of q's error over a method's ok rows h / the median of its finite CRLB."""
    col = q.side("crlb_")
    if not col or col not in h or not np.isfinite(h[col]).any():
        return math.nan
    bound = np.nanmedian(h[col])
    return rs.rmse(h[q.column]) / bound if bound > 0 else math.nan


def score_quantity(frames, q):
    series, same = quantity_series(frames, q)
    score = QuantityScore(q, {m: rs.abs_band(s) for m, s in series.items()}, same,
                          {m: rmse_over_crlb(frames[m], q) for m in series})
    ranked = sorted((b[0], i, m) for i, (m, b) in enumerate(score.bands.items())
                    if np.isfinite(b[0]))
    if not ranked:
        return score
    score.best = ranked[0][2]
    score.runner_up = ranked[1][2] if len(ranked) > 1 else None
    for m in series:
        if m != score.best:
            score.comparisons[m] = rs.compare(rs.paired_differences(series[m], series[score.best]))
    return score


def score_point(rows):
    """[QuantityScore] of one sweep point, the p-values Holm-adjusted over all of them."""
    frames = by_seed(rows)
    scores = [score_quantity(frames, q) for q in present(QUANTITIES, ok_rows(rows))]
    rs.holm([c for s in scores for c in s.comparisons.values()])
    return scores


def data_used(rows, method):
    """The trials and the median data the method's rows used ('not recorded' without columns)."""
    h = rows[rows.method == method]
    ok = int((h.status == "ok").sum())
    cells = [f"{ok}" + (f" ({len(h) - ok} failed)" if ok < len(h) else "")]
    return cells + [f"{v:.0f}" if v is not None else "not recorded" for v in median_data_used(h)]


def target_text(rows, method):
    """✓/✗ of the 0.1 deg target and the 97.5th percentiles of |roll|, |pitch| error."""
    h = ok_rows(rows[rows.method == method])
    if not all(c in h for c in TARGET_COLUMNS):
        return "–"
    p975 = [rs.abs_band(h[c])[2] for c in TARGET_COLUMNS]
    if not all(np.isfinite(p975)):
        return "–"
    mark = "✓" if max(p975) <= TARGET_DEG else "✗"
    return f"{mark} {num(p975[0], 2)} / {num(p975[1], 2)}"


def band_cell(score, method):
    if method in score.same:
        return f"= {score.same[method]}"
    if method not in score.bands:
        return "–"
    med, lo, hi = score.bands[method]
    text = f"**{num(med)}**" if method == score.best else num(med)
    return f"{text} [{num(lo, 2)}, {num(hi, 2)}]"


def crlb_cell(scores, method):
    parts = [f"{s.quantity.label} {s.rmse_crlb[method]:.2f}" for s in scores
             if np.isfinite(s.rmse_crlb.get(method, math.nan))]
    return ", ".join(parts) or "–"


def best_cell(score):
    if not score.best:
        return "–"
    if not score.runner_up:
        return f"{score.best} (alone)"
    c = score.comparisons[score.runner_up]
    return f"{score.best}; vs {score.runner_up} {p_text(c)}"


def scoreboard(rows, methods, scores):
    head = (["method", "trials", "frames used", "observations used"]
            + [s.quantity.title for s in scores]
            + ["RMSE/CRLB", f"{TARGET_DEG}° target: p97.5 roll / pitch (°)"])
    body = [[m] + data_used(rows, m) + [band_cell(s, m) for s in scores]
            + [crlb_cell(scores, m), target_text(rows, m)] for m in methods]
    body.append(["**best** (adj. p vs runner-up)", "", "", ""] + [best_cell(s) for s in scores]
                + ["", ""])
    return table(head, body)


def comparison_cell(score, method):
    if method == score.best:
        return "best"
    if method in score.same:
        return f"= {score.same[method]}"
    c = score.comparisons.get(method)
    if c is None:
        return "–"
    if c.reason == f"n<{rs.MIN_PAIRS}":
        return f"n/a (n={c.n}<{rs.MIN_PAIRS})"
    return f"{effect_text(c)}, {p_text(c)}"


def comparison_table(methods, scores):
    head = ["quantity", "best"] + methods
    body = [[s.quantity.title, s.best or "–"] + [comparison_cell(s, m) for m in methods]
            for s in scores]
    return table(head, body)


def best_summary(point_scores):
    """Per sweep: rows = points, cells = each quantity's best method and its p vs the runner-up."""
    quantities = list(dict.fromkeys(s.quantity for _, scores in point_scores for s in scores))
    body = []
    for params, scores in point_scores:
        by_q = {s.quantity: s for s in scores}
        body.append([params] + [best_cell(by_q[q]) if q in by_q else "–" for q in quantities])
    return table(["point"] + [q.title for q in quantities], body)


def repeats_note(rows, scores):
    """A warning when every trial of the point gave the same values (nothing random in it)."""
    columns = [s.quantity.column for s in scores]
    spread = ok_rows(rows).groupby("method")[columns].agg(np.ptp).to_numpy(dtype=float)
    if rows.trial.nunique() < 2 or np.nanmax(spread, initial=0) > 0:
        return []
    return ["**Every trial of this point gave the same values** (no randomness: the trials "
            "repeat one another); the bands are a single value and no test applies.", ""]


def sweep_section(runs, sweep):
    rows = runs[runs.sweep == sweep]
    methods = method_order(rows)
    trials = rows.trial.nunique()
    points, md = [], []
    for point, g in rows.groupby("point"):
        params = g["params"].iloc[0]
        scores = score_point(g)
        points.append((params, scores))
        md += [f"#### {sweep}: {params}", ""] + repeats_note(g, scores) + [
               scoreboard(g, methods, scores), "",
               "Paired comparisons with the best method (Δ = |error| − |error of best|, median "
               "and bootstrap 95% interval; Holm-adjusted p over this table):", "",
               comparison_table(methods, scores), ""]
    head = [f"### {sweep} ({trials} trials per point)", "",
            "Best method per quantity (smallest median |error|) and its Holm-adjusted p-value "
            "against the runner-up (adjusted within the point's comparison table):", "",
            best_summary(points), ""]
    return head + md


# ---------------------------------------------------------------------------------------------
# Reported standard deviations against the Monte Carlo spread


def std_quantities(rows):
    return [q for q in QUANTITIES if q.side("std_") in rows
            and np.isfinite(rows[q.side("std_")]).any()]


def std_methods(rows, quantities):
    """The methods with a finite reported std, without those whose std and errors repeat an
    earlier one's; and those twins {method: earlier method}."""
    stds = [q.side("std_") for q in quantities]
    cols = [q.column for q in quantities] + stds
    frames = {m: h.set_index(["point", "seed"])[cols].sort_index()
              for m, h in ok_rows(rows).groupby("method", sort=False)
              if np.isfinite(h[stds].to_numpy(dtype=float)).any()}
    same = twins(frames)
    return [m for m in frames if m not in same], same


def std_cell(h, q):
    """'reported / spread = ratio; bias; coverage' with ⚠ outside the binomial band."""
    err, std = h[q.column].to_numpy(dtype=float), h[q.side("std_")].to_numpy(dtype=float)
    if not np.isfinite(std).any():
        return "–"
    spread = np.nanstd(err, ddof=1) if np.isfinite(err).sum() > 1 else math.nan
    reported = np.nanmedian(std)
    ratio = reported / spread if spread > 0 else math.nan
    cover, n = rs.coverage(err, std)
    lo, hi = rs.coverage_band(n)
    flag = " ⚠" if not lo <= cover <= hi else ""
    return (f"{num(reported, 2)} / {num(spread, 2)} = {num(ratio, 2)}; bias "
            f"{signed(np.nanmean(err))}; {100 * cover:.0f}%{flag}")


def uncertainty_table(rows):
    quantities = std_quantities(ok_rows(rows))
    methods, same = std_methods(rows, quantities)
    if not methods:
        return None
    body, ns = [], set()
    for point, g in rows.groupby("point"):
        for m in methods:
            h = ok_rows(g[g.method == m])
            ns.add(len(h))
            body.append([g["params"].iloc[0], m, str(len(h))]
                        + [std_cell(h, q) for q in quantities])
    bands = "; ".join(f"{n} trials: {rs.coverage_band(n)[0]:.2f}–{rs.coverage_band(n)[1]:.2f}"
                      for n in sorted(ns))
    head = ["point", "method", "trials"] + [q.title for q in quantities]
    notes = [f"Band of the coverage: {bands}."]
    notes += [f"{m}: the same stds and errors as {t} in every row (not repeated)."
              for m, t in same.items()]
    return table(head, body), " ".join(notes)


def uncertainty_section(runs, sweeps):
    md = ["## Reported uncertainty against the Monte Carlo spread", "",
          "For each method that reports standard deviations (std_ columns of runs.csv): "
          "*reported / spread = ratio; bias; coverage*. Reported: the median over the trials of "
          "the std the method reports; spread: the standard deviation over the trials of its "
          "error (ddof 1; 0 when the trials repeat one another); ratio > 1: the method overstates "
          "its uncertainty; bias: the mean signed error, which no std covers. Coverage: the "
          "share of trials with |error| ≤ 1.96·std (its 95% interval holds the truth); ⚠ marks a "
          "coverage outside the binomial 95% band for that number of trials at a true coverage "
          "of 95%.", ""]
    any_table = False
    for sweep in sweeps:
        result = uncertainty_table(runs[runs.sweep == sweep])
        if result is None:
            continue
        text, notes = result
        md += [f"### {sweep}", "", notes, "", text, ""]
        any_table = True
    return md if any_table else []


# ---------------------------------------------------------------------------------------------
# Gain trade-off


def gain_instance(sweep, params):
    """The instance and gain of a gain sweep point 'methods.<instance>.<gain>=value', else None."""
    field, value = axis_value(params)
    if not sweep.startswith("gain") or not field or not field.startswith("methods."):
        return None
    instance, _, gain = field[len("methods."):].rpartition(".")
    return (instance, gain, value) if instance and isinstance(value, float) else None


def median_data_used(h):
    """(median n_frames_used, median n_obs_used) of rows h; None where not recorded (no column,
    or only -1)."""
    out = []
    for col, _ in DATA_USED:
        v = h[col].to_numpy(dtype=float) if col in h else np.array([])
        v = v[np.isfinite(v) & (v >= 0)]
        out.append(float(np.median(v)) if v.size else None)
    return tuple(out)


def bound_of(g, instance, column):
    """(median CRLB, whose rows, how they relate): the instance's own bound if finite, else that of
    the first method that used the same frames and observations (where recorded), else of the
    first method with one (its views may differ)."""
    if column not in g:
        return math.nan, None, ""
    mine = median_data_used(g[g.method == instance])
    others = [m for m in dict.fromkeys(g.method) if m != instance]
    same = [m for m in others if None not in mine and median_data_used(g[g.method == m]) == mine]
    for m in [instance] + same + [m for m in others if m not in same]:
        b = g.loc[g.method == m, column]
        if np.isfinite(b).any():
            relation = ("own" if m == instance else "same data" if m in same
                        else "other data" if None not in mine else "data not recorded")
            return float(np.nanmedian(b)), m, relation
    return math.nan, None, ""


def gain_point(g, instance):
    h = ok_rows(g[g.method == instance])
    out = {"trials": len(h), "rmse": {}, "crlb": {}, "crlb_of": {}, "crlb_relation": {}}
    for q in QUANTITIES:
        if q.column in ("err_fku",) + TARGET_COLUMNS and q.column in h:
            out["rmse"][q] = rs.rmse(h[q.column])
            out["crlb"][q], out["crlb_of"][q], out["crlb_relation"][q] = bound_of(
                g, instance, q.side("crlb_"))
    t = h["converge_time_s"].to_numpy(dtype=float)
    out["converged"] = float(np.isfinite(t).mean()) if t.size else math.nan
    out["converge_s"] = float(np.nanmedian(t)) if np.isfinite(t).any() else math.nan
    return out


def gain_points(runs):
    """{sweep: (instance, gain name, [(value, gain_point)])} of the gain sweeps."""
    out = {}
    for sweep in dict.fromkeys(runs.sweep):
        rows = runs[runs.sweep == sweep]
        axis = gain_instance(sweep, rows["params"].iloc[0])
        if not axis:
            continue
        pts = [(gain_instance(sweep, g["params"].iloc[0])[2], gain_point(g, axis[0]))
               for _, g in rows.groupby("point")]
        out[sweep] = (axis[0], axis[1], sorted(pts, key=lambda p: p[0]))
    return out


def gain_figure(gains, path):
    """(a) RMSE of f·ku with its CRLB, RMSE/CRLB, RMSE of roll and pitch; (b) the median
    convergence time and the share converged, against the gain (log x)."""
    fig, axes = plt.subplots(1, 4, figsize=(19, 4), sharex=True)
    share = axes[3].twinx()
    fku = QUANTITIES[0]
    angles = [q for q in QUANTITIES if q.column in TARGET_COLUMNS]
    for k, (sweep, (instance, gain, pts)) in enumerate(gains.items()):
        x = [v for v, _ in pts]
        style = dict(color=f"C{k}", marker="o", ms=4)
        source = next((p["crlb_of"][fku] for _, p in pts if p["crlb_of"][fku]), None)
        axes[0].plot(x, [p["rmse"][fku] for _, p in pts], label=f"RMSE, {sweep}", **style)
        if source:
            axes[0].plot(x, [p["crlb"][fku] for _, p in pts], ls="--", color=f"C{k}",
                         label=f"CRLB ({source}'s rows), {sweep}")
            axes[1].plot(x, [p["rmse"][fku] / p["crlb"][fku] for _, p in pts], label=sweep,
                         **style)
        for q, ls in zip(angles, ("-", ":")):
            axes[2].plot(x, [p["rmse"].get(q, math.nan) for _, p in pts], ls=ls,
                         label=f"{q.label}, {sweep}", **style)
        axes[3].plot(x, [p["converge_s"] for _, p in pts], label=f"median, {sweep}", **style)
        share.plot(x, [100 * p["converged"] for _, p in pts], ls="--", color=f"C{k}",
                   label=f"% converged, {sweep}")
    axes[1].axhline(1, color="k", lw=0.8)
    axes[2].axhline(TARGET_DEG, color="k", ls=":", lw=1, label=f"{TARGET_DEG}° target")
    if not any(np.isfinite(p["converge_s"]) for _, _, pts in gains.values() for _, p in pts):
        axes[3].text(0.5, 0.6, "no trial converged\n(converge_time_s NaN in every row)",
                     ha="center", transform=axes[3].transAxes, fontsize=8)
    share.set_ylim(-5, 105)
    share.set_ylabel("trials converged (%)", fontsize=8)
    titles = ["(a) RMSE of f·ku (px) and its CRLB", "(a) RMSE / CRLB of f·ku",
              "(a) RMSE of roll, pitch (°; no CRLB)", "(b) convergence time (s), % converged"]
    for ax, title in zip(axes, titles):
        ax.set_xscale("log")
        if ax is not axes[3]:
            ax.set_yscale("log")
        ax.set_title(title, fontsize=9)
        ax.set_xlabel(next(iter(gains.values()))[1])
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=6, loc="upper left")
    share.legend(fontsize=6, loc="upper right")
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def gain_table(gains):
    fku = QUANTITIES[0]
    angles = [q for q in QUANTITIES if q.column in TARGET_COLUMNS]
    head = (["sweep", "instance", "gain", "trials", "RMSE f·ku (px)", "CRLB f·ku (px), from",
             "RMSE/CRLB"] + [f"RMSE {q.label} (°)" for q in angles]
            + ["median converge time (s)", "converged"])
    body = []
    for sweep, (instance, gain, pts) in gains.items():
        for value, p in pts:
            body.append([sweep, instance, f"{gain} = {value:g}", str(p["trials"]),
                         num(p["rmse"][fku]),
                         f"{num(p['crlb'][fku])}, {p['crlb_of'][fku] or 'none'}",
                         num(p["rmse"][fku] / p["crlb"][fku])]
                        + [num(p["rmse"].get(q, math.nan)) for q in angles]
                        + [num(p["converge_s"]), f"{100 * p['converged']:.0f}%"])
    return table(head, body)


RELATION_TEXT = {
    "same data": "it used the same frames and observations as {instance} (median n_frames_used "
                 "and n_obs_used)",
    "other data": "no method with {instance}'s frames and observations has one, so its data differ",
    "data not recorded": "the data each method used is not recorded, so its views may differ",
}


def crlb_sources(gains):
    """Sentences saying whose CRLB of f·ku the ratios use."""
    fku = QUANTITIES[0]
    out = []
    for sweep, (instance, _, pts) in gains.items():
        sources = dict.fromkeys((p["crlb_of"][fku], p["crlb_relation"][fku]) for _, p in pts)
        for source, relation in sources:
            if source is None:
                out.append(f"{sweep}: no method has a finite CRLB of f·ku (RMSE alone).")
            elif source == instance:
                out.append(f"{sweep}: the bound of {instance}'s own rows.")
            else:
                why = RELATION_TEXT[relation].format(instance=instance)
                out.append(f"{sweep}: {instance}'s rows have no CRLB; the bound is {source}'s, "
                           f"in its parametrisation: {why}.")
    return out


def gain_section(runs, out):
    gains = gain_points(runs)
    if not gains:
        return []
    gain_figure(gains, os.path.join(out, "gain_tradeoff.png"))
    return (["## Gain trade-off", "",
             "The swept instance (the axis methods.<instance>.<gain>) per gain value: RMSE over "
             "the trials of its f·ku error and of its roll and pitch errors (no CRLB of the angles "
             "exists in runs.csv: RMSE alone), the Cramér–Rao bound of f·ku (median over the "
             "trials of crlb_fku) and RMSE/CRLB; converge_time_s: the time after which ‖θ̃‖ stays "
             "below the instance's convergence tolerance (NaN: still above at the end), its "
             "median over the converged trials and the share of trials converged. CRLB used:", ""]
            + [f"- {s}" for s in crlb_sources(gains)]
            + ["", "![gain trade-off](gain_tradeoff.png)", "", gain_table(gains), ""])


# ---------------------------------------------------------------------------------------------
# Figures kept from the first report


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
    """Error against the measured Euclidean corner error: oracle sigma*sqrt(2), rendered measured
    (median corner_rms_px)."""
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
                pts.append((x, rs.abs_band(ok_rows(h)[METRIC])[0]))
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


CORNER_STAGES = ("raw", "edge_fit", "saddle", "photometric", "lens_aware")
CORNER_STAGE_NAMES = {"raw": "AprilTag 3", "edge_fit": "edge fit", "saddle": "edge fit + saddle",
                      "photometric": "photometric fit", "lens_aware": "lens-aware fit"}


def corner_bias_section(dirs, out):
    """The corner-error study of `calibench corner-bias` (corner_bias.csv in a DIR): per case
    (lens, border, corner squares, tag size, tilt, blur) and stage, the systematic bias along the
    tag diagonals (radial, > 0 outward), the RMS against the Cramer-Rao floor, failed tags and the
    time per tag; figures against viewing angle and of RMS / CRLB per case."""
    paths = [os.path.join(d, "corner_bias.csv") for d in dirs]
    paths = [p for p in paths if os.path.exists(p)]
    if not paths:
        return []
    cb = pd.read_csv(paths[0], keep_default_na=False, na_values=["nan"])
    for col in ("crlb_px", "rms_px", "rms_over_crlb", "bias_radial_px", "bias_tangent_px",
                "view_rms_px", "noise_rms_px"):
        cb[col] = pd.to_numeric(cb[col], errors="coerce")
    per_case = cb.groupby(["case", "stage"], sort=True).agg(
        lens=("lens", "first"), border=("black_border_bits", "first"),
        squares=("corner_squares", "first"), tag_px=("tag_px", "first"),
        tilt=("tilt_deg", "first"), roll=("roll_deg", "first"),
        angle=("view_angle_deg", "first"), blur=("blur_sigma_px", "first"),
        u=("centre_u_px", "first"), v=("centre_v_px", "first"),
        radial=("bias_radial_px", "mean"), tangent=("bias_tangent_px", "mean"),
        radial_max=("bias_radial_px", lambda x: x.abs().max()),
        view_rms=("view_rms_px", "first"), rms=("rms_px", "first"), crlb=("crlb_px", "first"),
        ratio=("rms_over_crlb", "first"), n=("detections", "first"),
        failed=("failed", "first"), refused=("refused", "first"),
        us=("us_per_tag", "first"), status=("status", "first")).reset_index()
    base = per_case[(per_case.lens == "none") & (per_case.border == 1) & (per_case.squares == 0)
                    & (per_case.tag_px == 32) & (per_case.blur == 0.5) & (per_case.u == 319.5)]
    fig, axes = plt.subplots(1, 4, figsize=(19, 4), gridspec_kw={"width_ratios": [1, 1, 1, 1.6]})
    for ax, stage in zip(axes[:3], ("raw", "edge_fit", "photometric")):
        for roll, style in ((0.0, "o-"), (22.5, "s--")):
            h = base[(base.stage == stage) & (base.roll == roll)].sort_values("angle")
            ax.plot(h.angle, h.radial, style, color="C0", label=f"radial (roll {roll:g}°)")
            ax.plot(h.angle, h.tangent, style, color="C1", label=f"tangential (roll {roll:g}°)")
            ax.plot(h.angle, h.view_rms, style, color="C2", alpha=0.6,
                    label=f"view-to-view bias RMS (roll {roll:g}°)")
        ax.axhline(0, color="k", lw=0.5)
        ax.set_title(f"{CORNER_STAGE_NAMES[stage]}: 32 px tag, blur 0.5 px, no lens", fontsize=9)
        ax.set_xlabel("viewing angle (deg)")
        ax.set_ylabel("px")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=6)
    ax = axes[3]
    ok = per_case[np.isfinite(per_case.ratio)]
    for i, stage in enumerate(CORNER_STAGES):
        h = ok[ok.stage == stage]
        ax.scatter(h.case, h.ratio, s=12, color=f"C{i}", label=CORNER_STAGE_NAMES[stage])
    ax.axhline(2, color="k", lw=0.8, ls="--", label="2 × CRLB")
    ax.set_yscale("log")
    ax.set_xlabel("case (table below)")
    ax.set_ylabel("corner RMS per axis / Cramér–Rao std")
    ax.set_title("every case: RMS against the floor", fontsize=9)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=6)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "corner_bias.png"), dpi=110)
    plt.close(fig)

    head = ["case", "lens", "grid", "tag px", "tilt / roll", "blur px"]
    for stage in ("raw", "edge_fit / saddle", "photometric", "lens_aware"):
        head += [f"{stage}: radial bias", "RMS / CRLB", "failed"]
    head += ["CRLB px", "µs per tag (raw, edge, photometric, lens-aware)"]
    lines = []
    for case, g in per_case.groupby("case", sort=True):
        first = g.iloc[0]
        grid = f"{int(first.border)}-bit" + (" + squares" if first.squares else "")
        row = [str(case), first.lens, grid, num(first.tag_px), f"{num(first.tilt)} / {num(first.roll)}",
               num(first.blur)]
        us = []
        for stages in (("raw",), ("edge_fit", "saddle"), ("photometric",), ("lens_aware",)):
            h = g[g.stage.isin(stages)]
            if h.empty:
                row += ["", "", ""]
                continue
            r = h.iloc[0]
            row += [signed(r.radial), num(r.ratio, 2), f"{int(r.failed)}/{int(r.n + r.failed)}"]
            us.append(num(r.us, 3))
        row += [num(first.crlb, 2), ", ".join(us)]
        lines.append(row)
    best = per_case[((per_case.lens == "none") & (per_case.stage == "photometric"))
                    | ((per_case.lens != "none") & (per_case.stage == "lens_aware"))]
    meets = best[(best.radial.abs() <= 0.005) & (best.ratio <= 2)]
    return ["## Corner bias of the rendered pipeline", "",
            f"`calibench corner-bias` ({paths[0]}): one tag36h11 tag rendered (exact to 1/256 px "
            "on an axis-aligned edge), found and refined by every stage on the same frames: "
            "AprilTag 3 alone (quad_decimate 2), the edge fit (on corner squares followed by "
            "the saddle), the photometric fit through a homography, and the photometric fit drawn "
            "through the camera (lens cases). Views are shifted by random sub-pixel offsets, each "
            "with independent noise draws (2 gray levels). Radial bias: the mean error along the "
            "tag's diagonal over the four corners, > 0 outward; RMS per axis over all errors, "
            "against the mean Cramér–Rao std of the photometric corners (lens-aware with a lens).",
            "",
            f"With the fit that matches the case (photometric without a lens, lens-aware with "
            f"one), {len(meets)} of {len(best)} cases have |radial bias| ≤ 0.005 px and RMS ≤ "
            "2 × CRLB. The lone tag with corner squares is harder to find than a grid's (a grid's "
            "tags are found by painting out the squares next to the tags already found).", "",
            "![corner bias](corner_bias.png)", "", table(head, lines), ""]


def matched_oracle_table(runs):
    """Per rendered noise point and method: the median |f*ku error| against the oracle's at the
    same Euclidean corner RMS (the oracle's sigma * sqrt(2) interpolated, log-log, in the oracle
    noise sweep's medians: same rig, same motion distribution), and their ratio."""
    oracle, rendered = runs[runs.sweep == "noise_oracle"], runs[runs.sweep == "noise_rendered"]
    if oracle.empty or rendered.empty:
        return []
    curve = {}  # method -> [(corner rms, median |err|)]
    for (point, method), h in oracle.groupby(["point", "method"], sort=False):
        _, sigma = axis_value(h["params"].iloc[0])
        curve.setdefault(method, []).append((float(sigma) * math.sqrt(2),
                                             rs.abs_band(ok_rows(h)[METRIC])[0]))
    head = ["rendered point", "corner RMS (px)", "method", "rendered median |f·ku err|",
            "oracle at that RMS", "ratio (target ≤ 1.5)"]
    lines = []
    for point, g in rendered.groupby("point"):
        rms = float(np.nanmedian(g["corner_rms_px"]))
        for method in distinct_methods(g):
            pts = sorted(curve.get(method, []))
            if len(pts) < 2 or not (pts[0][0] <= rms <= pts[-1][0]):
                continue
            x = np.log([p[0] for p in pts])
            y = np.log([max(p[1], 1e-12) for p in pts])
            at = float(np.exp(np.interp(math.log(rms), x, y)))
            mine = rs.abs_band(ok_rows(g[g.method == method])[METRIC])[0]
            lines.append([g["params"].iloc[0], num(rms), method, num(mine), num(at),
                          num(mine / at) if at > 0 else "–"])
    if not lines:
        return []
    return ["### Rendered against oracle at equal corner RMS", "",
            "Each rendered noise point's median |f·ku error| against the oracle noise sweep's at "
            "the same Euclidean corner RMS (oracle σ·√2; log-log interpolation between its "
            "points), method by method.", "", table(head, lines), ""]


# ---------------------------------------------------------------------------------------------
# The document


def introduction(dirs, runs):
    recorded = [label for col, label in DATA_USED
                if col in runs and (runs[col].fillna(-1) >= 0).any()]
    columns = " and ".join(c for c, _ in DATA_USED)
    data = (f"median {' and '.join(recorded)} per method over its trials (runs.csv {columns})"
            if recorded else f"frames and observations used: not recorded (runs.csv has no "
            f"{columns})")
    return [
        "# calibench report", "",
        f"Run directories: {', '.join(dirs)}.", "",
        "Definitions used throughout:", "",
        "- **Quantities**: " + ", ".join(q.title for q in QUANTITIES) + ". Errors are estimate "
        "minus truth; φ only for methods that estimate the skew (an all-zero column is skipped); "
        "the reprojection RMS is a fit, not an error against the truth.",
        "- **Median and 95% interval**: of the *absolute* error |error| over the Monte Carlo "
        "trials (the 2.5th and 97.5th percentiles, seed 001's percentile interval), cells "
        "*median [p2.5, p97.5]*; the best method's median in bold. Plots: the same medians and "
        "bands, log y; dashed: the Cramér–Rao standard deviation of a method's parametrisation "
        "where runs.csv has one; dotted: the 0.1° target on angles.",
        "- **RMSE/CRLB**: the RMSE over the trials of the signed error divided by the median over "
        "the trials of the method's crlb_ column, where that is finite (≈ 1: efficient).",
        f"- **{TARGET_DEG}° target** (seed 001: roll and pitch accurate to {TARGET_DEG}°): holds "
        f"(✓) when the 97.5th percentile of |error| is ≤ {TARGET_DEG}° for roll and for pitch; "
        "the cell gives both percentiles. Yaw and the geodesic angle are shown, not part of it.",
        "- **Best method** of a quantity at a point: the smallest median |error|.",
        "- **Paired comparison** with the best method on the same trials (same seed: same frames, "
        "same noise; trials without a finite value in both dropped): Δ = |error of method| − "
        "|error of best|. Lilliefors test of normality of Δ at the 5% level; not rejected: paired "
        "t-test (t), rejected: Wilcoxon signed-rank test (W). Effect size: median Δ with a "
        f"percentile bootstrap 95% interval ({rs.BOOTSTRAP_RESAMPLES} resamples, numpy Generator "
        f"seed {rs.BOOTSTRAP_SEED}). **The p-values shown are Holm–Bonferroni adjusted** over all "
        f"the comparisons of the point's table. n/a: fewer than {rs.MIN_PAIRS} paired trials, "
        "identical series (Δ = 0), or the same Δ in every trial (Δ constant: the trials repeat one "
        "another, e.g. rendered frames without image noise). With 5 trials the smallest two-sided "
        "Wilcoxon p is 0.0625 (a paired t-test can go lower).",
        f"- **Data used**: the number of ok trials per method (failed ones in brackets), and the "
        f"{data}.",
        "- A method whose values of a quantity equal an earlier method's in every row is shown "
        "as \"= that method\" and left out of that quantity's tests and plots.", ""]


def sweep_kinds(runs):
    swept = [s for s in dict.fromkeys(runs.sweep)
             if axis_value(runs[runs.sweep == s].params.iloc[0])[0]]
    kinds = {}
    for s in swept:
        kinds.setdefault(kind_of(s)[0], []).append(s)
    return swept, kinds


def read_all(dirs):
    all_runs, all_curves, notes = [], [], []
    for d in dirs:
        if not os.path.exists(os.path.join(d, "runs.csv")) and os.path.exists(
                os.path.join(d, "corner_bias.csv")):
            continue  # A directory of the corner study only.
        try:
            runs, curves, _ = read_dir(d)
        except (OSError, pd.errors.ParserError) as e:
            raise ValueError(f"{d}: {e}") from e
        all_runs.append(runs)
        all_curves.append(curves)
        cost = os.path.join(d, "gain_cost.txt")
        if os.path.exists(cost):
            notes.append(open(cost).read().strip())
    runs = pd.concat(all_runs, ignore_index=True)
    curves = pd.concat(all_curves, ignore_index=True) if all_curves else pd.DataFrame()
    return runs, curves, notes


def document(args, runs, curves, notes):
    swept, kinds = sweep_kinds(runs)
    md = introduction(args.dirs, runs)
    for kind, sweeps in kinds.items():
        name = f"error_vs_{kind}.png"
        sweep_grid(runs, sweeps, os.path.join(args.out, name))
        md += [f"## {kind}", "", f"![quantities vs {kind}]({name})", ""]
        for sweep in sweeps:
            md += sweep_section(runs, sweep)
    md += gain_section(runs, args.out)
    md += uncertainty_section(runs, swept)
    if oracle_vs_rendered(runs, os.path.join(args.out, "oracle_vs_rendered.png")):
        md += ["## Oracle vs rendered detections", "",
               "The noise sweeps on one axis: the error against the corner error the estimators "
               "actually saw.", "", "![oracle vs rendered](oracle_vs_rendered.png)", ""]
        md += matched_oracle_table(runs)
    if convergence_plot(curves, swept, os.path.join(args.out, "convergence.png")):
        md += ["## Adaptive convergence", "", "‖θ̃‖(t) of trial 0 at every sweep point.", "",
               "![convergence](convergence.png)", ""]
    md += corner_bias_section(args.dirs, args.out)
    if notes:
        md += ["## Cost of a method-only sweep", ""] + notes + [""]
    return md + report_dynamic.section(args.dirs, args.out)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--out", required=True)
    parser.add_argument("dirs", nargs="+")
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    try:
        runs, curves, notes = read_all(args.dirs)
    except ValueError as e:
        print(f"calibench report: {e}", file=sys.stderr)
        return 2
    gc.freeze()  # statsmodels' Holm adjustment calls gc.collect(): skip the frames read so far.
    md = document(args, runs, curves, notes)
    tmp = os.path.join(args.out, "report.md.tmp")
    with open(tmp, "w") as f:
        f.write("\n".join(md) + "\n")
    os.replace(tmp, os.path.join(args.out, "report.md"))
    print(f"calibench report: wrote {os.path.join(args.out, 'report.md')}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
