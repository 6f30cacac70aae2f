"""The corner-error study of `calibench corner-bias` (corner_bias.csv): per case (lens, border,
corner squares, tag size, tilt, blur) and stage, the systematic bias along the tag diagonals
(radial, > 0 outward), the RMS against the Cramér–Rao floor, failed tags and the time per tag.

Everything about the cases is read from the CSV: the viewing-angle series are the groups of
cases that differ only in their tilt; the fit that matches a case is the lens-aware fit where the
case has a lens, else the photometric fit (MATCHING_STAGES)."""
import numpy as np
import pandas as pd

from calibench_report import io, plots, stats
from calibench_report.sections import Section
from calibench_report.tables import effect_text, markdown, num, p_text, signed

# How the study names its stages (detect/corner_bias.h, CornerStageName).
STAGE_NAMES = {"raw": "AprilTag 3", "edge_fit": "edge fit", "saddle": "edge fit + saddle",
               "photometric": "photometric fit", "lens_aware": "lens-aware fit"}
# The saddle is the edge fit's step on corner squares: one method for the comparisons.
STAGE_METHOD = {"saddle": "edge_fit"}
# The study's bounds on the fit that matches a case (README, "Corner bias"): |radial bias| and
# RMS / CRLB.
BIAS_BOUND_PX = 0.005
RMS_OVER_CRLB_BOUND = 2.0
# A case's geometry (the columns that vary between cases).
CASE_AXES = ("lens", "black_border_bits", "corner_squares", "tag_px", "tilt_deg", "roll_deg",
             "blur_sigma_px", "centre_u_px", "centre_v_px")


def per_case(cb):
    """One row per (case, stage): the case's axes, mean radial and tangential bias over its
    corners and the stage's figures."""
    for col in ("crlb_px", "rms_px", "rms_over_crlb", "bias_radial_px", "bias_tangent_px",
                "view_rms_px", "noise_rms_px", "wall_per_tag_us"):
        if col in cb:
            cb[col] = pd.to_numeric(cb[col], errors="coerce")
    order = {s: i for i, s in enumerate(dict.fromkeys(cb.stage))}
    first = {c: (c, "first") for c in CASE_AXES + ("view_angle_deg", "rms_px", "crlb_px",
                                                   "rms_over_crlb", "detections", "failed",
                                                   "wall_per_tag_us", "status", "view_rms_px")}
    out = cb.groupby(["case", "stage"], sort=False).agg(
        radial=("bias_radial_px", "mean"), tangent=("bias_tangent_px", "mean"),
        **{k: v for k, v in first.items() if v[0] in cb}).reset_index()
    out["stage_order"] = out.stage.map(order)
    out["method"] = out.stage.map(lambda s: STAGE_METHOD.get(s, s))
    return out.sort_values(["case", "stage_order"])


def angle_series(cases):
    """The viewing-angle series: groups of cases equal in every axis but the tilt, with the most
    tilts (at least 3); {label: [case, ...]} labelled by the axes that differ between groups."""
    firsts = cases.drop_duplicates("case")
    keys = [a for a in CASE_AXES if a != "tilt_deg" and a in firsts]
    groups = {k: g for k, g in firsts.groupby(keys, sort=False, dropna=False)}
    longest = max((g.tilt_deg.nunique() for g in groups.values()), default=0)
    if longest < 3:
        return {}
    chosen = {k: g for k, g in groups.items() if g.tilt_deg.nunique() == longest}
    varying = [a for i, a in enumerate(keys) if len({k[i] for k in chosen}) > 1]
    return {", ".join(f"{a} {k[keys.index(a)]}" for a in varying) or "series": list(g.case)
            for k, g in chosen.items()}


# The fit that matches a case, most specific first: the lens-aware fit where a lens is given, else
# the photometric fit (the default refinement, corner squares included); the saddle is the edge
# fit's step, compared but not the default.
MATCHING_STAGES = ("lens_aware", "photometric")


def matched(cases):
    """Per case the row of the fit that matches it (MATCHING_STAGES; else its last stage)."""
    n = len(MATCHING_STAGES)
    last = cases.groupby("case", sort=False).cumcount(ascending=False) == 0
    rank = cases.stage.map({s: i for i, s in enumerate(MATCHING_STAGES)})
    rank = rank.fillna(last.map({True: n, False: n + 1}))
    return (cases.assign(_rank=rank).sort_values(["case", "_rank"], kind="stable")
            .groupby("case", sort=False).head(1).drop(columns="_rank"))


def figure(cases, series, path):
    stages = [s for s in dict.fromkeys(cases.stage) if s in STAGE_NAMES and s != "lens_aware"]
    stages = [s for s in stages if cases[cases.case.isin(
        [c for cs in series.values() for c in cs]) & (cases.stage == s)].size]
    fig, axes = plots.figure(1, len(stages) + 1, 4.6, 4.0)
    axes = axes[0]
    styles = ("o-", "s--", "^:", "v-.")
    for ax, stage in zip(axes[:-1], stages):
        for (label, members), style in zip(series.items(), styles):
            h = cases[cases.case.isin(members) & (cases.stage == stage)].sort_values(
                "view_angle_deg")
            ax.plot(h.view_angle_deg, h.radial, style, color="C0", label=f"radial ({label})")
            ax.plot(h.view_angle_deg, h.tangent, style, color="C1",
                    label=f"tangential ({label})")
            if "view_rms_px" in h:
                ax.plot(h.view_angle_deg, h.view_rms_px, style, color="C2", alpha=0.6,
                        label=f"view-to-view bias RMS ({label})")
        ax.axhline(0, color="k", lw=0.5)
        ax.set_title(f"{STAGE_NAMES.get(stage, stage)}: bias against viewing angle", fontsize=9)
        ax.set_xlabel("viewing angle (deg)")
        ax.set_ylabel("px")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=5)
    ax = axes[-1]
    finite = cases[np.isfinite(cases.rms_over_crlb)]
    for i, stage in enumerate(dict.fromkeys(cases.stage)):
        h = finite[finite.stage == stage]
        ax.scatter(h.case, h.rms_over_crlb, s=10, color=f"C{i}",
                   label=STAGE_NAMES.get(stage, stage))
    ax.axhline(RMS_OVER_CRLB_BOUND, color="k", lw=0.8, ls="--",
               label=f"{RMS_OVER_CRLB_BOUND:g} × CRLB")
    ax.set_yscale("log")
    ax.set_xlabel("case (appendix table)")
    ax.set_ylabel("corner RMS per axis / Cramér–Rao std")
    ax.set_title("every case: RMS against the floor", fontsize=9)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=6)
    plots.save(fig, path, dpi=100)


def case_table(cases):
    stage_columns = [s for s in ("raw", "edge_fit", "photometric", "lens_aware")
                     if (cases.method == s).any()]
    head = ["case", "lens", "grid", "tag px", "tilt / roll", "blur px"]
    for s in stage_columns:
        head += [f"{STAGE_NAMES[s]}: radial bias", "RMS / CRLB", "failed"]
    head += ["CRLB px", "µs per tag (" + ", ".join(STAGE_NAMES[s] for s in stage_columns) + ")"]
    body = []
    for case, g in cases.groupby("case", sort=True):
        first = g.iloc[0]
        squares = " + squares" if first.corner_squares else ""
        grid = f"{int(first.black_border_bits)}-bit{squares}"
        row = [str(case), first.lens, grid, num(first.tag_px),
               f"{num(first.tilt_deg)} / {num(first.roll_deg)}", num(first.blur_sigma_px)]
        us = []
        for s in stage_columns:
            h = g[g.method == s]
            if h.empty:
                row += ["", "", ""]
                continue
            r = h.iloc[0]
            row += [signed(r.radial), num(r.rms_over_crlb, 2),
                    f"{int(r.failed)}/{int(r.detections + r.failed)}"]
            us.append(num(r.wall_per_tag_us, 3))
        body.append(row + [num(first.crlb_px, 2), ", ".join(us)])
    return markdown(body, head)


def contest(cases):
    """Which stage has the most accurate corners (smallest RMS per axis). The candidates are the
    stages every case ran; the winner is the one with the smallest RMS in the most cases. Every
    other stage, those that ran on some cases only included, is compared with it on the cases
    both found the tag in (paired by case: Δ = RMS of the other - RMS of the winner), the
    comparisons Holm-adjusted as one family. Returns (winner, wins, cases, {stage: (cases it ran,
    Comparison)}) or None."""
    ran = cases.groupby("method", sort=False).case.nunique()
    everywhere = [m for m, n in ran.items() if n == cases.case.nunique()]
    table = cases[np.isfinite(cases.rms_px)].pivot_table(index="case", columns="method",
                                                         values="rms_px", aggfunc="first")
    candidates = [m for m in everywhere if m in table]
    if len(table.columns) < 2 or not candidates:
        return None
    best = table[candidates].idxmin(axis=1, skipna=True).dropna()
    wins = best.value_counts()
    winner = wins.index[0]
    comparisons = {m: (int(ran[m]), stats.compare(stats.paired_differences(table[m],
                                                                           table[winner])))
                   for m in table.columns if m != winner}
    stats.holm([c for _, c in comparisons.values()])
    return winner, int(wins.iloc[0]), int(best.size), comparisons


def cases_of(data):
    """The study's per-case table (per_case), or None when the directories hold no study."""
    if data.corner_bias is None or not len(data.corner_bias):
        return None
    return per_case(data.corner_bias.copy())


def section(ctx):
    data = ctx.data
    cases = cases_of(data)
    if cases is None:
        return None
    series = angle_series(cases)
    figure(cases, series, ctx.path("corner_bias.png"))
    best = matched(cases)
    meets = best[(best.radial.abs() <= BIAS_BOUND_PX) & (best.rms_over_crlb <= RMS_OVER_CRLB_BOUND)]
    unfound = best[~best.case.isin(meets.case) & ~(pd.to_numeric(best.detections) > 0)]
    page = "appendix/corner_bias.md"
    out = Section()
    source = io.display_path(data.corner_bias_path, ctx.out)
    out.md += ["## Corner bias of the rendered pipeline", "",
               f"`calibench corner-bias` ({source}): one tag36h11 tag per case, rendered, found "
               "and refined by every stage on the same frames: " +
               ", ".join(STAGE_NAMES.get(s, s) for s in dict.fromkeys(cases.stage)) + ". Views "
               "are shifted by random sub-pixel offsets, each with independent noise draws. Radial "
               "bias: the mean error along the tag's diagonal over the four corners, > 0 outward; "
               "RMS per axis over all errors, against the mean Cramér–Rao std of the photometric "
               "corners (lens-aware with a lens).", "",
               f"With the fit that matches the case (lens-aware with a lens, else photometric), "
               f"{len(meets)} of {len(best)} cases have |radial bias| ≤ {BIAS_BOUND_PX:g} px and "
               f"RMS ≤ {RMS_OVER_CRLB_BOUND:g} × CRLB; {len(unfound)} of the others have no tag "
               "found in any view. The left panels follow the viewing-angle "
               "series (cases equal in all but the tilt: " + "; ".join(series) + "). Every case: "
               f"[{page}]({page}).", "", "![corner bias](corner_bias.png)", ""]
    out.pages[page] = ["# Corner bias: every case", "", "[Back to the report](../report.md)", "",
                       case_table(cases), ""]
    return out


# The first page's answer (sections/answers.py).

def answer(ctx):
    """The first page's answer on corner detection: a lead, a table and a figure, or None."""
    cases = cases_of(ctx.data)
    result = contest(cases) if cases is not None else None
    if result is None:
        return None
    winner, wins, counted, comparisons = result
    names = STAGE_NAMES
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
