"""‖θ̃‖(t) of trial 0 at every point of each sweep that recorded it (curves.csv)."""
import math

from calibench_report import plots
from calibench_report.sections import Section


def section(ctx):
    curves = ctx.data.curves
    if not len(curves):
        return None
    sweeps = [s for s in ctx.data.schema.sweeps if s.swept]
    sweep_of = dict(zip(ctx.data.runs.scenario, ctx.data.runs.sweep))
    curves = curves.assign(sweep=curves.scenario.map(sweep_of))
    shown = [s for s in sweeps if (curves.sweep == s.name).any()]
    if not shown:
        return None
    cols = min(3, len(shown))
    nrows = math.ceil(len(shown) / cols)
    fig, axes = plots.figure(nrows, cols, 5, 3.6)
    points = {s.name: {p.scenario: p.label for p in ctx.analysis.points(s)} for s in shown}
    for ax, sweep in zip(axes.flat, shown):
        sub = curves[(curves.sweep == sweep.name) & (curves.trial == 0)]
        several = sub.method.nunique() > 1
        for (scenario, method), g in sub.groupby(["scenario", "method"], sort=False):
            label = points[sweep.name].get(scenario, scenario).split("=")[-1]
            ax.plot(g.t_s, g.theta_err_norm, label=f"{method} {label}" if several else label)
        ax.set_yscale("log")
        ax.set_xlabel("t (s)")
        ax.set_ylabel("‖θ̃‖")
        ax.set_title(f"{sweep.name} (trial 0)", fontsize=9)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=6)
    for ax in list(axes.flat)[len(shown):]:
        ax.axis("off")
    plots.save(fig, ctx.path("convergence.png"), dpi=100)
    out = Section()
    out.md += ["## Adaptive convergence", "", "‖θ̃‖(t) of trial 0 at every sweep point.", "",
               "![convergence](convergence.png)", ""]
    return out
