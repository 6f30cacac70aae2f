"""Sweep points and their scores: which method is best at each point, and against whom.

Every per-(point, method, quantity) statistic is summary.csv's (`calibench run` computed it from
runs.csv): the median and 95% band of |error|, the RMSE, the bound. From runs.csv come only what
needs the trials: the paired comparisons (stats.py), which methods repeat another's values, and
the data each method used.
"""
import dataclasses
import functools
import math
from typing import Optional

import numpy as np
import pandas as pd

from calibench_report import stats
from calibench_report.schema import Quantity, Sweep

DATA_USED = (("n_frames_used", "frames"), ("n_obs_used", "observations"))


@dataclasses.dataclass(frozen=True)
class Point:
    sweep: Sweep
    index: int  # runs.csv `point`.
    scenario: str
    params: str  # "field=value" ("" when not swept).
    x: object  # The swept value (a points sweep: the feature points), for plots.

    @property
    def label(self):
        return self.params or self.scenario


@dataclasses.dataclass
class QuantityScore:
    """One quantity at one sweep point."""
    quantity: Quantity
    bands: dict  # method -> (median, p2.5, p97.5) of |value| (summary.csv)
    same: dict  # method -> earlier method with equal values (not scored)
    rmse_crlb: dict  # method -> RMSE / CRLB (summary.csv), NaN without a bound
    best: Optional[str] = None
    runner_up: Optional[str] = None
    comparisons: dict = dataclasses.field(default_factory=dict)  # method -> Comparison vs best

    @property
    def contest(self):
        """The comparison of the runner-up with the best method, or None."""
        return self.comparisons.get(self.runner_up) if self.runner_up else None


@dataclasses.dataclass
class PointScore:
    point: Point
    quantities: list  # [QuantityScore]

    def of(self, quantity):
        return next((s for s in self.quantities if s.quantity == quantity), None)


def axis_value(params):
    """The (field, value) of a one-axis sweep point 'field=value'; (None, None) otherwise."""
    if not params or ";" in params or "=" not in params:
        return None, None
    field, value = params.split("=", 1)
    try:
        return field, float(value)
    except ValueError:
        return field, value


def ok_rows(rows):
    return rows[rows.status == "ok"]


def estimates(values):
    """Whether a method estimates a quantity: a finite value in some row, not all exactly 0 (a
    parameter held at its truth, e.g. the skew of a model without one, has error 0)."""
    v = pd.to_numeric(values, errors="coerce").to_numpy(dtype=float)
    finite = v[np.isfinite(v)]
    return finite.size > 0 and bool((finite != 0).any())


def twins(series):
    """{method: the earlier method whose series is equal in every row}."""
    out, kept = {}, []
    for m, s in series.items():
        twin = next((k for k in kept if s.index.equals(series[k].index)
                     and np.array_equal(s.to_numpy(dtype=float), series[k].to_numpy(dtype=float),
                                        equal_nan=True)), None)
        if twin:
            out[m] = twin
        else:
            kept.append(m)
    return out


class Analysis:
    """The run data with its summary indexed, and the scores of every sweep point (computed once,
    shared by the first page, the sections and the appendix)."""

    def __init__(self, data):
        self.data = data
        summary = data.summary
        if "camera" in summary:  # A rig's run: camera c >= 1 is the rig section's (rig.csv).
            camera = pd.to_numeric(summary.camera, errors="coerce")
            summary = summary[camera.isna() | (camera == 0)]
        self._summary = (summary.set_index(["scenario", "method", "metric"]).sort_index()
                         if len(summary) else None)

    # -- summary.csv ----------------------------------------------------------------------------

    def stat(self, scenario, method, metric, column):
        """summary.csv's `column` of (scenario, method, metric); NaN when absent."""
        if self._summary is None or metric is None:
            return math.nan
        try:
            value = self._summary.at[(scenario, method, metric), column]
        except KeyError:
            return math.nan
        return float(value) if np.isscalar(value) else math.nan

    def band(self, scenario, method, metric):
        """(median, p2.5, p97.5) of |value| from summary.csv."""
        return tuple(self.stat(scenario, method, metric, c)
                     for c in ("median_abs", "p2_5_abs", "p97_5_abs"))

    # -- sweeps ---------------------------------------------------------------------------------

    def rows_of(self, sweep):
        return self.data.runs[self.data.runs.sweep == sweep.name]

    def points(self, sweep):
        rows = self.rows_of(sweep)
        firsts = rows.drop_duplicates("point").sort_values("point")
        out = []
        for _, r in firsts.iterrows():
            x = int(r.n_points) if sweep.role == "points" else axis_value(r.params)[1]
            out.append(Point(sweep, int(r.point), r.scenario, r.params, x))
        return out

    def methods_of(self, rows):
        return list(dict.fromkeys(rows.method))

    def by_seed(self, rows):
        """{method: its ok rows indexed by seed} (trials pair across methods by seed)."""
        return {m: h.set_index("seed") for m, h in ok_rows(rows).groupby("method", sort=False)}

    def series(self, rows, quantity):
        """({method: |quantity| by seed} of the methods that estimate it, twins removed; the
        twins {method: earlier method})."""
        column = quantity.compared
        if column not in rows:
            return {}, {}
        series = {m: h[column].abs() for m, h in self.by_seed(rows).items()
                  if estimates(h[column])}
        same = twins(series)
        return {m: s for m, s in series.items() if m not in same}, same

    def present(self, rows):
        """The ranked quantities some method of `rows` estimates."""
        ok = ok_rows(rows)
        return [q for q in self.data.schema.ranked()
                if q.compared in ok and estimates(ok[q.compared])]

    @functools.lru_cache(maxsize=None)
    def scores(self, sweep):
        """[PointScore] of a sweep, in point order."""
        return [self.score_point(p) for p in self.points(sweep)]

    def point_rows(self, point):
        return self.data.runs[self.data.runs.scenario == point.scenario]

    def score_point(self, point):
        """The point's QuantityScores, every comparison of the point Holm-adjusted as one family."""
        rows = self.point_rows(point)
        out = []
        for q in self.present(rows):
            series, same = self.series(rows, q)
            if not series:
                continue
            score = QuantityScore(
                q, {m: self.band(point.scenario, m, q.summary_metric) for m in series}, same,
                {m: self.stat(point.scenario, m, q.summary_metric, "rmse_over_crlb")
                 for m in series})
            ranked = sorted((b[0], i, m) for i, (m, b) in enumerate(score.bands.items())
                            if math.isfinite(b[0]))
            if ranked:
                score.best = ranked[0][2]
                score.runner_up = ranked[1][2] if len(ranked) > 1 else None
                for m in series:
                    if m != score.best:
                        score.comparisons[m] = stats.compare(
                            stats.paired_differences(series[m], series[score.best]))
            out.append(score)
        stats.holm([c for s in out for c in s.comparisons.values()])
        return PointScore(point, out)

    # -- per method -----------------------------------------------------------------------------

    def trials(self, scenario, method):
        """(ok trials, failed trials) from summary.csv's n and n_failed (any of its metrics)."""
        if self._summary is None:
            return 0, 0
        try:
            rows = self._summary.loc[(scenario, method)]
        except KeyError:
            return 0, 0
        n, failed = int(rows["n"].iloc[0]), int(rows["n_failed"].iloc[0])
        return n - failed, failed

    def data_used(self, rows, method):
        """(median n_frames_used, median n_obs_used) of a method's rows; None where not
        recorded (no column, or only -1)."""
        h = rows[rows.method == method]
        out = []
        for col, _ in DATA_USED:
            v = h[col].to_numpy(dtype=float) if col in h else np.array([])
            v = v[np.isfinite(v) & (v >= 0)]
            out.append(float(np.median(v)) if v.size else None)
        return tuple(out)
