"""The swept scenarios by role: error against the swept value, the best method per point, and
(in an appendix page per sweep) every point's scoreboard and paired comparisons."""
import collections
import functools
import math

import numpy as np

from calibench_report import plots, stats
from calibench_report.sections import Section
from calibench_report.tables import (SIGNIFICANT, band, effect_text, markdown, num, p_text,
                                     error_words, ratio_versus_text)

TITLES = {
    "noise": "Error against the pixel noise",
    "points": "Error against the number of feature points",
    "gain": "Error against the adaptive gain",
    "": "Other sweeps",
}
ROLES = ("noise", "points", "gain", "")


def x_label(sweep):
    return "feature points" if sweep.role == "points" else ", ".join(sweep.axes)


def quantity_lines(analysis, sweep, quantity):
    """({method: [(x, median, lo, hi)]}, {method: [(x, crlb)]}) of one sweep and quantity."""
    lines, bounds = {}, {}
    for score in analysis.scores(sweep):
        s = score.of(quantity)
        if s is None or not isinstance(score.point.x, (int, float)):
            continue
        for m, b in s.bands.items():
            lines.setdefault(m, []).append((score.point.x, *b))
            bound = analysis.stat(score.point.scenario, m, quantity.summary_metric, "crlb")
            if math.isfinite(bound):
                bounds.setdefault(m, []).append((score.point.x, bound))
    distinct = {}
    for m, pts in bounds.items():  # One line per distinct bound.
        if not any(len(p) == len(pts) and np.allclose([v for _, v in p], [v for _, v in pts])
                   for p in distinct.values()):
            distinct[m] = pts
    return ({m: sorted(p) for m, p in lines.items()},
            {m: sorted(p) for m, p in distinct.items()})


def grid(ctx, sweeps, quantities, path, per_row=2):
    """Per quantity one panel per sweep, `per_row` quantities a row, a quantity's panels on one y
    scale, one legend."""
    nrows = math.ceil(len(quantities) / per_row)
    ncols = per_row * len(sweeps)
    fig, axes = plots.figure(nrows, ncols, 3.6, 2.7)
    for i, q in enumerate(quantities):
        r, block = divmod(i, per_row)
        block_axes = [axes[r][block * len(sweeps) + j] for j in range(len(sweeps))]
        for ax, sweep in zip(block_axes, sweeps):
            lines, bounds = quantity_lines(ctx.analysis, sweep, q)
            plots.band_lines(ax, lines, ctx.palette, bounds, q.target)
            plots.axis_scale(ax, [p.x for p in ctx.analysis.points(sweep)])
            ax.set_xlabel(x_label(sweep), fontsize=7)
            ax.set_ylabel(f"|{q.label}| ({q.unit_text})" if q.unit else q.label, fontsize=7)
            ax.set_title(f"{q.label}: {sweep.name}", fontsize=8)
        limits = [ax.get_ylim() for ax in block_axes]
        for ax in block_axes:
            ax.set_ylim(min(lo for lo, _ in limits), max(hi for _, hi in limits))
    for ax in list(axes.flat)[len(quantities) * len(sweeps):]:
        ax.axis("off")
    legend = plots.legend_of(axes.flat)
    fig.legend(list(legend.values()), list(legend.keys()), loc="upper center",
               ncol=min(6, len(legend)), fontsize=8, frameon=False)
    height = 2.7 * nrows  # Fixed margins: tight_layout costs seconds on this many panels.
    fig.subplots_adjust(left=0.05, right=0.99, bottom=0.5 / height, top=1 - 0.75 / height,
                        wspace=0.3, hspace=0.55)
    plots.save(fig, path, dpi=80, tight=False)


def best_cell(score):
    if score is None or not score.best:
        return "–"
    if not score.runner_up:
        return f"{score.best} (alone)"
    return f"{score.best}; vs {score.runner_up} {p_text(score.contest)}"


def best_summary(analysis, sweep):
    """Rows = points, cells = each quantity's best method and its adjusted p vs the runner-up."""
    scores = analysis.scores(sweep)
    quantities = list(dict.fromkeys(s.quantity for p in scores for s in p.quantities))
    rows = [[p.point.label] + [best_cell(p.of(q)) for q in quantities] for p in scores]
    return markdown(rows, ["point"] + [q.title for q in quantities])


# -- the appendix page of a sweep: every point's scoreboard and comparisons ------------------------


def target_text(analysis, scenario, method):
    """✓/✗ of Algers 2018's targets (§1.2) and the 97.5th percentiles of |error| (summary.csv)."""
    targeted = analysis.data.schema.targeted()
    p975 = [analysis.stat(scenario, method, q.summary_metric, "p97_5_abs") for q in targeted]
    if not targeted or not all(math.isfinite(p) for p in p975):
        return "–"
    met = all(p <= q.target for p, q in zip(p975, targeted))
    return f"{'✓' if met else '✗'} " + " / ".join(num(p, 2) for p in p975)


def band_cell(score, method):
    if method in score.same:
        return f"= {score.same[method]}"
    if method not in score.bands:
        return "–"
    return band(*score.bands[method], bold=method == score.best)


def crlb_cell(scores, method):
    parts = [f"{s.quantity.label} {s.rmse_crlb[method]:.2f}" for s in scores
             if math.isfinite(s.rmse_crlb.get(method, math.nan))]
    return ", ".join(parts) or "–"


def data_cells(analysis, point, rows, method):
    ok, failed = analysis.trials(point.scenario, method)
    cells = [f"{ok}" + (f" ({failed} failed)" if failed else "")]
    return cells + [f"{v:.0f}" if v is not None else "not recorded"
                    for v in analysis.data_used(rows, method)]


def scoreboard(analysis, point_score, methods):
    point = point_score.point
    rows = analysis.point_rows(point)
    scores = point_score.quantities
    targeted = analysis.data.schema.targeted()
    target = ("target: p97.5 " + " / ".join(f"{q.label}" for q in targeted)
              + f" ≤ {targeted[0].target:g}{targeted[0].unit_text}") if targeted else "target"
    head = (["method", "trials", "frames used", "observations used"]
            + [s.quantity.title for s in scores] + ["RMSE/CRLB", target])
    body = [[m] + data_cells(analysis, point, rows, m) + [band_cell(s, m) for s in scores]
            + [crlb_cell(scores, m), target_text(analysis, point.scenario, m)] for m in methods]
    body.append(["**best** (adj. p vs runner-up)", "", "", ""]
                + [best_cell(s) for s in scores] + ["", ""])
    return markdown(body, head)


def comparison_cell(score, method):
    if method == score.best:
        return "best"
    if method in score.same:
        return f"= {score.same[method]}"
    c = score.comparisons.get(method)
    if c is None:
        return "–"
    return f"{effect_text(c)}, {p_text(c)}"


def comparison_table(scores, methods):
    head = ["quantity", "best"] + methods
    body = [[s.quantity.title, s.best or "–"] + [comparison_cell(s, m) for m in methods]
            for s in scores]
    return markdown(body, head)


def repeats_note(analysis, point_score, methods):
    """A warning when every trial of the point gave the same values (nothing random in it)."""
    spread = [analysis.stat(point_score.point.scenario, m, s.quantity.summary_metric, "std")
              for s in point_score.quantities for m in methods]
    spread = [x for x in spread if math.isfinite(x)]
    if not spread or max(spread) > 0:
        return []
    return ["**Every trial of this point gave the same values** (no randomness: the trials "
            "repeat one another); the bands are a single value and no test applies.", ""]


def appendix_page(analysis, sweep):
    rows = analysis.rows_of(sweep)
    methods = analysis.methods_of(rows)
    md = [f"# {sweep.name}: every point", "", "[Back to the report](../report.md)", "",
          f"{sweep.trials} trials per point. Per point: the scoreboard (median |error| and its "
          "95% interval over the trials, from summary.csv), then the paired comparisons of each "
          "method with the point's best (Δ = |error| − |error of best|, median with its bootstrap "
          "95% interval; Holm-adjusted p over the point's table).", ""]
    for score in analysis.scores(sweep):
        md += [f"## {score.point.label}", ""] + repeats_note(analysis, score, methods) + [
            scoreboard(analysis, score, methods), "", comparison_table(score.quantities, methods),
            ""]
    return md


def section(ctx, role):
    sweeps = ctx.analysis.data.schema.sweeps_of(role)
    sweeps = [s for s in sweeps if len(ctx.analysis.rows_of(s))]
    if not sweeps:
        return None
    out = Section()
    figure = f"error_vs_{role or 'other'}.png"
    rows = ctx.analysis.data.runs[ctx.analysis.data.runs.sweep.isin([s.name for s in sweeps])]
    quantities = ctx.analysis.present(rows)
    if quantities:
        grid(ctx, sweeps, quantities, ctx.path(figure))
    out.md += [f"## {TITLES[role]}", "",
               "Median |error| over the trials per method against the swept value, with its 95% "
               "band (summary.csv), the Cramér–Rao bound (dashed) and Algers 2018's target "
               "(dotted).",
               ""]
    if quantities:
        out.md += [f"![{TITLES[role]}]({figure})", ""]
    for sweep in sweeps:
        page = f"appendix/{sweep.name}.md"
        out.pages[page] = appendix_page(ctx.analysis, sweep)
        out.md += [f"### {sweep.name} ({sweep.trials} trials per point, {sweep.detections})", "",
                   "Best method per quantity (smallest median |error|) and its Holm-adjusted p "
                   "against the runner-up. Every point's scoreboard and comparisons: "
                   f"[{page}]({page}).", "", best_summary(ctx.analysis, sweep), ""]
    return out


# The first page's answer (sections/answers.py).

def adjusted(c):
    return c.p_adjusted if c is not None and math.isfinite(c.p_adjusted) else math.inf


def answer_row(analysis, sweep, quantity):
    """One first-page row: (row cells, winner) of a sweep and quantity, or None."""
    scored = [(p.point, p.of(quantity)) for p in analysis.scores(sweep)]
    scored = [(p, s) for p, s in scored if s is not None and s.best]
    if not scored:
        return None
    order = {m: i for i, m in enumerate(analysis.methods_of(analysis.rows_of(sweep)))}
    counts = collections.Counter(s.best for _, s in scored)
    winner = min(counts, key=lambda m: (-counts[m], order.get(m, 0)))
    wins = [(p, s) for p, s in scored if s.best == winner]
    significant = [(p, s) for p, s in wins if s.contest is not None and s.contest.significant]
    point, score = max(wins, key=lambda ps: adjusted(ps[1].contest))
    c = score.contest
    closest = (f"{point.label}: {score.runner_up}, {effect_text(c, quantity.unit_text)}, "
               f"{p_text(c)}" if score.runner_up else f"{point.label}: alone")
    others = collections.Counter(s.best for _, s in scored if s.best != winner)
    elsewhere = ", ".join(f"{m} at {k}" for m, k in others.items()) or "–"
    name = (f"**{winner}**" if significant else
            f"none significantly ({winner} has the smallest median)")
    return [f"{sweep.name}", quantity.title, name, f"{len(wins)} of {len(scored)}",
            f"{len(significant)} of {len(wins)}", closest, elsewhere]


def versus_batch(ctx, sweep, quantity):
    """The adaptive estimator against the best batch method over a sweep: at each point the
    trials paired by seed, ln(|adaptive error| / |batch error|) pooled over the points (a ratio:
    the points' scales differ). The best batch method has the smallest median |error| at the
    most points (ties: its order). (adaptive, batch, Comparison) or None; not Holm-adjusted."""
    analysis, data = ctx.analysis, ctx.data
    methods = analysis.methods_of(analysis.rows_of(sweep))
    adaptive, batch = data.of_family(methods, "adaptive"), data.of_family(methods, "batch")
    if not adaptive or not batch:
        return None
    series_at = [analysis.series(analysis.point_rows(p), quantity)[0]
                 for p in analysis.points(sweep)]
    wins = collections.Counter()
    for series in series_at:
        medians = {m: float(series[m].median()) for m in batch if m in series}
        medians = {m: v for m, v in medians.items() if math.isfinite(v)}
        if medians:
            wins[min(medians, key=lambda m: (medians[m], batch.index(m)))] += 1
    if not wins:
        return None
    best = min(wins, key=lambda m: (-wins[m], batch.index(m)))
    a = adaptive[0]
    d = [stats.log_ratios(s[a], s[best]) for s in series_at if a in s and best in s]
    d = np.concatenate(d) if d else np.array([])
    return a, best, stats.compare(d)


@functools.lru_cache(maxsize=None)
def versus_rows(ctx, role):
    """{(sweep, quantity): (adaptive, batch, Comparison)} of a role's sweeps and headline
    quantities, Holm-adjusted as one family (once per report)."""
    out = {}
    for sweep in ctx.data.schema.sweeps_of(role):
        for q in ctx.data.schema.headline():
            if len(ctx.analysis.rows_of(sweep)):
                v = versus_batch(ctx, sweep, q)
                if v:
                    out[(sweep.name, q.name)] = v
    stats.holm([c for _, _, c in out.values()])
    return out


def verdict(ctx, role):
    """The first screen's line for a role's sweeps: the adaptive estimator against the best
    batch method in the bounded headline quantity (f·ku), per sweep; or None."""
    q = ctx.data.schema.bounded_headline()
    rows = versus_rows(ctx, role)
    parts = [f"{sweep}: {ratio_versus_text(a, b, c, error_words(q))}"
             for (sweep, name), (a, b, c) in rows.items() if q and name == q.name]
    return "; ".join(parts) if parts else None


def answer_figure(ctx, sweep_list, quantities, path):
    fig, axes = plots.figure(len(quantities), len(sweep_list), 4.2, 3.0)
    for r, q in enumerate(quantities):
        for c, sweep in enumerate(sweep_list):
            ax = axes[r][c]
            lines, bounds = quantity_lines(ctx.analysis, sweep, q)
            plots.band_lines(ax, lines, ctx.palette, bounds, q.target)
            plots.axis_scale(ax, [p.x for p in ctx.analysis.points(sweep)])
            ax.set_title(f"{q.label}: {sweep.name}", fontsize=8)
            ax.set_xlabel(x_label(sweep), fontsize=7)
            ax.set_ylabel(f"median |{q.label}| ({q.unit_text})", fontsize=7)
    legend = plots.legend_of(axes.flat)
    fig.legend(list(legend.values()), list(legend.keys()), loc="lower center",
               ncol=min(5, len(legend)), fontsize=7, frameon=False)
    fig.tight_layout(rect=(0, 0.1, 1, 1))
    plots.save(fig, path, dpi=85, tight=False)


def answer(ctx, role):
    """The first page's answer for the sweeps of a role: a table and a figure, or None."""
    schema = ctx.data.schema
    sweep_list = [s for s in schema.sweeps_of(role) if len(ctx.analysis.rows_of(s))]
    quantities = schema.headline()
    versus = versus_rows(ctx, role)
    body = [r + [ratio_versus_text(*versus[(s.name, q.name)], error_words(q))
                 if (s.name, q.name) in versus else "–"]
            for s in sweep_list for q in quantities
            for r in [answer_row(ctx.analysis, s, q)] if r]
    if not body:
        return None
    figure = f"answer_{role}.png"
    answer_figure(ctx, sweep_list, quantities, ctx.path(figure))
    head = ["sweep", "quantity", "winner", "best at (points)", f"significant ({SIGNIFICANT})",
            "closest win: point, runner-up, Δ of the runner-up [95% CI], p",
            "other best methods (points)",
            "adaptive against the best batch method (median ratio [95% CI], p Holm)"]
    note = ("The last column pools the sweep's points: at each, the trials paired by seed, the "
            "ratio of the two |errors|; its median over all pairs, the bootstrap interval of "
            "that median, the test on the log ratios, Holm over the table's rows.")
    return [markdown(body, head), "", note, "", f"![{role}]({figure})", ""]
