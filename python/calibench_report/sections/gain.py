"""The gain trade-off: the swept instance of a gain sweep (role gain, axis
methods.<instance>.<option>) against its gain: RMSE and RMSE/CRLB, the angles' RMSE, convergence
time and share converged, all from summary.csv."""
import dataclasses
import functools
import math

from calibench_report import plots, stats
from calibench_report.sections import Section
from calibench_report.tables import (effect_text, error_words, markdown, num, p_text,
                                     ratio_versus_text)

CONVERGE = "converge_time_s"


def gain_axis(sweep):
    """(instance, option) of a gain sweep's axis methods.<instance>.<option>, or None."""
    if len(sweep.axes) != 1 or not sweep.axes[0].startswith("methods."):
        return None
    instance, _, option = sweep.axes[0][len("methods."):].rpartition(".")
    return (instance, option) if instance else None


@dataclasses.dataclass
class GainPoint:
    value: float
    scenario: str
    trials: int
    rmse: dict  # Quantity -> RMSE of the instance.
    crlb: float
    crlb_of: str  # The method whose bound it is ("" if none).
    relation: str  # own | same data | other data | data not recorded
    converged: float  # Share of the ok trials with a finite convergence time.
    converge_s: float  # Their median.


def bound_of(analysis, point, instance, quantity):
    """(median CRLB, whose, relation): the instance's own bound if finite, else that of the first
    method that used the same frames and observations (where recorded), else of the first method
    with one (its views may differ)."""
    rows = analysis.point_rows(point)
    mine = analysis.data_used(rows, instance)
    others = [m for m in analysis.methods_of(rows) if m != instance]
    same = [m for m in others if None not in mine and analysis.data_used(rows, m) == mine]
    for m in [instance] + same + [m for m in others if m not in same]:
        b = analysis.stat(point.scenario, m, quantity.summary_metric, "crlb")
        if math.isfinite(b):
            relation = ("own" if m == instance else "same data" if m in same
                        else "other data" if None not in mine else "data not recorded")
            return b, m, relation
    return math.nan, "", ""


def gain_points(analysis, sweep):
    axis = gain_axis(sweep)
    if axis is None:
        return None
    instance = axis[0]
    schema = analysis.data.schema
    fku = schema.bounded_headline()
    quantities = [q for q in [fku] + schema.targeted() if q is not None]
    out = []
    for p in analysis.points(sweep):
        if not isinstance(p.x, float):
            continue
        n_ok, _ = analysis.trials(p.scenario, instance)
        used = analysis.stat(p.scenario, instance, CONVERGE, "n_used")
        crlb, whose, relation = (bound_of(analysis, p, instance, fku) if fku
                                 else (math.nan, "", ""))
        out.append(GainPoint(
            value=p.x, scenario=p.scenario, trials=n_ok,
            rmse={q: analysis.stat(p.scenario, instance, q.summary_metric, "rmse")
                  for q in quantities},
            crlb=crlb, crlb_of=whose, relation=relation,
            converged=used / n_ok if n_ok and math.isfinite(used) else math.nan,
            converge_s=analysis.stat(p.scenario, instance, CONVERGE, "median")))
    return instance, axis[1], sorted(out, key=lambda g: g.value), fku


def figure(gains, schema, path):
    fig, axes = plots.figure(1, 4, 4.7, 4.0, sharex=True)
    axes = axes[0]
    share = axes[3].twinx()
    targeted = schema.targeted()
    for k, (sweep, (instance, option, pts, fku)) in enumerate(gains.items()):
        x = [g.value for g in pts]
        style = dict(color=f"C{k}", marker="o", ms=4)
        if fku:
            axes[0].plot(x, [g.rmse[fku] for g in pts], label=f"RMSE, {sweep}", **style)
            whose = next((g.crlb_of for g in pts if g.crlb_of), "")
            if whose:
                axes[0].plot(x, [g.crlb for g in pts], ls="--", color=f"C{k}",
                             label=f"CRLB ({whose}'s rows), {sweep}")
                axes[1].plot(x, [g.rmse[fku] / g.crlb for g in pts], label=sweep, **style)
        for q, ls in zip(targeted, ("-", ":", "-.")):
            axes[2].plot(x, [g.rmse.get(q, math.nan) for g in pts], ls=ls,
                         label=f"{q.label}, {sweep}", **style)
        axes[3].plot(x, [g.converge_s for g in pts], label=f"median, {sweep}", **style)
        share.plot(x, [100 * g.converged for g in pts], ls="--", color=f"C{k}",
                   label=f"% converged, {sweep}")
    axes[1].axhline(1, color="k", lw=0.8)
    if targeted:
        axes[2].axhline(targeted[0].target, label=f"{targeted[0].target:g}° target",
                        **plots.TARGET_STYLE)
    if not any(math.isfinite(g.converge_s) for v in gains.values() for g in v[2]):
        axes[3].text(0.5, 0.6, "no trial converged", ha="center", transform=axes[3].transAxes,
                     fontsize=8)
    share.set_ylim(-5, 105)
    share.set_ylabel("trials converged (%)", fontsize=8)
    label = next(iter(gains.values()))[1]
    titles = ["(a) RMSE of f·ku (px) and its CRLB", "(a) RMSE / CRLB of f·ku",
              "(a) RMSE of the target angles (°)", "(b) convergence time (s), % converged"]
    for ax, title in zip(axes, titles):
        ax.set_xscale("log")
        if ax is not axes[3]:
            ax.set_yscale("log")
        ax.set_title(title, fontsize=9)
        ax.set_xlabel(label)
        ax.grid(True, which="both", alpha=0.3)
        if ax.get_legend_handles_labels()[0]:
            ax.legend(fontsize=6, loc="upper left")
    share.legend(fontsize=6, loc="upper right")
    plots.save(fig, path)


RELATION_TEXT = {
    "same data": "it used the same frames and observations as {instance} (median n_frames_used "
                 "and n_obs_used)",
    "other data": "no method with {instance}'s frames and observations has one, so its data differ",
    "data not recorded": "the data each method used is not recorded, so its views may differ",
}


def crlb_sources(gains):
    out = []
    for sweep, (instance, _, pts, fku) in gains.items():
        for whose, relation in dict.fromkeys((g.crlb_of, g.relation) for g in pts):
            if not whose:
                out.append(f"{sweep}: no method has a finite CRLB of {fku.label if fku else 'it'} "
                           "(RMSE alone).")
            elif whose == instance:
                out.append(f"{sweep}: the bound of {instance}'s own rows.")
            else:
                why = RELATION_TEXT[relation].format(instance=instance)
                out.append(f"{sweep}: {instance}'s rows have no CRLB; the bound is {whose}'s, in "
                           f"its parametrisation: {why}.")
    return out


def table(gains, schema):
    targeted = schema.targeted()
    head = (["sweep", "instance", "gain", "trials", "RMSE f·ku (px)", "CRLB f·ku (px), from",
             "RMSE/CRLB"] + [f"RMSE {q.label} (°)" for q in targeted]
            + ["median converge time (s)", "converged"])
    body = []
    for sweep, (instance, option, pts, fku) in gains.items():
        for g in pts:
            rmse = g.rmse.get(fku, math.nan) if fku else math.nan
            body.append([sweep, instance, f"{option} = {g.value:g}", str(g.trials), num(rmse),
                         f"{num(g.crlb)}, {g.crlb_of or 'none'}", num(rmse / g.crlb)]
                        + [num(g.rmse.get(q, math.nan)) for q in targeted]
                        + [num(g.converge_s),
                           f"{100 * g.converged:.0f}%" if math.isfinite(g.converged) else "–"])
    return markdown(body, head)


def all_gains(analysis):
    gains = {}
    for sweep in analysis.data.schema.sweeps_of("gain"):
        result = gain_points(analysis, sweep)
        if result and result[2]:
            gains[sweep.name] = result
    return gains


def section(ctx):
    gains = all_gains(ctx.analysis)
    if not gains:
        return None
    figure(gains, ctx.data.schema, ctx.path("gain_tradeoff.png"))
    out = Section()
    out.md += ["## Gain trade-off", "",
               "The swept instance (the axis methods.<instance>.<option>) per gain value, from "
               "summary.csv: the RMSE over the trials of its f·ku error and of its target angles' "
               "errors (no CRLB of the angles: RMSE alone), the Cramér–Rao bound of f·ku and "
               "RMSE/CRLB; converge_time_s: the time after which ‖θ̃‖ stays below the instance's "
               "convergence tolerance, its median over the converged trials and the share of "
               "trials converged. CRLB used:", ""]
    out.md += [f"- {s}" for s in crlb_sources(gains)]
    out.md += ["", "![gain trade-off](gain_tradeoff.png)", "", table(gains, ctx.data.schema), ""]
    for note in ctx.data.notes:
        out.md += ["Cost of a method-only sweep: " + note, ""]
    return out


# The first page's answer (sections/answers.py).

def answer_row(analysis, sweep, quantity):
    """(row, best point, instance) of a gain sweep: the swept instance's best gain for the
    quantity (smallest median |error|, summary.csv), compared with every other gain on the same
    trials."""
    axis = gain_axis(sweep)
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
    converge = analysis.stat(best.scenario, instance, CONVERGE, "median")
    name = f"**{axis[1]} = {best.x:g}**" if c is not None and c.significant else \
        f"none significantly ({axis[1]} = {best.x:g} has the smallest median)"
    ratio = (f" ({ranked[0][0] / rival[0]:.2g}× that of {rival[1]}, the best other method)"
             if rival[1] and math.isfinite(rival[0]) and rival[0] > 0 else "")
    row = [sweep.name, instance, quantity.title, name,
           f"{num(ranked[0][0])} {quantity.unit_text}{ratio}", f"{num(converge)} s",
           f"{axis[1]} = {runner.x:g}: {effect_text(c, quantity.unit_text)}, {p_text(c)}"
           if runner else "–"]
    return row, best, instance


def versus_batch(ctx, point, instance, quantity):
    """The adaptive instance at `point` (its best gain) against the best batch method there
    (smallest median |error|): ln(|adaptive error| / |batch error|) paired by seed.
    (batch, Comparison) or None; not Holm-adjusted."""
    analysis = ctx.analysis
    series, _ = analysis.series(analysis.point_rows(point), quantity)
    batch = [m for m in ctx.data.of_family(series, "batch")
             if math.isfinite(float(series[m].median()))]
    if instance not in series or not batch:
        return None
    best = min(batch, key=lambda m: (float(series[m].median()), batch.index(m)))
    return best, stats.compare(stats.log_ratios(series[instance], series[best]))


@functools.lru_cache(maxsize=None)
def versus_rows(ctx):
    """[(row, gain text, quantity, (batch, Comparison) or None)] of the gain sweeps, the
    comparisons Holm-adjusted as one family (once per report)."""
    gains = all_gains(ctx.analysis)
    out = []
    for name in gains:
        sweep = ctx.data.schema.sweep(name)
        axis = gain_axis(sweep)
        for q in ctx.data.schema.headline():
            r = answer_row(ctx.analysis, sweep, q)
            if r:
                row, best, instance = r
                out.append((row, f"{instance} at {axis[1]} = {best.x:g}", q,
                            versus_batch(ctx, best, instance, q)))
    stats.holm([v[1] for _, _, _, v in out if v])
    return out


def verdict(ctx):
    """The first screen's line: the adaptive estimator at its best gain against the best batch
    method, in the bounded headline quantity (f·ku), per gain sweep; or None."""
    q = ctx.data.schema.bounded_headline()
    parts = [f"{row[0]}: {ratio_versus_text(who, v[0], v[1], error_words(q))}"
             for row, who, quantity, v in versus_rows(ctx) if v and q and quantity == q]
    return "; ".join(parts) if parts else None


def answer_figure(ctx, gains, quantities, path):
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


def answer(ctx):
    """The first page's answer on the gain sweeps: a table and a figure, or None."""
    gains = all_gains(ctx.analysis)
    quantities = ctx.data.schema.headline()
    body = [row + [ratio_versus_text(who, v[0], v[1], error_words(q)) if v else "–"]
            for row, who, q, v in versus_rows(ctx)]
    if not body:
        return None
    answer_figure(ctx, gains, quantities, ctx.path("answer_gain.png"))
    head = ["sweep", "instance", "quantity", "best gain", "its median |error|",
            "its median convergence", "next gain: Δ [95% CI], p (Holm over the gains)",
            "at its best gain against the best batch method (median ratio [95% CI], p Holm)"]
    return [markdown(body, head), "", "![gain](answer_gain.png)", ""]
