"""The first page: for each question the runs answer (noise, points, gain, the dynamic events,
detection) the winner, its effect size with its interval and its adjusted p, and one figure.

A sweep question is answered per sweep (oracle, rendered) and per headline quantity (schema.json:
f·ku and the geodesic rotation error): the winner is the method with the smallest median |error|
at the most points; each of its wins is significant when its comparison with the point's
runner-up has a Holm-adjusted p below stats.SIGNIFICANCE (the family: every comparison of that
point, as in the appendix tables); its closest win, the one with the largest p, is shown with the
runner-up's effect. Where it wins nowhere significantly, the table says so."""
import collections
import math
import os

import numpy as np

from calibench_report import plots, stats
from calibench_report.sections import Section, corner_bias, dynamic, gain, sweeps
from calibench_report.tables import effect_text, markdown, num, p_text

QUESTIONS = {
    "noise": "Pixel noise: which method is most accurate as the noise grows?",
    "points": "Feature points: which method is most accurate from few to many points?",
    "gain": "Adaptive gain: which gain makes the adaptive estimator most accurate?",
    "dynamic": "A calibration that changes: which method re-converges first?",
    "detection": "Detection: which corner refinement gives the most accurate corners?",
}
SIGNIFICANT = f"Holm-adjusted p < {stats.SIGNIFICANCE:g}"


def adjusted(c):
    return c.p_adjusted if c is not None and math.isfinite(c.p_adjusted) else math.inf


def sweep_rows(analysis, sweep, quantity):
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


def sweep_figure(ctx, sweep_list, quantities, path):
    fig, axes = plots.figure(len(quantities), len(sweep_list), 4.2, 3.0)
    for r, q in enumerate(quantities):
        for c, sweep in enumerate(sweep_list):
            ax = axes[r][c]
            lines, bounds = sweeps.quantity_lines(ctx.analysis, sweep, q)
            plots.band_lines(ax, lines, ctx.palette, bounds, q.target)
            plots.axis_scale(ax, [p.x for p in ctx.analysis.points(sweep)])
            ax.set_title(f"{q.label}: {sweep.name}", fontsize=8)
            ax.set_xlabel(sweeps.x_label(sweep), fontsize=7)
            ax.set_ylabel(f"median |{q.label}| ({q.unit_text})", fontsize=7)
    legend = plots.legend_of(axes.flat)
    fig.legend(list(legend.values()), list(legend.keys()), loc="lower center",
               ncol=min(5, len(legend)), fontsize=7, frameon=False)
    fig.tight_layout(rect=(0, 0.1, 1, 1))
    plots.save(fig, path, dpi=85, tight=False)


def sweep_question(ctx, role):
    schema = ctx.data.schema
    sweep_list = [s for s in schema.sweeps_of(role) if len(ctx.analysis.rows_of(s))]
    quantities = schema.headline()
    body = [r for s in sweep_list for q in quantities
            for r in [sweep_rows(ctx.analysis, s, q)] if r]
    if not body:
        return None
    figure = f"answer_{role}.png"
    sweep_figure(ctx, sweep_list, quantities, ctx.path(figure))
    head = ["sweep", "quantity", "winner", "best at (points)", f"significant ({SIGNIFICANT})",
            "closest win: point, runner-up, Δ of the runner-up [95% CI], p",
            "other best methods (points)"]
    return [markdown(body, head), "", f"![{role}]({figure})", ""]


def gain_rows(analysis, sweep, quantity):
    """(row, best point) of a gain sweep: the swept instance's best gain for the quantity
    (smallest median |error|, summary.csv), compared with every other gain on the same trials."""
    axis = gain.gain_axis(sweep)
    if axis is None:
        return None
    instance = axis[0]
    points = [p for p in analysis.points(sweep) if isinstance(p.x, float)]
    medians = {p: analysis.band(p.scenario, instance, quantity.summary_metric)[0] for p in points}
    ranked = sorted((m, p.x, p) for p, m in medians.items() if math.isfinite(m))
    if not ranked:
        return None
    best = ranked[0][2]

    def errors(p):
        rows = analysis.point_rows(p)
        h = rows[(rows.method == instance) & (rows.status == "ok")].set_index("seed")
        return h[quantity.compared].abs() if quantity.compared in h else None

    mine = errors(best)
    comparisons = {p: stats.compare(stats.paired_differences(errors(p), mine))
                   for _, _, p in ranked[1:] if errors(p) is not None}
    stats.holm(list(comparisons.values()))
    runner = ranked[1][2] if len(ranked) > 1 else None
    c = comparisons.get(runner)
    rival = min(((analysis.band(best.scenario, m, quantity.summary_metric)[0], m)
                 for m in analysis.methods_of(analysis.point_rows(best)) if m != instance),
                default=(math.nan, None))
    converge = analysis.stat(best.scenario, instance, gain.CONVERGE, "median")
    name = f"**{axis[1]} = {best.x:g}**" if c is not None and c.significant else \
        f"none significantly ({axis[1]} = {best.x:g} has the smallest median)"
    ratio = (f" ({ranked[0][0] / rival[0]:.2g}× that of {rival[1]}, the best other method)"
             if rival[1] and math.isfinite(rival[0]) and rival[0] > 0 else "")
    return [sweep.name, instance, quantity.title, name,
            f"{num(ranked[0][0])} {quantity.unit_text}{ratio}", f"{num(converge)} s",
            f"{axis[1]} = {runner.x:g}: {effect_text(c, quantity.unit_text)}, {p_text(c)}"
            if runner else "–"]


def gain_figure(ctx, gains, quantities, path):
    fig, axes = plots.figure(1, len(quantities) + 1, 4.4, 3.4)
    axes = axes[0]
    for k, (name, (instance, option, pts, _)) in enumerate(gains.items()):
        sweep = ctx.data.schema.sweep(name)
        points = [p for p in ctx.analysis.points(sweep) if isinstance(p.x, float)]
        for ax, q in zip(axes, quantities):
            b = [ctx.analysis.band(p.scenario, instance, q.summary_metric) for p in points]
            x = [p.x for p in points]
            ax.plot(x, [v[0] for v in b], "o-", ms=3, color=f"C{k}", label=f"{instance}, {name}")
            ax.fill_between(x, [v[1] for v in b], [v[2] for v in b], color=f"C{k}", alpha=0.12)
            others = [min((ctx.analysis.band(p.scenario, m, q.summary_metric)[0]
                           for m in ctx.analysis.methods_of(ctx.analysis.point_rows(p))
                           if m != instance), default=math.nan) for p in points]
            ax.plot(x, others, "--", color=f"C{k}", lw=1,
                    label=f"the best other method's median, {name}")
            ax.set_title(f"median |{q.label}| ({q.unit_text}) against {option}", fontsize=8)
        axes[-1].plot([g.value for g in pts], [g.converge_s for g in pts], "o-", ms=3,
                      color=f"C{k}", label=name)
        axes[-1].set_title("median convergence time (s)", fontsize=8)
    for ax in axes:
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.grid(True, which="both", alpha=0.3)
        ax.tick_params(labelsize=6)
        if ax.get_legend_handles_labels()[0]:
            ax.legend(fontsize=6)
    plots.save(fig, path, dpi=85)


def gain_question(ctx):
    gains = gain.all_gains(ctx.analysis)
    quantities = ctx.data.schema.headline()
    body = [r for name in gains for q in quantities
            for r in [gain_rows(ctx.analysis, ctx.data.schema.sweep(name), q)] if r]
    if not body:
        return None
    gain_figure(ctx, gains, quantities, ctx.path("answer_gain.png"))
    head = ["sweep", "instance", "quantity", "best gain", "its median |error|",
            "its median convergence", "next gain: Δ [95% CI], p (Holm over the gains)"]
    return [markdown(body, head), "", "![gain](answer_gain.png)", ""]


def dynamic_question(ctx):
    rows = dynamic.answer_rows(ctx)
    if not rows:
        return None
    head = ["scenario", "first change", "first to re-converge", "its median (trials)",
            "runner-up", "Δ of the runner-up [95% CI]", "p (Holm over the methods)"]
    md = [markdown([r[:-1] for r in rows], head), ""]
    trials = ctx.data.events.groupby("scenario").trial.nunique()
    if (trials < stats.MIN_PAIRS).all():
        span = (f"{trials.min()}" if trials.min() == trials.max()
                else f"{trials.min()}–{trials.max()}")
        md += [f"No comparison is testable: these scenarios have {span} trials, a paired test "
               f"needs {stats.MIN_PAIRS}; the medians and their differences are indicative.", ""]
    if os.path.exists(ctx.path("tracking_pareto.png")):
        md += ["![dynamic](tracking_pareto.png)", ""]
    return md


def detection_question(ctx):
    data = ctx.data
    if data.corner_bias is None or not len(data.corner_bias):
        return None
    cases = corner_bias.per_case(data.corner_bias.copy())
    result = corner_bias.contest(cases)
    if result is None:
        return None
    winner, wins, counted, comparisons = result
    names = corner_bias.STAGE_NAMES
    body = [[names.get(m, m), f"{n} cases", effect_text(c, "px"), p_text(c),
             "yes" if c.significant else "no"]
            for m, (n, c) in sorted(comparisons.items(), key=lambda kv: kv[1][1].effect)]
    head = ["stage", "ran on", f"Δ RMS against {names.get(winner, winner)} [95% CI]",
            "p (Holm over the stages)", "significant"]
    lead = (f"**{names.get(winner, winner)}** has the smallest corner RMS in {wins} of {counted} "
            "cases (among the stages every case ran); against each other stage, on the cases both "
            "found the tag in (Δ > 0: the other stage's corners are worse):")
    better = [names.get(m, m) for m, (n, c) in comparisons.items()
              if c.significant and c.effect < 0]
    if better:
        lead += (f" {', '.join(better)}, which ran on some cases only, "
                 f"{'is' if len(better) == 1 else 'are'} better still on the cases "
                 f"{'it' if len(better) == 1 else 'they'} ran.")
    fig, axes = plots.figure(1, 1, 7.0, 3.6)
    ax = axes[0][0]
    stages = list(dict.fromkeys(cases.method))
    values = [cases[(cases.method == s) & np.isfinite(cases.rms_px)].rms_px for s in stages]
    ax.boxplot(values, labels=[names.get(s, s) for s in stages], showfliers=True)
    ax.set_yscale("log")
    ax.set_ylabel("corner RMS per axis (px), per case")
    ax.grid(True, which="both", alpha=0.3)
    ax.tick_params(labelsize=7)
    plots.save(fig, ctx.path("answer_detection.png"), dpi=90)
    return [lead, "", markdown(body, head), "", "![detection](answer_detection.png)", ""]


def section(ctx):
    out = Section()
    out.md += ["## The answers", "",
               "Each question below is answered from these runs alone. *Winner*: the smallest "
               "median |error| over the trials (summary.csv). *Significant*: its paired "
               f"comparison with the runner-up on the same trials has a {SIGNIFICANT} "
               "(Lilliefors, then a paired t-test or a Wilcoxon signed-rank test; Holm over the "
               "family named). Δ: the median paired difference, the runner-up's |error| minus "
               "the winner's, with its percentile bootstrap 95% interval.", ""]
    for key, answer in (("noise", lambda: sweep_question(ctx, "noise")),
                        ("points", lambda: sweep_question(ctx, "points")),
                        ("gain", lambda: gain_question(ctx)),
                        ("dynamic", lambda: dynamic_question(ctx)),
                        ("detection", lambda: detection_question(ctx))):
        md = answer()
        out.md += [f"### {QUESTIONS[key]}", ""] + (md or ["Not in these runs.", ""])
    return out
