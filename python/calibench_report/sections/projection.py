"""Where each method's image projects right: one table, per sweep (a scenario that is not swept
is its own) with at least two methods and per method, the median over its ok rows of the
projection error against the truth over the image (the quantity schema.json marks projection
"error", runs.csv proj_err_px) and the RMS of its ratio to the projection error the method's own
covariance predicts (projection "ratio", proj_err_ratio): ≈ 1 the method knows how wrong it is,
≫ 1 it is overconfident, ≪ 1 underconfident; "–" where it reports no covariance. Sweeps whose
truth changes are left to the dynamic section (their rows compare the last estimate with the
truth at the start)."""
import math

import numpy as np
import pandas as pd

from calibench_report.scores import ok_rows
from calibench_report.sections import Section
from calibench_report.tables import markdown, num

# Bounds of the verdict on the RMS ratio: within them it is called consistent. A loose band (a
# first-order prediction, and the RMS of a few dozen trials: ±20% at 30 trials of a ratio whose
# square has a chi-square-like spread).
CONSISTENT_BAND = (0.7, 1.5)


def verdict(rms_ratio):
    if not math.isfinite(rms_ratio):
        return "no covariance"
    lo, hi = CONSISTENT_BAND
    if rms_ratio > hi:
        return "overconfident"
    if rms_ratio < lo:
        return "underconfident"
    return "consistent"


def _values(rows, column):
    if column is None or column not in rows:
        return np.array([])
    v = pd.to_numeric(rows[column], errors="coerce").to_numpy(dtype=float)
    return v[np.isfinite(v)]


def table_rows(rows, error_column, ratio_column):
    """[(method, median error, RMS ratio, trials)] of the methods with a finite error."""
    out = []
    for method, h in ok_rows(rows).groupby("method", sort=False):
        errors = _values(h, error_column)
        if errors.size == 0:
            continue
        ratios = _values(h, ratio_column)
        rms = float(np.sqrt(np.mean(ratios ** 2))) if ratios.size else math.nan
        out.append((method, float(np.median(errors)), rms, int(errors.size)))
    return out


def section(ctx):
    schema = ctx.data.schema
    error, ratio = schema.projection("error"), schema.projection("ratio")
    runs = ctx.data.runs
    if error is None or not len(runs) or error.column("value") not in runs:
        return None
    error_column = error.column("value")
    ratio_column = ratio.column("value") if ratio is not None else None
    table = []
    for sweep, rows in runs.groupby("sweep", sort=False):
        described = schema.sweep(sweep)
        if described is not None and described.tracks:
            continue  # The truth changes: the row's figures are against its start (t = 0).
        cells = table_rows(rows, error_column, ratio_column)
        if len(cells) < 2:
            continue  # Nothing to compare (the thesis reproduction's single estimator).
        table += [[sweep, m, num(e), num(r, 2), verdict(r), str(n)] for m, e, r, n in cells]
    if not table:
        return None
    lo, hi = CONSISTENT_BAND
    return Section(md=[
        "## Where each method's image projects right", "",
        f"Per sweep (over all its points; a scenario that is not swept is its own) with at least "
        f"two methods, and per method: the median of {error_column} ({error.doc}), and the RMS "
        f"of {ratio_column}, its ratio to the projection error the method's own covariance "
        "predicts: ≈ 1 it knows how wrong it is, ≫ 1 it is overconfident (called consistent "
        f"here within {lo:g}–{hi:g}); no covariance: the method reports none (or its lens model "
        "has distortion terms the covariance lacks).", "",
        markdown(table, ["sweep", "method", f"median {error_column}", f"RMS {ratio_column}",
                         "verdict", "trials"]), ""])
