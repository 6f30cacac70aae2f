"""The first page: for each question the runs answer (noise, points, gain, the dynamic events,
the rig, detection) the winner, its effect size with its interval and its adjusted p, and one figure.
Each section answers its own question (its answer(ctx)); this page puts them in order.

A sweep question is answered per sweep (oracle, rendered) and per headline quantity (schema.json:
f·ku and the geodesic rotation error): the winner is the method with the smallest median |error|
at the most points; each of its wins is significant when its comparison with the point's
runner-up has a Holm-adjusted p below stats.SIGNIFICANCE (the family: every comparison of that
point, as in the appendix tables); its closest win, the one with the largest p, is shown with the
runner-up's effect. Where it wins nowhere significantly, the table says so."""
import math

from calibench_report import stats
from calibench_report.sections import Section, corner_bias, dynamic, gain, rig, sweeps
from calibench_report.tables import SIGNIFICANT, markdown, num

QUESTIONS = {
    "noise": "Pixel noise: which method is most accurate as the noise grows?",
    "points": "Feature points: which method is most accurate from few to many points?",
    "gain": "Adaptive gain: which gain makes the adaptive estimator most accurate?",
    "dynamic": "A calibration that changes: which method re-converges first?",
    "rig": "A camera rig: which method follows a change of its relative pose first, and closest?",
    "detection": "Detection: which corner refinement gives the most accurate corners?",
}


SHORT = {"noise": "Pixel noise", "points": "Feature points", "gain": "Adaptive gain",
         "dynamic": "A calibration that changes", "rig": "A camera rig"}


def verdicts(ctx):
    """The first screen: per question, where the adaptive estimator stands against the best
    batch method (the suite's question), with its effect, interval and Holm-adjusted p; or []."""
    lines = []
    for key, verdict in (("noise", lambda: sweeps.verdict(ctx, "noise")),
                         ("points", lambda: sweeps.verdict(ctx, "points")),
                         ("gain", lambda: gain.verdict(ctx)),
                         ("dynamic", lambda: dynamic.verdict(ctx)),
                         ("rig", lambda: rig.verdict(ctx))):
        text = verdict()
        if text:
            lines.append(f"- **{SHORT[key]}**: {text}.")
    if not lines:
        return []
    return ["## Verdicts: the adaptive estimator against batch calibration", "",
            "Static questions: the ratio of the two |errors| on the same trials (its median, the "
            "bootstrap 95% interval of that median, the paired test on the log ratios); changes: "
            "the difference of the re-convergence times, batch's minus adaptive's. Each against "
            "the best batch method of its runs; p Holm-adjusted within its question. The tables "
            "below name the winners.", ""] + lines + [""] + power_table(ctx)


def verdict_comparisons(ctx):
    """[(question, case, Comparison, family size)]: every comparison a verdict line reads, with
    the size of the family its p is Holm-adjusted in (each question's versus_rows)."""
    q = ctx.data.schema.bounded_headline()
    out = []
    for role in ("noise", "points"):
        rows = sweeps.versus_rows(ctx, role)
        out += [(SHORT[role], sweep, c, len(rows)) for (sweep, name), (_, _, c) in rows.items()
                if q and name == q.name]
    rows = [(row, quantity, v) for row, _, quantity, v in gain.versus_rows(ctx) if v]
    out += [(SHORT["gain"], row[0], v[1], len(rows)) for row, quantity, v in rows
            if q and quantity == q]
    rows = dynamic.versus_rows(ctx)
    out += [(SHORT["dynamic"], scenario, v[2], len(rows)) for scenario, (_, v) in rows.items()
            if v]
    rows = rig.versus_rows(ctx)
    out += [(SHORT["rig"], f"{scenario}, camera {camera}", c, len(rows))
            for (scenario, camera), (_, _, c) in rows.items()]
    return out


def power_table(ctx):
    """The trial counts against the effects measured: per verdict comparison its pairs, its
    standardized effect, and the pairs at which it would be significant with 80% power at the
    strictest Holm level of its family (stats.trials_for_power); or []."""
    body = []
    for question, case, c, family in verdict_comparisons(ctx):
        alpha = stats.SIGNIFICANCE / max(1, family)
        needed = stats.trials_for_power(c.standardized, alpha)
        dz = "∞" if math.isinf(c.standardized) else num(c.standardized, 2)
        if needed:
            pairs = str(needed)
        else:  # No effect measured, or one too small to test.
            pairs = "> 1000" if math.isfinite(c.standardized) and c.standardized != 0 else "–"
        body.append([question, case, str(c.n), dz, pairs])
    if not body:
        return []
    return ["The trials against the effects: per verdict the pairs it used, the mean paired "
            "difference over its standard deviation (Cohen's dz; the log ratio for a static "
            "question), and the pairs a paired t-test needs to find that effect with "
            f"{stats.POWER:.0%} power at the strictest Holm level of its question "
            f"({stats.SIGNIFICANCE:g} / the question's comparisons), never fewer than the "
            "Wilcoxon test's floor (2 / 2ⁿ below that level). \"–\": no effect measured (every "
            "pair equal, or fewer than 2); \"> 1000\": an effect too small to test.", "",
            markdown(body, ["question", "case", "pairs", "dz", "pairs for 80% power"]), ""]


def section(ctx):
    out = Section()
    out.md += verdicts(ctx)
    out.md += ["## The answers", "",
               "Each question below is answered from these runs alone. *Winner*: the smallest "
               "median |error| over the trials (summary.csv). *Significant*: its paired "
               f"comparison with the runner-up on the same trials has a {SIGNIFICANT} "
               "(Lilliefors, then a paired t-test or a Wilcoxon signed-rank test; Holm over the "
               "family named). Δ: the median paired difference, the runner-up's |error| minus "
               "the winner's, with its percentile bootstrap 95% interval.", ""]
    for key, answer in (("noise", lambda: sweeps.answer(ctx, "noise")),
                        ("points", lambda: sweeps.answer(ctx, "points")),
                        ("gain", lambda: gain.answer(ctx)),
                        ("dynamic", lambda: dynamic.answer(ctx)),
                        ("rig", lambda: rig.answer(ctx)),
                        ("detection", lambda: corner_bias.answer(ctx))):
        md = answer()
        out.md += [f"### {QUESTIONS[key]}", ""] + (md or ["Not in these runs.", ""])
    return out
