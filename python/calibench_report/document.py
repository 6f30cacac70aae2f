"""The report's pages: report.md opens with the answers, then how to read it, the sections, and
links to the appendix pages (every point's tables)."""
import os

from calibench_report import io, stats
from calibench_report.sections import (Context, answers, convergence, corner_bias, dynamic, gain,
                                       oracle_rendered, projection, rig, sweeps, uncertainty)


def header(ctx):
    data = ctx.data
    shown = [io.display_path(d, ctx.out) for d in data.dirs]
    tables = [io.display_path(os.path.join(d, "table.md"), ctx.out) for d in data.dirs
              if os.path.exists(os.path.join(d, "table.md"))
              and os.path.getsize(os.path.join(d, "table.md")) > 0]
    md = ["# calibench report", "",
          f"Run directories (relative to this report): {', '.join(shown)}. "
          f"{data.runs.scenario.nunique() if len(data.runs) else 0} scenarios, "
          f"{len(data.runs)} rows, {len(data.methods())} method instances.", ""]
    if tables:
        md += ["The tables of the scenarios that are not swept (the thesis reproduction's among "
               "them): " + ", ".join(f"[{t}]({t})" for t in tables) + ".", ""]
    return md


def definitions(ctx):
    schema = ctx.data.schema
    quantities = ", ".join(q.title for q in schema.ranked())
    targets = " and ".join(q.label for q in schema.targeted())
    target = schema.targeted()[0].target if schema.targeted() else None
    return [
        "## How to read this report", "",
        f"- **Quantities** (schema.json of each run directory): {quantities}. Errors are estimate "
        "minus truth; a method whose error of a quantity is exactly 0 in every trial does not "
        "estimate it (e.g. φ without skew) and is left out of it; the reprojection RMS is a fit, "
        "not an error against the truth.",
        "- **Median and 95% interval**: of |error| over the Monte Carlo trials (the 2.5th and "
        "97.5th percentiles: the percentile interval of Algers 2018, *Stereo Camera Calibration "
        "Accuracy in Real-time Car Angles Estimation*, Umeå University, §3.6), as summary.csv "
        "holds them; cells "
        "*median [p2.5, p97.5]*, the best method's median in bold. Plots: the same medians and "
        "bands, log y; dashed: the Cramér–Rao standard deviation of a method's parametrisation "
        "where runs.csv has one.",
        "- **RMSE/CRLB**: summary.csv's rmse_over_crlb (≈ 1: efficient).",
        (f"- **{target:g}° target** (Algers 2018, §1.2: {targets} accurate to {target:g}°): "
         "holds (✓) when "
         f"the 97.5th percentile of |error| is ≤ {target:g}° for each; the cell gives the "
         "percentiles." if target else "- **Target**: none declared."),
        "- **Best method** of a quantity at a point: the smallest median |error|.",
        "- **Paired comparison** with the best method on the same trials (same seed: same "
        "frames, same noise; trials without a finite value in both dropped): Δ = |error of "
        "method| − |error of best|. Lilliefors test of normality of Δ at the 5% level; not "
        "rejected: paired t-test, rejected: Wilcoxon signed-rank test. Effect size: median Δ "
        f"with a percentile bootstrap 95% interval (scipy.stats.bootstrap, "
        f"{stats.BOOTSTRAP_RESAMPLES} resamples, seed {stats.BOOTSTRAP_SEED}). **The p-values are "
        "Holm–Bonferroni adjusted** over the comparisons of the point's table. Not testable: "
        f"fewer than {stats.MIN_PAIRS} paired trials; n/a: identical series (Δ = 0) or the same "
        "Δ in every trial (the trials repeat one another).",
        "- **Data used**: ok trials per method (failed ones in brackets, from summary.csv) and "
        "the median frames and observations its estimate used (runs.csv n_frames_used, "
        "n_obs_used).",
        "- A method whose values of a quantity equal an earlier method's in every row is shown "
        "as \"= that method\" and left out of that quantity's tests and plots.", ""]


def build(data, out):
    """{page (relative to out): Markdown text}; the figures are written into `out`."""
    ctx = Context(data, out)
    parts = [sweeps.section(ctx, role) for role in sweeps.ROLES]
    parts += [gain.section(ctx), uncertainty.section(ctx), projection.section(ctx),
              oracle_rendered.section(ctx),
              convergence.section(ctx), corner_bias.section(ctx), dynamic.section(ctx),
              rig.section(ctx)]
    parts = [p for p in parts if p is not None]
    first = answers.section(ctx)  # After the sections: it shows some of their figures.
    md = header(ctx) + first.md + definitions(ctx)
    pages = {}
    for part in parts:
        md += part.md
        pages.update(part.pages)
    if pages:
        md += ["## Appendix", "", "Every point's tables, one page each:", ""]
        md += [f"- [{name}]({name})" for name in pages] + [""]
    return {"report.md": "\n".join(md) + "\n",
            **{name: "\n".join(lines) + "\n" for name, lines in pages.items()}}
