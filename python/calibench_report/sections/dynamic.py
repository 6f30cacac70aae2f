"""Dynamic calibration: the scenarios whose truth changes (role dynamic; events.csv, tracks.csv,
track_bands.csv of bench/run/run_row.h).
  * per scenario and changed quantity: trial 0's estimates as deviations from the nominal value
    (the truth at t = 0; angles unwrapped, so no jump at +-180 deg) against the truth's, and the
    median |error| over the trials with its 95% band (track_bands.csv), events marked;
  * a table per scenario: per event the re-convergence time (median over the trials) of the
    quantity the event changes, the steady error, whether the angle targets hold, the cost per
    frame and the mean NEES over the steady parts against the 95% band of its mean;
  * a Pareto figure: steady error against re-convergence time, marker area ~ cost per frame;
  * the windup law: the re-convergence of the thesis's estimator against t0 / alpha ln(e0 / tol);
  * the first page's answer (answer): per scenario of role dynamic, who re-converges first after
    its first change, compared with the others paired by trial.
Methods are named by their instances; none is known by name: the windup rows are those of the
instances whose type declares a windup law (schema.json `methods`) that holds for their options,
read from config.resolved.yaml."""
import dataclasses
import functools
import math
import os

import numpy as np
import pandas as pd
import yaml
from scipy import stats as sps

from calibench_report import plots, stats
from calibench_report.sections import Section
from calibench_report.tables import effect_text, markdown, num, p_text, time_versus_text


def wrap(d):
    return (d + 180.0) % 360.0 - 180.0


def scenarios(data, role_only=False):
    """The scenarios that wrote events (their truth changes), in order, but a rig's (role rig:
    their rows are per camera; the rig section reports them); with role_only, those of the sweeps
    whose role is dynamic."""
    if not len(data.events):
        return []
    roles = {s.name: s.role for s in data.schema.sweeps}
    sweep_of = dict(zip(data.runs.scenario, data.runs.sweep))
    return [s for s in dict.fromkeys(data.events.scenario)
            if roles.get(sweep_of.get(s)) != "rig"
            and (not role_only or roles.get(sweep_of.get(s)) == "dynamic")]


def deviation(t, q):
    """Trial 0's estimate and truth of q as deviations from the nominal value (the truth at the
    first report time); for an angle the estimate is the truth's deviation plus the wrapped error,
    so neither jumps at +-180 deg."""
    true = t["true_" + q.name].to_numpy(dtype=float)
    est = t["est_" + q.name].to_numpy(dtype=float)
    if not len(true):
        return est, true
    nominal = true[0]
    if q.is_angle:
        true_dev = wrap(true - nominal)
        return true_dev + wrap(est - true), true_dev
    return est - nominal, true - nominal


def changed_quantities(data, scenario):
    """The tracked quantities whose truth changes in the scenario (trial 0's truth columns)."""
    t = data.tracks[data.tracks.scenario == scenario]
    out = []
    for q in data.schema.tracked():
        column = "true_" + q.name
        if column not in t or not len(t):
            continue
        true = t[column].to_numpy(dtype=float)
        dev = wrap(true - true[0]) if q.is_angle else true - true[0]
        if np.nanmax(dev) - np.nanmin(dev) > 1e-9:
            out.append(q)
    return out


def truth_of(data, scenario):
    t = data.tracks[data.tracks.scenario == scenario]
    return t[t.method == t.method.iloc[0]] if len(t) else t


def event_quantity(data, scenario, at_s, changed):
    """The quantity whose truth an event changes most over the 2 s after it (a ramp: its first
    2 s), relative to its tolerance."""
    t = truth_of(data, scenario)
    before = t[t.t_s < at_s].tail(1)
    after = t[(t.t_s >= at_s) & (t.t_s <= at_s + 2)].tail(1)
    if before.empty or after.empty:
        return changed[0] if changed else None
    ev = data.events[(data.events.scenario == scenario)]
    change = {}
    for q in changed:
        d = float(after["true_" + q.name].iloc[0] - before["true_" + q.name].iloc[0])
        tol = ev[ev.quantity == q.name].tol
        scale = float(tol.iloc[0]) if len(tol) else 1.0
        change[q] = abs(wrap(d) if q.is_angle else d) / scale
    return max(change, key=change.get)


@dataclasses.dataclass
class Event:
    index: int
    at_s: float
    end_s: float  # The segment's end: the next event, or the end of the run.
    quantity: object


def events_of(data, scenario, changed):
    ev = data.events[data.events.scenario == scenario]
    starts = sorted(set(ev.at_s))
    t = data.tracks[data.tracks.scenario == scenario]
    end = float(t.t_s.max()) if len(t) else max(starts)
    out = []
    for k, e in sorted(set(zip(ev.event, ev.at_s))):
        later = [s for s in starts if s > e]
        q = (event_quantity(data, scenario, e, changed) if k > 0
             else next(iter(data.schema.targeted()), None))
        out.append(Event(int(k), float(e), later[0] if later else end, q))
    return out


def reconvergence(data, scenario, event, method):
    """Per trial the re-convergence time of the event's quantity, a trial that never re-converges
    censored at the segment's length (it is at least that), indexed by trial; and its steady
    errors."""
    ev = data.events
    x = ev[(ev.scenario == scenario) & (ev.method == method) & (ev.event == event.index)
           & (ev.quantity == event.quantity.name)].set_index("trial")
    return x.reconverge_s.fillna(event.end_s - event.at_s), x.steady_err


def plot_tracks(ctx, scenario, changed, path):
    data = ctx.data
    tracks = data.tracks[data.tracks.scenario == scenario]
    bands = data.bands[data.bands.scenario == scenario]
    events = data.events[data.events.scenario == scenario]
    at = sorted(set(events[events.event > 0].at_s))
    methods = list(dict.fromkeys(tracks.method))
    fig, axes = plots.figure(2, len(changed), 6.5, 3.8)
    for c, q in enumerate(changed):
        ax = axes[0][c]
        truth = None
        for m in methods:
            t = tracks[tracks.method == m]
            est, truth = deviation(t, q)
            ax.plot(t.t_s, est, color=ctx.palette[m], lw=0.8, label=m)
        t0 = tracks[tracks.method == methods[0]]
        _, truth = deviation(t0, q)
        ax.plot(t0.t_s, truth, "k--", lw=1.2, label="truth")
        # The y range of the truth's change plus a few tolerances: an estimate's start-up
        # transient stays off the scale instead of hiding the change.
        tol = events[events.quantity == q.name].tol
        margin = 5 * (float(tol.iloc[0]) if len(tol) else 1.0)
        ax.set_ylim(np.nanmin(truth) - margin, np.nanmax(truth) + margin)
        ax.set_title(f"{scenario}: {q.label}, trial 0", fontsize=9)
        ax.set_xlabel("t (s)")
        ax.set_ylabel(f"{q.label} − nominal ({q.unit_text})")
        ax.legend(fontsize=6, ncol=2)
        ax = axes[1][c]
        for m in methods:
            b = bands[(bands.method == m) & (bands.quantity == q.name)].sort_values("t_s")
            ax.plot(b.t_s, b.median_abs, color=ctx.palette[m], lw=0.9, label=m)
            ax.fill_between(b.t_s, np.abs(b.p2_5).clip(1e-6), np.abs(b.p97_5).clip(1e-6),
                            color=ctx.palette[m], alpha=0.08)
        if len(tol):
            ax.axhline(float(tol.iloc[0]), color="k", ls=":", lw=1,
                       label=f"tolerance {float(tol.iloc[0]):g}")
        ax.set_yscale("log")
        ax.set_title(f"|error| of {q.label}: median and 95% band over the trials", fontsize=9)
        ax.set_xlabel("t (s)")
        for axis in axes[:, c]:
            for x in at:
                axis.axvline(x, color="grey", lw=0.8, alpha=0.6)
        ax.legend(fontsize=6, ncol=2)
    plots.save(fig, path, dpi=100)


def steady_times(bands, events, fraction=0.2):
    """Rows of `bands` in the steady part (the last `fraction`) of a segment between events: NEES
    right after a change measures the change, not the covariance."""
    starts = sorted(set(events.at_s))
    end = bands.t_s.max() if len(bands) else 0.0
    keep = np.zeros(len(bands), dtype=bool)
    t = bands.t_s.to_numpy()
    for k, a in enumerate(starts):
        b = starts[k + 1] if k + 1 < len(starts) else end + 1e-9
        keep |= (t >= b - fraction * (b - a)) & (t < b)
    return keep


def chi2_band(n, d):
    return sps.chi2.ppf(0.025, n * d) / n, sps.chi2.ppf(0.975, n * d) / n


def median(values):
    """The median of the finite values; NaN (no warning) when there is none."""
    v = pd.to_numeric(pd.Series(values), errors="coerce")
    v = v[np.isfinite(v)]
    return float(v.median()) if len(v) else math.nan


def method_table(ctx, scenario, events_list):
    data = ctx.data
    events = data.events[data.events.scenario == scenario]
    timings = data.timings[data.timings.scenario == scenario] if len(data.timings) else \
        pd.DataFrame(columns=["method", "wall_per_frame_us"])
    bands = data.bands[data.bands.scenario == scenario]
    trials = events.trial.nunique()
    lo, hi = chi2_band(trials, 7)
    lo3, hi3 = chi2_band(trials, 3)
    targeted = data.schema.targeted()
    head = ["method"]
    for e in events_list:
        label = "start" if e.index == 0 else f"event {e.index} at {e.at_s:g} s"
        q = e.quantity.label if e.quantity else "–"
        unit = f" ({e.quantity.unit_text})" if e.quantity else ""
        head += [f"{label}: re-converge (s) of {q}", f"steady{unit}"]
    head += [" and ".join(q.label for q in targeted) + " target (steady)", "µs per frame",
             "ms per simulated s",
             f"NEES, steady parts (7 dof; 95% band [{lo:.2f}, {hi:.2f}])",
             f"NEES rotation, steady parts (3 dof; [{lo3:.2f}, {hi3:.2f}])"]
    steady = steady_times(bands, events)
    tracks = data.tracks[data.tracks.scenario == scenario] if len(data.tracks) else None
    duration_s = float(tracks.t_s.max()) if tracks is not None and len(tracks) else math.nan
    body = []
    for m in dict.fromkeys(events.method):
        e = events[events.method == m]
        cells = [m]
        for ev in events_list:
            x = e[(e.event == ev.index) & (e.quantity == (ev.quantity.name if ev.quantity else ""))]
            r = x.reconverge_s
            never = int(r.isna().sum())
            med = median(r) if never <= len(r) / 2 else math.nan
            cell = "never" if not math.isfinite(med) else f"{med:.2f}"
            if never and math.isfinite(med):
                cell += f" ({never}/{len(r)} never)"
            cells += [cell if len(r) else "–", num(median(x.steady_err))]
        names = [q.name for q in targeted]
        rp = e[e.quantity.isin(names) & (e.event > 0)]
        limit = {q.name: q.target for q in targeted}
        holds = bool(len(rp)) and all(s <= limit[q] for q, s in zip(rp.quantity, rp.steady_err))
        cells.append("holds" if holds else "no")
        cost = median(timings[timings.method == m].wall_per_frame_us) if len(timings) else math.nan
        cells.append(f"{cost:.0f}" if math.isfinite(cost) else "–")
        per_s = (median(timings[timings.method == m].wall_ms) / duration_s
                 if len(timings) and duration_s > 0 else math.nan)
        cells.append(num(per_s))
        for quantity, (a, b) in (("nees", (lo, hi)), ("nees_rotation", (lo3, hi3))):
            n = bands[(bands.method == m) & (bands.quantity == quantity) & steady]
            if n["mean"].notna().any():
                inside = ((n["mean"] >= a) & (n["mean"] <= b)).mean()
                cells.append(f"{median(n['mean']):.3g} ({100 * inside:.0f}% of times inside)")
            else:
                cells.append("–")
        body.append(cells)
    return markdown(body, head)


def first_change(events_list):
    return next((e for e in events_list if e.index > 0 and e.quantity is not None), None)


def pareto_rows(ctx, scenario, events_list):
    """(method, quantity, median re-convergence, median steady error, cost) after the first
    change of the scenario."""
    data = ctx.data
    e = first_change(events_list)
    if e is None:
        return []
    ev = data.events[(data.events.scenario == scenario) & (data.events.event == e.index)
                     & (data.events.quantity == e.quantity.name)]
    timings = data.timings[data.timings.scenario == scenario] if len(data.timings) else None
    out = []
    for m, x in ev.groupby("method", sort=False):
        never = x.reconverge_s.isna().sum() > len(x) / 2
        cost = median(timings[timings.method == m].wall_per_frame_us) if timings is not None \
            else math.nan
        out.append((m, e.quantity, math.nan if never else median(x.reconverge_s),
                    median(x.steady_err), cost))
    return out


def pareto(ctx, rows_by_scenario, path):
    """Steady error against re-convergence after each scenario's first change, one panel per
    unit; marker area ~ cost per frame, x: never."""
    panels = {}
    for scenario, rows in rows_by_scenario.items():
        for m, q, rec, steady, cost in rows:
            if math.isfinite(steady):
                panels.setdefault(q.unit, []).append((scenario, m, q, rec, steady, cost))
    if not panels:
        return False
    fig, axes = plots.figure(1, len(panels), 7.5, 5.2)
    for ax, (unit, pts) in zip(axes.flat, panels.items()):
        for scenario, m, q, rec, steady, cost in pts:
            never = not math.isfinite(rec)
            size = max(8, math.sqrt(cost) * 2) if math.isfinite(cost) else 8
            ax.scatter(0 if never else rec, steady, s=size, marker="x" if never else "o",
                       color=ctx.palette[m], alpha=0.7)
            ax.annotate(f"{m} ({scenario})", (0 if never else rec, steady), fontsize=5)
        ax.set_xscale("symlog", linthresh=0.1)
        ax.set_yscale("log")
        ax.set_xlabel("re-convergence after the first change (s, median; x at 0: never)")
        ax.set_ylabel(f"steady error after it ({unit}, median)")
        ax.set_title(f"changes in {unit}; marker area ~ cost per frame", fontsize=9)
        ax.grid(True, which="both", alpha=0.3)
    plots.save(fig, path, dpi=100)
    return True


def windup_instances(config_text, schema):
    """{scenario: {instance: exponent}} of the instances whose type declares a windup law that
    holds for their options (those it names are all 0); the exponent is their option the law
    names."""
    out = {}
    for s in (yaml.safe_load(config_text) or {}).get("scenarios", []):
        for m in s.get("methods", []):
            t = schema.method_type(m.get("type"))
            law = t.windup if t else None
            exponent = m.get(law.exponent) if law else None
            if (isinstance(exponent, (int, float)) and not isinstance(exponent, bool)
                    and not any(m.get(o) for o in law.only_when_zero)):
                out.setdefault(s["name"], {})[m["name"]] = float(exponent)
    return out


def exponent_names(schema):
    """The options that hold the declared windup laws' exponents, in registry order."""
    return list(dict.fromkeys(t.windup.exponent for t in schema.methods if t.windup))


def step_size(data, scenario, at_s, q):
    """|jump| of q's truth at at_s, or None when it is not a step (a ramp: still moving later)."""
    t = truth_of(data, scenario)
    before = t[t.t_s < at_s].tail(1)
    first = t[t.t_s >= at_s].head(1)
    later = t[(t.t_s >= at_s) & (t.t_s <= at_s + 2)].tail(1)
    if before.empty or first.empty or later.empty:
        return None

    def delta(row):
        d = float(row["true_" + q.name].iloc[0] - before["true_" + q.name].iloc[0])
        return abs(wrap(d) if q.is_angle else d)

    jump, moved = delta(first), delta(later)
    return jump if jump > 0 and abs(moved - jump) <= 0.01 * jump else None


def windup_table(ctx, per_scenario):
    plain = {}
    for text in ctx.data.configs:
        plain.update(windup_instances(text, ctx.data.schema))
    body = []
    for scenario, events_list in per_scenario.items():
        for m, exponent in plain.get(scenario, {}).items():
            for e in events_list:
                if e.index == 0 or e.quantity is None:
                    continue
                e0 = step_size(ctx.data, scenario, e.at_s, e.quantity)
                if e0 is None:
                    continue
                ev = ctx.data.events
                x = ev[(ev.scenario == scenario) & (ev.method == m) & (ev.event == e.index)
                       & (ev.quantity == e.quantity.name)]
                if not len(x):
                    continue
                tol = float(x.tol.iloc[0])
                law = e.at_s / exponent * math.log(max(e0 / tol, 1.0))
                measured = median(x.reconverge_s)
                body.append([scenario, m, f"{exponent:g}", f"{e.at_s:g}", e.quantity.name,
                             num(e0), num(law), num(measured),
                             f"{measured / law:.2f}" if law > 0 and math.isfinite(measured)
                             else "–"])
    head = ["scenario", "instance", " / ".join(exponent_names(ctx.data.schema)), "t0 (s)",
            "quantity", "step e0",
            "law t0/α·ln(e0/tol) (s)", "measured (s, median)", "measured / law"]
    return markdown(body, head) if body else ""


def analyse(ctx, role_only=False):
    """{scenario: (changed quantities, [Event])} of the scenarios whose truth changes."""
    out = {}
    for scenario in scenarios(ctx.data, role_only):
        changed = changed_quantities(ctx.data, scenario)
        if changed:
            out[scenario] = (changed, events_of(ctx.data, scenario, changed))
    return out


def reconvergence_by_method(ctx, scenario, event):
    """{method: (censored re-convergence per trial, steady error per trial)} after `event`, and
    whether the trials differ (stats.trials_differ on the steady errors)."""
    ev = ctx.data.events
    methods = dict.fromkeys(ev[ev.scenario == scenario].method)
    times = {m: reconvergence(ctx.data, scenario, event, m) for m in methods}
    return times, stats.trials_differ(steady for _, steady in times.values())


def contest(ctx, scenario, event):
    """Who re-converges first after `event`: per method the median (over the trials) of the
    censored re-convergence time, ties broken by the median steady error; the winner compared
    with each other method, paired by trial (Δ = other - winner), Holm-adjusted as one family.
    Returns (winner, its median, its steady error, runner-up, {method: Comparison}, trials)."""
    times, distinct = reconvergence_by_method(ctx, scenario, event)
    ranked = sorted(times, key=lambda m: (median(times[m][0]), median(times[m][1])))
    if not ranked:
        return None
    winner = ranked[0]
    comparisons = {m: stats.compare(stats.paired_differences(times[m][0], times[winner][0]),
                                    grid=distinct)
                   for m in ranked[1:]}
    stats.holm(list(comparisons.values()))
    trials = len(times[winner][0])
    return (winner, median(times[winner][0]), median(times[winner][1]),
            ranked[1] if len(ranked) > 1 else None, comparisons, trials)


def section(ctx):
    per = analyse(ctx)
    if not per:
        return None
    out = Section()
    out.md += ["## Dynamic calibration", "",
               "Scenarios whose truth changes (truth.changes). Re-convergence: the first time "
               "after an event from which |error| stays within the tolerance until the next event; "
               "steady error: median |error| over the last 20% of the segment; both medians over "
               "the trials. The top panels show trial 0's estimates as deviations from the nominal "
               "value (the truth at the start; angles unwrapped), the bottom ones the median "
               "|error| over the trials with its 95% band. NEES (methods that report a "
               "covariance): eᵀP⁻¹e averaged over the trials at each time, its median over the "
               "steady parts of the segments (the last 20%) and the share of those times inside "
               "the 95% band of the mean of N chi-square(d) variables.", ""]
    rows = {}
    for scenario, (changed, events_list) in per.items():
        name = "tracking_" + "".join(c if c.isalnum() or c in "-_" else "_" for c in scenario)
        plot_tracks(ctx, scenario, changed, ctx.path(name + ".png"))
        trials = ctx.data.events[ctx.data.events.scenario == scenario].trial.nunique()
        rows[scenario] = pareto_rows(ctx, scenario, events_list)
        out.md += [f"### {scenario} ({trials} trials)", "", f"![{scenario}]({name}.png)", "",
                   method_table(ctx, scenario, events_list), ""]
    if pareto(ctx, rows, ctx.path("tracking_pareto.png")):
        out.md += ["### Steady error against re-convergence time", "",
                   "![pareto](tracking_pareto.png)", ""]
    windup = windup_table(ctx, {s: e for s, (_, e) in per.items()})
    if windup:
        out.md += ["### Windup of the thesis's estimator", "",
                   "After a change at t0 its error decays as (t0/t)^α: it is within tol after "
                   "(t0/α)·ln(e0/tol), e0 the error the change made (its peak).", "", windup, ""]
    return out


def versus_batch(ctx, scenario, event):
    """The adaptive estimator against batch calibration after `event`
    (stats.first_against_first on the censored re-convergence times, ties by steady error)."""
    times, distinct = reconvergence_by_method(ctx, scenario, event)
    return stats.first_against_first({m: t for m, (t, _) in times.items()},
                                     {m: median(s) for m, (_, s) in times.items()},
                                     ctx.data.families, grid=distinct)


@functools.lru_cache(maxsize=None)
def versus_rows(ctx):
    """{scenario: (event, (adaptive, batch, Comparison) or None)} of the dynamic scenarios'
    first changes, the comparisons Holm-adjusted as one family (once per report: the verdict
    and the answer table read it)."""
    out = {}
    for scenario, (_, events_list) in analyse(ctx, role_only=True).items():
        e = first_change(events_list)
        if e is not None:
            out[scenario] = (e, versus_batch(ctx, scenario, e))
    stats.holm([v[2] for _, v in out.values() if v])
    return out


def verdict(ctx):
    """The first screen's line: per dynamic scenario, the adaptive estimator against batch
    calibration after its first change; or None."""
    parts = [f"{scenario}: {time_versus_text(v[0], v[1], v[2], 're-converges')} "
             f"({e.quantity.label} at {e.at_s:g} s)"
             for scenario, (e, v) in versus_rows(ctx).items() if v]
    return "; ".join(parts) if parts else None


def answer_rows(ctx):
    """Per dynamic scenario (role dynamic), its first change and who re-converges first."""
    body = []
    versus = versus_rows(ctx)
    for scenario, (_, events_list) in analyse(ctx, role_only=True).items():
        e = first_change(events_list)
        if e is None:
            continue
        result = contest(ctx, scenario, e)
        if result is None:
            continue
        winner, time_s, steady, runner, comparisons, trials = result
        c = comparisons.get(runner)
        tied = c is not None and c.reason == "identical"
        v = versus.get(scenario, (None, None))[1]
        body.append([scenario, f"{e.quantity.label} at {e.at_s:g} s",
                     f"{winner} (tied with {runner})" if tied else winner,
                     f"{num(time_s)} s; steady {num(steady, 2)} {e.quantity.unit_text}",
                     runner or "–", effect_text(c, "s"), p_text(c),
                     time_versus_text(*v, "re-converges") if v else "–"])
    return body


def answer(ctx):
    """The first page's answer on the dynamic scenarios: a table, a note when no comparison is
    testable, and the Pareto figure (written by section(), which runs first), or None."""
    rows = answer_rows(ctx)
    if not rows:
        return None
    head = ["scenario", "first change", "first to re-converge", "its median (trials)",
            "runner-up", "Δ of the runner-up [95% CI]", "p (Holm over the methods)",
            "adaptive against batch: the first of each, Δ [95% CI], p (Holm over the scenarios)"]
    md = [markdown(rows, head), ""]
    trials = ctx.data.events.groupby("scenario").trial.nunique()
    if (trials < stats.MIN_PAIRS).all():
        span = (f"{trials.min()}" if trials.min() == trials.max()
                else f"{trials.min()}–{trials.max()}")
        md += [f"No comparison is testable: these scenarios have {span} trials, a paired test "
               f"needs {stats.MIN_PAIRS}; the medians and their differences are indicative.", ""]
    if os.path.exists(ctx.path("tracking_pareto.png")):
        md += ["![dynamic](tracking_pareto.png)", ""]
    return md
