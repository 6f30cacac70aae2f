"""Oracle against rendered detections: the noise sweeps (role noise) on one axis, the error
against the corner error the estimators actually saw: for oracle detections the swept pixel sigma
(noise.pixel_sigma_px) times sqrt(2) (Euclidean), for rendered ones the measured corner RMS
(summary.csv corner_rms_px); and each rendered point against the oracle at the same corner RMS."""
import math

import numpy as np

from calibench_report import plots
from calibench_report.sections import Section
from calibench_report.tables import markdown, num

PIXEL_SIGMA_AXIS = "noise.pixel_sigma_px"  # The scenario field of the oracle's pixel noise.
CORNER_RMS = "corner_rms_px"


def curves(analysis, sweep, quantity):
    """{method: [(corner RMS, median |error|)]} of a noise sweep, sorted by corner RMS."""
    out = {}
    for score in analysis.scores(sweep):
        p = score.point
        s = score.of(quantity)
        if s is None:
            continue
        for m, b in s.bands.items():
            if sweep.detections == "oracle":
                if sweep.axes != (PIXEL_SIGMA_AXIS,) or not isinstance(p.x, float):
                    return {}
                x = p.x * math.sqrt(2)
            else:
                x = analysis.stat(p.scenario, m, CORNER_RMS, "median")
            if math.isfinite(x) and math.isfinite(b[0]):
                out.setdefault(m, []).append((x, b[0]))
    return {m: sorted(v) for m, v in out.items()}


def figure(ctx, lines, quantity, path):
    fig, axes = plots.figure(1, 1, 6.5, 4.2)
    ax = axes[0][0]
    for (sweep, detections), by_method in lines.items():
        style = "o-" if detections == "oracle" else "s--"
        for m, pts in by_method.items():
            ax.plot([p[0] for p in pts], [p[1] for p in pts], style, color=ctx.palette[m],
                    label=f"{m} ({detections})")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("corner error, RMS (px): oracle σ·√2, rendered measured")
    ax.set_ylabel(f"median |{quantity.label} error| ({quantity.unit_text})")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=6, ncol=2)
    plots.save(fig, path, dpi=110)


def matched_table(analysis, oracle, rendered, quantity):
    """Per rendered point and method: the median |error| against the oracle's at the same
    Euclidean corner RMS (log-log interpolation in the oracle sweep's medians) and their ratio."""
    curve = curves(analysis, oracle, quantity)
    body = []
    for score in analysis.scores(rendered):
        s = score.of(quantity)
        if s is None:
            continue
        for m, b in s.bands.items():
            rms = analysis.stat(score.point.scenario, m, CORNER_RMS, "median")
            pts = curve.get(m, [])
            if len(pts) < 2 or not math.isfinite(rms) or not pts[0][0] <= rms <= pts[-1][0]:
                continue
            x = np.log([p[0] for p in pts])
            y = np.log([max(p[1], 1e-12) for p in pts])
            at = float(np.exp(np.interp(math.log(rms), x, y)))
            body.append([score.point.label, num(rms), m, num(b[0]), num(at),
                         num(b[0] / at) if at > 0 else "–"])
    head = ["rendered point", "corner RMS (px)", "method",
            f"rendered median |{quantity.label} err|", "oracle at that RMS", "ratio"]
    return markdown(body, head) if body else ""


def section(ctx):
    analysis = ctx.analysis
    quantity = analysis.data.schema.bounded_headline()
    sweeps = [s for s in analysis.data.schema.sweeps_of("noise") if len(analysis.rows_of(s))]
    oracle = [s for s in sweeps if s.detections == "oracle"]
    rendered = [s for s in sweeps if s.detections == "rendered"]
    if quantity is None or not oracle or not rendered:
        return None
    lines = {(s.name, s.detections): curves(analysis, s, quantity) for s in oracle + rendered}
    lines = {k: v for k, v in lines.items() if v}
    if not lines:
        return None
    figure(ctx, lines, quantity, ctx.path("oracle_vs_rendered.png"))
    out = Section()
    out.md += ["## Oracle against rendered detections", "",
               "The noise sweeps on one axis: the error against the corner error the estimators "
               "actually saw.", "", "![oracle vs rendered](oracle_vs_rendered.png)", ""]
    table = matched_table(analysis, oracle[0], rendered[0], quantity)
    if table:
        out.md += ["### Rendered against oracle at equal corner RMS", "",
                   f"Each rendered noise point's median |{quantity.label} error| against the "
                   "oracle noise sweep's at the same Euclidean corner RMS (oracle σ·√2; log-log "
                   "interpolation between its points), method by method.", "", table, ""]
    return out
