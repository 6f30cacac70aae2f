"""Camera rigs: the scenarios with a `rig:` (rig.csv of bench/run/run_row.h: per trial, method and
camera c >= 1 the relative pose cam_c_from_cam_0 that the method's estimates of camera 0 and of
camera c give, against the truth; camera/rig.h has the conventions).
  * a table per scenario and camera: per method the medians over the trials of the relative
    rotation's geodesic error at the end of the run, |baseline error|, the RMS vertical disparity
    of a plane 10 m ahead rectified with the estimated rig, |depth error| at 30 m, and for a
    tracking scenario the re-convergence of the relative rotation after the last change that
    moves the pair (censored at the segment's length when it never re-converges) and its steady
    error;
  * who re-converges first, compared with every other method paired by trial (Δ = other -
    winner), Holm-adjusted as one family, as the dynamic section does for one camera.
Methods are named by their instances; none is known by name."""
import functools
import math

import pandas as pd

from calibench_report import stats
from calibench_report.sections import Section
from calibench_report.tables import effect_text, markdown, num, p_text, time_versus_text


def median(values):
    v = pd.to_numeric(pd.Series(values), errors="coerce")
    v = v[v.notna() & (v.abs() != math.inf)]
    return float(v.median()) if len(v) else math.nan


def run_end(data, scenario):
    """The last report time of the scenario's tracks (≈ its duration), or NaN."""
    t = data.tracks
    if not len(t) or "scenario" not in t:
        return math.nan
    t = t[t.scenario == scenario]
    return float(t.t_s.max()) if len(t) else math.nan


def reconvergence(rig, end_s):
    """Per trial (indexed by trial) the relative rotation's re-convergence, a trial that never
    re-converges censored at its segment's length."""
    x = rig.set_index("trial")
    censor = (end_s - x.segment_from_s) if math.isfinite(end_s) else math.nan
    return x.rel_rot_reconverge_s.fillna(censor)


def reconvergence_by_method(rig, end_s):
    """({method: censored re-convergence per trial}, {method: median steady error}, whether the
    trials differ (stats.trials_differ on the steady errors)), methods in their order of appearance."""
    by_method = {m: rig[rig.method == m] for m in dict.fromkeys(rig.method)}
    times = {m: reconvergence(x, end_s) for m, x in by_method.items()}
    steady = {m: median(x.rel_rot_steady_err_deg) for m, x in by_method.items()}
    distinct = stats.trials_differ(x.rel_rot_steady_err_deg for x in by_method.values())
    return times, steady, distinct


def contest(rig, end_s):
    """Who re-converges first: per method the median censored re-convergence, ties broken by the
    median steady error; the winner against each other method paired by trial, Holm over them.
    (winner, {method: Comparison}) or None."""
    times, steady, distinct = reconvergence_by_method(rig, end_s)
    ranked = sorted(times, key=lambda m: (median(times[m]), steady[m]))
    if not ranked or not math.isfinite(median(times[ranked[0]])):
        return None
    winner = ranked[0]
    comparisons = {m: stats.compare(stats.paired_differences(times[m], times[winner]),
                                    grid=distinct)
                   for m in ranked[1:]}
    stats.holm(list(comparisons.values()))
    return winner, comparisons


def table(rig, end_s, tracking):
    result = contest(rig, end_s) if tracking else None
    winner, comparisons = result if result else (None, {})
    head = ["method", "trials ok", "relative rotation error (deg)", "|baseline error| (mm)",
            "vertical disparity RMS (px)", "|depth error| at 30 m (%)"]
    if tracking:
        head += ["re-converge (s) to the tolerance", "steady error (deg)",
                 "Δ re-converge vs the first [95% CI]", "p (Holm)"]
    body = []
    for m in dict.fromkeys(rig.method):
        x = rig[rig.method == m]
        ok = x[x.status == "ok"]
        cells = [m + (" (first)" if m == winner else ""), f"{len(ok)}/{len(x)}",
                 num(median(ok.rel_rot_err_deg)), num(median(ok.err_baseline_mm.abs())),
                 num(median(ok.vdisp_rms_px)), num(median(ok.depth_err_30m_pct.abs()))]
        if tracking:
            r = x.rel_rot_reconverge_s
            never = int(r.isna().sum())
            med = median(r) if never <= len(r) / 2 else math.nan
            cell = "never" if not math.isfinite(med) else f"{med:.2f}"
            if never and math.isfinite(med):
                cell += f" ({never}/{len(r)} never)"
            c = comparisons.get(m)
            cells += [cell, num(median(x.rel_rot_steady_err_deg)),
                      effect_text(c, "s") if c else "–", p_text(c) if c else "–"]
        body.append(cells)
    return markdown(body, head)


def section(ctx):
    rig = ctx.data.table("rig")
    if not len(rig):
        return None
    out = Section()
    out.md += ["## Camera rigs", "",
               "Each camera of a rig is measured on its own. Every method but the joint ekf_rig "
               "(which carries the relative pose in its state) also estimates each camera on its "
               "own; the relative pose of camera c is what the estimates of camera 0 and camera c "
               "give "
               "(cam_c_from_cam_0), against the truth, at the end of the run. Vertical disparity: "
               "the true projections of a 5 × 5 grid on a plane 10 m ahead, rectified with the "
               "estimated rig; depth error: a point 30 m ahead through the estimated rig's "
               "disparity. Tracking scenarios: the relative rotation's re-convergence after the "
               "last change that moves the pair (never: censored at the segment's length in the "
               "paired test), its steady error (median over the last part of the segment); "
               "medians over the trials; paired by trial against the first to re-converge, "
               "Holm-adjusted over the methods.", ""]
    for (scenario, camera), x in rig.groupby(["scenario", "camera"], sort=False):
        tracking = x.segment_from_s.notna().any()
        trials = x.trial.nunique()
        out.md += [f"### {scenario}, camera {camera} against camera 0 ({trials} trials)", "",
                   table(x, run_end(ctx.data, scenario), tracking), ""]
        if tracking and trials < stats.MIN_PAIRS:
            out.md += [f"Not testable: {trials} trials, a paired test needs {stats.MIN_PAIRS}.",
                       ""]
    return out



def steady_contest(rig):
    """Who follows the relative rotation closest once settled: per method the median steady error
    (median |error| over the last part of the segment after the last change), the winner against
    every other method paired by trial, Holm over them. (winner, {method: Comparison}) or None."""
    methods = list(dict.fromkeys(rig.method))
    steady = {m: pd.to_numeric(rig[rig.method == m].set_index("trial").rel_rot_steady_err_deg,
                               errors="coerce") for m in methods}
    ranked = sorted((m for m in methods if math.isfinite(median(steady[m]))),
                    key=lambda m: median(steady[m]))
    if not ranked:
        return None
    winner = ranked[0]
    comparisons = {m: stats.compare(stats.paired_differences(steady[m], steady[winner]))
                   for m in ranked[1:]}
    stats.holm(list(comparisons.values()))
    return winner, comparisons


def versus_batch(ctx, rig, end_s):
    """The adaptive estimator against batch calibration on a rig camera's relative rotation
    (stats.first_against_first on the censored re-convergence times, ties by steady error)."""
    times, steady, distinct = reconvergence_by_method(rig, end_s)
    return stats.first_against_first(times, steady, ctx.data.families, grid=distinct)


@functools.lru_cache(maxsize=None)
def versus_rows(ctx):
    """{(scenario, camera): (adaptive, batch, Comparison)} of the rig tracking scenarios, the
    comparisons Holm-adjusted as one family (once per report)."""
    rig = ctx.data.table("rig")
    out = {}
    if not len(rig):
        return out
    for (scenario, camera), x in rig.groupby(["scenario", "camera"], sort=False):
        if x.segment_from_s.notna().any():
            v = versus_batch(ctx, x, run_end(ctx.data, scenario))
            if v:
                out[(scenario, camera)] = v
    stats.holm([c for _, _, c in out.values()])
    return out


def verdict(ctx):
    """The first screen's line: per rig scenario and camera, the adaptive estimator against
    batch calibration on the relative rotation; or None."""
    parts = [f"{scenario}, camera {camera}: "
             f"{time_versus_text(a, b, c, 're-converges in relative rotation')}"
             for (scenario, camera), (a, b, c) in versus_rows(ctx).items()]
    return "; ".join(parts) if parts else None


def answer(ctx):
    """The first page's answer on the rig tracking scenarios: per scenario and camera, who
    re-converges first in relative rotation and who then follows it closest, each against its
    runner-up, or None."""
    rig = ctx.data.table("rig")
    if not len(rig):
        return None
    body = []
    versus = versus_rows(ctx)
    for (scenario, camera), x in rig.groupby(["scenario", "camera"], sort=False):
        if not x.segment_from_s.notna().any():
            continue
        end_s = run_end(ctx.data, scenario)
        first, closest = contest(x, end_s), steady_contest(x)
        if first is None or closest is None:
            continue
        row = [f"{scenario}, camera {camera}", f"{x.trial.nunique()}"]
        v = versus.get((scenario, camera))
        for (winner, comparisons), value, unit in (
                (first, lambda w: median(reconvergence(w, end_s)), "s"),
                (closest, lambda w: median(w.rel_rot_steady_err_deg), "deg")):
            runner = next(iter(comparisons), None)
            c = comparisons.get(runner)
            row += [f"{winner} ({num(value(x[x.method == winner]), 2)} {unit})",
                    f"{runner or '–'}: {effect_text(c, unit)}", p_text(c)]
        row.append(time_versus_text(*v, "re-converges") if v else "–")
        body.append(row)
    if not body:
        return None
    head = ["scenario", "trials", "first to re-converge (median)", "runner-up, Δ [95% CI]",
            "p (Holm)", "closest once settled (median steady error)", "runner-up, Δ [95% CI]",
            "p (Holm)", "adaptive against batch: the first of each, Δ [95% CI], p (Holm)"]
    return [markdown(body, head), "",
            "Re-convergence: the first time after the last change from which the relative "
            "rotation's error stays within the tolerance; steady error: its median |error| over "
            "the segment's last part. Both paired by trial, Holm-adjusted over the methods.", ""]
