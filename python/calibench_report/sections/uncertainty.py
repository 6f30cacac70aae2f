"""Reported standard deviations against the Monte Carlo spread: per method that reports them
(std_Q columns), the median reported std (summary.csv std_reported) against the spread of its
errors (summary.csv std), their ratio, the bias (summary.csv mean) and the coverage of the 95%
intervals (from the trials: |error| <= 1.96 std), flagged outside the binomial band."""
import dataclasses
import math

import numpy as np

from calibench_report import stats
from calibench_report.scores import ok_rows, twins
from calibench_report.sections import Section
from calibench_report.tables import markdown, num, signed


@dataclasses.dataclass
class Cell:
    reported: float
    spread: float
    bias: float
    coverage: float
    n: int

    @property
    def ratio(self):
        return self.reported / self.spread if self.spread > 0 else math.nan

    @property
    def outside(self):
        lo, hi = stats.coverage_band(self.n)
        return math.isfinite(self.coverage) and not lo <= self.coverage <= hi

    def text(self):
        flag = " ⚠" if self.outside else ""
        cover = f"{100 * self.coverage:.0f}%" if math.isfinite(self.coverage) else "–"
        return (f"{num(self.reported, 2)} / {num(self.spread, 2)} = {num(self.ratio, 2)}; bias "
                f"{signed(self.bias)}; {cover}{flag}")


def std_quantities(schema, rows):
    ok = ok_rows(rows)
    return [q for q in schema.quantities if q.column("std") in ok
            and np.isfinite(ok[q.column("std")].to_numpy(dtype=float)).any()]


def std_methods(rows, quantities):
    """The methods with a finite reported std, without those whose stds and errors repeat an
    earlier one's; and those twins {method: earlier method}."""
    stds = [q.column("std") for q in quantities]
    cols = [q.compared for q in quantities] + stds
    frames = {m: h.set_index(["point", "seed"])[cols].sort_index()
              for m, h in ok_rows(rows).groupby("method", sort=False)
              if np.isfinite(h[stds].to_numpy(dtype=float)).any()}
    same = twins({m: f.stack(dropna=False) for m, f in frames.items()})
    return [m for m in frames if m not in same], same


def cell(analysis, point, method, q):
    h = ok_rows(analysis.point_rows(point))
    h = h[h.method == method]
    cover, n = stats.coverage(h[q.compared], h[q.column("std")])
    metric = q.summary_metric
    return Cell(analysis.stat(point.scenario, method, metric, "std_reported"),
                analysis.stat(point.scenario, method, metric, "std"),
                analysis.stat(point.scenario, method, metric, "mean"), cover, n)


def sweep_cells(analysis, sweep):
    rows = analysis.rows_of(sweep)
    quantities = std_quantities(analysis.data.schema, rows)
    if not quantities:
        return None
    methods, same = std_methods(rows, quantities)
    if not methods:
        return None
    cells = {(p, m, q): cell(analysis, p, m, q)
             for p in analysis.points(sweep) for m in methods for q in quantities}
    return quantities, methods, same, cells


def range_text(values, fmt):
    values = [v for v in values if math.isfinite(v)]
    if not values:
        return "–"
    lo, hi = min(values), max(values)
    return fmt(lo) if lo == hi else f"{fmt(lo)}–{fmt(hi)}"


def section(ctx):
    analysis = ctx.analysis
    sweeps = [s for s in analysis.data.schema.sweeps if s.swept and len(analysis.rows_of(s))]
    results = {s: sweep_cells(analysis, s) for s in sweeps}
    results = {s: r for s, r in results.items() if r}
    if not results:
        return None
    out = Section()
    page = "appendix/uncertainty.md"
    out.md += ["## Reported uncertainty against the Monte Carlo spread", "",
               "For each method that reports standard deviations (std_ columns): over the sweep's "
               "points, the range of *reported / spread* (the median reported std over the "
               "spread of its errors, both from summary.csv; > 1: it overstates its uncertainty) "
               "and of the coverage of its 95% intervals (the share of trials with |error| ≤ "
               "1.96·std), with the points whose coverage is outside the binomial 95% band for "
               f"their trials. Per point, with the bias: [{page}]({page}).", ""]
    union = [q for q in analysis.data.schema.quantities
             if any(q in r[0] for r in results.values())]
    body = []
    pages = ["# Reported uncertainty, per point", "", "[Back to the report](../report.md)", "",
             "Cells: *reported / spread = ratio; bias; coverage*; ⚠: coverage outside the "
             "binomial 95% band for that number of trials at a true coverage of 95%.", ""]
    for sweep, (quantities, methods, same, cells) in results.items():
        points = analysis.points(sweep)
        for m in methods:
            row = [sweep.name, m]
            for q in union:
                if q not in quantities:
                    row.append("–")
                    continue
                mine = [cells[(p, m, q)] for p in points]
                off = sum(c.outside for c in mine)
                ratio = range_text([c.ratio for c in mine], lambda v: f"{v:.2g}")
                cover = range_text([100 * c.coverage for c in mine], lambda v: f"{v:.0f}%")
                row.append(f"ratio {ratio}; coverage {cover}"
                           + (f" ({off} of {len(points)} points outside ⚠)" if off else ""))
            body.append(row)
        ns = sorted({c.n for c in cells.values()})
        bands = "; ".join(f"{n} trials: {stats.coverage_band(n)[0]:.2f}–"
                          f"{stats.coverage_band(n)[1]:.2f}" for n in ns if n)
        notes = [f"{m}: the same stds and errors as {t} in every row (not repeated)."
                 for m, t in same.items()]
        pages += [f"## {sweep.name}", "", f"Band of the coverage: {bands}. " + " ".join(notes), "",
                  markdown([[p.label, m, str(cells[(p, m, quantities[0])].n)]
                            + [cells[(p, m, q)].text() for q in quantities]
                            for p in points for m in methods],
                           ["point", "method", "trials"] + [q.title for q in quantities]), ""]
    out.md += [markdown(body, ["sweep", "method"] + [q.title for q in union]), ""]
    out.pages[page] = pages
    return out
