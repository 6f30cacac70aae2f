"""Dynamic calibration in the calibench report (imported by report.py).

For each run directory with tracking files (events.csv, tracks.csv, track_bands.csv; run_row.h):
  * per scenario and changed quantity: the error over time, median |error| over the trials with
    its 2.5-97.5% band, per method, events marked, and trial 0's estimate against the truth;
  * a table per scenario and method: per event the re-convergence time (median over trials) of
    the quantity the event changes, the steady error, whether the 0.1 deg target holds (steady
    error <= 0.1 deg on roll and pitch), the cost per frame (timings.csv) and the mean NEES after
    the start with the two-sided 95% band of its mean over the trials;
  * a Pareto figure: steady error against re-convergence time, marker area ~ cost per frame;
  * the windup law: the re-convergence of the thesis's estimator against t0 / alpha ln(e0 / tol).
Methods are named by their instances; none is known by name: the windup rows are those of the
instances of type adaptive without forgetting or resetting, read from config.resolved.yaml.
"""
import math
import os

import numpy as np
import pandas as pd
import yaml
from scipy import stats

import matplotlib.pyplot as plt  # noqa: E402  (report.py chose the Agg backend)

ANGLES = ["roll_deg", "pitch_deg", "yaw_deg"]
QUANTITIES = ANGLES + ["fku_px", "fkv_px", "u0_px", "v0_px"]


def read(d):
    paths = {n: os.path.join(d, n) for n in ("events.csv", "tracks.csv", "track_bands.csv",
                                              "timings.csv", "config.resolved.yaml")}
    if not os.path.exists(paths["events.csv"]):
        return None
    events = pd.read_csv(paths["events.csv"])
    if events.empty:
        return None
    return {
        "events": events,
        "tracks": pd.read_csv(paths["tracks.csv"]),
        "bands": pd.read_csv(paths["track_bands.csv"]),
        "timings": pd.read_csv(paths["timings.csv"]),
        "config": open(paths["config.resolved.yaml"]).read(),
    }


def changed_quantities(tracks, scenario):
    """The quantities whose truth changes in the scenario (from trial 0's truth columns)."""
    t = tracks[tracks.scenario == scenario]
    out = []
    for q in QUANTITIES:
        v = t["true_" + q].to_numpy()
        if q in ANGLES and len(v):  # Relative to the first value, wrapped.
            v = (v - v[0] + 180) % 360 - 180
        if len(v) and np.nanmax(v) - np.nanmin(v) > 1e-9:
            out.append(q)
    return out


def event_quantity(tracks, scenario, at_s, changed):
    """The quantity whose truth an event changes most: over the 2 s after it (a ramp: its first 2 s
    scaled by the ramp's slope), relative to its tolerance scale (1 deg, 1 px)."""
    t = tracks[(tracks.scenario == scenario) & (tracks.method == tracks.method.iloc[0])]
    before = t[t.t_s < at_s].tail(1)
    after = t[(t.t_s >= at_s) & (t.t_s <= at_s + 2)].tail(1)
    if before.empty or after.empty:
        return changed[0] if changed else None
    change = {}
    for q in changed:
        d = float(after["true_" + q].iloc[0] - before["true_" + q].iloc[0])
        change[q] = abs((d + 180) % 360 - 180) if q in ANGLES else abs(d)
    return max(change, key=change.get)


def chi2_band(n, d):
    return stats.chi2.ppf(0.025, n * d) / n, stats.chi2.ppf(0.975, n * d) / n


def plot_tracks(data, scenario, changed, path):
    tracks = data["tracks"][data["tracks"].scenario == scenario]
    bands = data["bands"][data["bands"].scenario == scenario]
    events = data["events"][data["events"].scenario == scenario]
    at = sorted(set(events[events.event > 0].at_s))
    methods = list(dict.fromkeys(tracks.method))
    fig, axes = plt.subplots(2, len(changed), figsize=(6.5 * len(changed), 7.5), squeeze=False)
    for c, q in enumerate(changed):
        ax = axes[0][c]
        for i, m in enumerate(methods):
            t = tracks[tracks.method == m]
            est = t["est_" + q]
            if q in ANGLES:  # The truth plus the wrapped error: no jumps at +-180 deg.
                est = t["true_" + q] + ((t["est_" + q] - t["true_" + q] + 180) % 360 - 180)
            ax.plot(t.t_s, est, color=f"C{i % 10}", lw=0.8, label=m)
        t0 = tracks[tracks.method == methods[0]]
        ax.plot(t0.t_s, t0["true_" + q], "k--", lw=1.2, label="truth")
        ax.set_title(f"{scenario}: {q}, trial 0")
        ax.set_xlabel("t (s)")
        ax.set_ylabel(q)
        ax.legend(fontsize=6, ncol=2)
        ax = axes[1][c]
        for i, m in enumerate(methods):
            b = bands[(bands.method == m) & (bands.quantity == q)].sort_values("t_s")
            ax.plot(b.t_s, b.median_abs, color=f"C{i % 10}", lw=0.9, label=m)
            ax.fill_between(b.t_s, np.abs(b.p2_5).clip(1e-6), np.abs(b.p97_5).clip(1e-6),
                            color=f"C{i % 10}", alpha=0.08)
        tol = events[events.quantity == q].tol.iloc[0] if (events.quantity == q).any() else None
        if tol:
            ax.axhline(tol, color="k", ls=":", lw=1, label=f"tolerance {tol:g}")
        ax.set_yscale("log")
        ax.set_title(f"|error| of {q}: median and 95% band over the trials")
        ax.set_xlabel("t (s)")
        for axis in axes[:, c]:
            for x in at:
                axis.axvline(x, color="grey", lw=0.8, alpha=0.6)
        ax.legend(fontsize=6, ncol=2)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def steady_times(bands, events, fraction=0.2):
    """Rows of `bands` in the steady part (the last `fraction`) of a segment between events: NEES
    right after a change measures the change, not the covariance."""
    starts = sorted(set(events.at_s))
    end = bands.t_s.max()
    keep = np.zeros(len(bands), dtype=bool)
    t = bands.t_s.to_numpy()
    for k, a in enumerate(starts):
        b = starts[k + 1] if k + 1 < len(starts) else end + 1e-9
        keep |= (t >= b - fraction * (b - a)) & (t < b)
    return keep


def method_table(data, scenario, changed):
    events = data["events"][data["events"].scenario == scenario]
    timings = data["timings"][data["timings"].scenario == scenario]
    bands = data["bands"][data["bands"].scenario == scenario]
    trials = events.trial.nunique()
    lo, hi = chi2_band(trials, 7)
    lo3, hi3 = chi2_band(trials, 3)
    evs = sorted(set(events.event))
    head = ["method"]
    per_event = []
    for ev in evs:
        at = events[events.event == ev].at_s.iloc[0]
        q = event_quantity(data["tracks"], scenario, at, changed) if ev > 0 else "pitch_deg"
        per_event.append((ev, q, at))
        label = "start" if ev == 0 else f"event {ev} at {at:g} s"
        head += [f"{label}: re-converge (s) of {q}", "steady"]
    head += ["0.1° target (roll, pitch)", "µs per frame", f"NEES, steady parts (7 dof; 95% band "
             f"[{lo:.2f}, {hi:.2f}])", f"NEES rotation, steady parts (3 dof; [{lo3:.2f}, "
             f"{hi3:.2f}])"]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    rows = []
    for m in dict.fromkeys(events.method):
        e = events[events.method == m]
        cells = [m]
        for ev, q, at in per_event:
            x = e[(e.event == ev) & (e.quantity == q)]
            r = x.reconverge_s
            never = r.isna().sum()
            med = r.median() if never <= len(r) / 2 else math.nan
            cell = "never" if not np.isfinite(med) else f"{med:.2f}"
            if never and np.isfinite(med):
                cell += f" ({never}/{len(r)} never)"
            cells += [cell, f"{x.steady_err.median():.3g}"]
        rp = e[(e.quantity.isin(["roll_deg", "pitch_deg"])) & (e.event > 0)]
        holds = bool(len(rp)) and (rp.steady_err <= 0.1).all()
        cells.append("holds" if holds else "no")
        cost = timings[timings.method == m].us_per_frame.median()
        cells.append(f"{cost:.0f}")
        steady = steady_times(bands, events)
        nees = bands[(bands.method == m) & (bands.quantity == "nees") & steady]
        nees3 = bands[(bands.method == m) & (bands.quantity == "nees_rotation") & steady]
        for n, (a, b) in ((nees, (lo, hi)), (nees3, (lo3, hi3))):
            if n["mean"].notna().any():
                inside = ((n["mean"] >= a) & (n["mean"] <= b)).mean()
                cells.append(f"{n['mean'].median():.3g} ({100 * inside:.0f}% of times inside)")
            else:
                cells.append("–")
        lines.append("| " + " | ".join(cells) + " |")
        first_ev, first_q, _ = per_event[1] if len(per_event) > 1 else per_event[0]
        x = e[(e.event == first_ev) & (e.quantity == first_q)]
        rows.append((m, first_q, x.reconverge_s.median(), x.steady_err.median(), cost))
    return "\n".join(lines), rows


def pareto(all_rows, path):
    """Steady error against re-convergence after each scenario's first change, one panel per unit
    (angle events in deg, intrinsic events in px); marker area ~ cost per frame, x: never."""
    panels = {"deg": [], "px": []}
    for scenario, rows in all_rows.items():
        for i, (m, q, rec, steady, cost) in enumerate(rows):
            if np.isfinite(steady) and np.isfinite(cost):
                panels["deg" if q in ANGLES else "px"].append((scenario, i, m, q, rec, steady, cost))
    used = [u for u in panels if panels[u]]
    if not used:
        return False
    fig, axes = plt.subplots(1, len(used), figsize=(7.5 * len(used), 5.2), squeeze=False)
    for ax, unit in zip(axes.flat, used):
        for scenario, i, m, q, rec, steady, cost in panels[unit]:
            never = not np.isfinite(rec)
            ax.scatter(0 if never else rec, steady, s=max(8, math.sqrt(cost) * 2),
                       marker="x" if never else "o", color=f"C{i % 10}", alpha=0.7)
            label = scenario.replace("_oracle", "").replace("_rendered", " rendered")
            ax.annotate(f"{m} ({label})", (0 if never else rec, steady),
                        fontsize=5)
        ax.set_xscale("symlog", linthresh=0.1)
        ax.set_yscale("log")
        ax.set_xlabel("re-convergence after the first change (s, median; x at 0: never)")
        ax.set_ylabel(f"steady error after it ({unit}, median)")
        ax.set_title(f"changes of {'an angle' if unit == 'deg' else 'an intrinsic'}; "
                     "marker area ~ cost per frame")
        ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return True


def plain_adaptive(config_text):
    """{scenario: {instance: alpha}} of the adaptive instances without forgetting or resetting."""
    out = {}
    for s in (yaml.safe_load(config_text) or {}).get("scenarios", []):
        for m in s.get("methods", []):
            if m.get("type") == "adaptive" and not m.get("forgetting_beta") and \
                    not m.get("reset_threshold"):
                out.setdefault(s["name"], {})[m["name"]] = float(m["alpha"])
    return out


def step_size(tracks, scenario, at_s, q):
    """|jump| of q's truth at at_s, or None when it is not a step (a ramp: still moving later)."""
    t = tracks[(tracks.scenario == scenario) & (tracks.method == tracks.method.iloc[0])]
    before = t[t.t_s < at_s].tail(1)
    first = t[t.t_s >= at_s].head(1)
    later = t[(t.t_s >= at_s) & (t.t_s <= at_s + 2)].tail(1)
    if before.empty or first.empty or later.empty:
        return None
    def delta(row):
        d = float(row["true_" + q].iloc[0] - before["true_" + q].iloc[0])
        return abs((d + 180) % 360 - 180) if q in ANGLES else abs(d)
    jump, moved = delta(first), delta(later)
    return jump if jump > 0 and abs(moved - jump) <= 0.01 * jump else None


def windup_table(datas):
    """Re-convergence of plain adaptive instances after steps against t0 / alpha ln(e0 / tol)."""
    lines = ["| scenario | instance | alpha | t0 (s) | quantity | step e0 | law t0/α·ln(e0/tol) (s) "
             "| measured (s, median) | measured / law |", "|---|---|---|---|---|---|---|---|---|"]
    found = False
    for data in datas:
        plain = plain_adaptive(data["config"])
        events, tracks = data["events"], data["tracks"]
        for (scenario, m), e in events[events.event > 0].groupby(["scenario", "method"],
                                                                  sort=False):
            alpha = plain.get(scenario, {}).get(m)
            if alpha is None:
                continue
            changed = changed_quantities(tracks, scenario)
            for ev, g in e.groupby("event"):
                t0 = g.at_s.iloc[0]
                q = event_quantity(tracks, scenario, t0, changed)
                e0 = step_size(tracks, scenario, t0, q) if q else None
                if e0 is None:
                    continue
                x = g[g.quantity == q]
                tol = x.tol.iloc[0]
                law = t0 / alpha * math.log(max(e0 / tol, 1.0))
                measured = x.reconverge_s.median()
                ratio = measured / law if law > 0 else math.nan
                lines.append(f"| {scenario} | {m} | {alpha:g} | {t0:g} | {q} | {e0:.3g} | "
                             f"{law:.3g} | {measured:.3g} | {ratio:.2f} |")
                found = True
    return "\n".join(lines) if found else ""


def section(dirs, out):
    datas = [d for d in (read(x) for x in dirs) if d is not None]
    if not datas:
        return []
    md = ["## Dynamic calibration", "",
          "Scenarios whose truth changes (truth.changes). Re-convergence: the first time after an "
          "event from which |error| stays within the tolerance until the next event (0.1° for the "
          "angles, 1 px for the intrinsics); steady error: median |error| over the last 20% of the "
          "segment; both medians over the trials. NEES (methods that report a covariance): eᵀP⁻¹e "
          "averaged over the trials at each time, then its median over the steady parts of the "
          "segments (the last 20%) and the share of those times inside the 95% band of the mean of "
          "N chi-square(d) variables.", ""]
    pareto_rows = {}
    for data in datas:
        for scenario in dict.fromkeys(data["events"].scenario):
            changed = changed_quantities(data["tracks"], scenario)
            if not changed:
                continue
            name = f"tracking_{scenario}.png".replace("[", "_").replace("]", "").replace("=", "_")
            plot_tracks(data, scenario, changed, os.path.join(out, name))
            table, rows = method_table(data, scenario, changed)
            pareto_rows[scenario] = rows
            trials = data["events"][data["events"].scenario == scenario].trial.nunique()
            md += [f"### {scenario} ({trials} trials)", "", f"![{scenario}]({name})", "", table, ""]
    if pareto(pareto_rows, os.path.join(out, "tracking_pareto.png")):
        md += ["### Steady error against re-convergence time", "",
               "![pareto](tracking_pareto.png)", ""]
    windup = windup_table(datas)
    if windup:
        md += ["### Windup of the thesis's estimator", "",
               "After a change at t0 its error decays as (t0/t)^α: it is within tol after "
               "(t0/α)·ln(e0/tol), e0 the error the change made (its peak).", "", windup, ""]
    return md
