"""Markdown of the report: tables (pandas' to_markdown) and the formats of numbers and tests."""
import math
import numbers

import pandas as pd

from calibench_report import stats

SIGNIFICANT = f"Holm-adjusted p < {stats.SIGNIFICANCE:g}"  # How a table names significance.


def markdown(rows, columns):
    """A Markdown table of `rows` (lists of cells, already text) under `columns`."""
    frame = pd.DataFrame(rows, columns=columns)
    return frame.to_markdown(index=False, disable_numparse=True)


def finite(x):
    # numbers.Real also holds numpy's integers (a CSV column of whole numbers reads as int64).
    return isinstance(x, numbers.Real) and math.isfinite(x)


def num(x, digits=3):
    return f"{x:.{digits}g}" if finite(x) else "–"


def signed(x, digits=2):
    return f"{x:+.{digits}g}" if finite(x) else "–"


def p_value(p):
    if not finite(p):
        return "–"
    return f"{p:.2g}" if p >= 1e-4 else f"{p:.1e}"


TEST_NAMES = {"t": "paired t", "W": "Wilcoxon"}


def p_text(c):
    """'p 0.003 (Wilcoxon)', the reason there is no test, or '–'."""
    if c is None:
        return "–"
    if not c.tested:
        if c.reason == f"n<{stats.MIN_PAIRS}":
            return f"not testable (n={c.n}<{stats.MIN_PAIRS})"
        return f"n/a ({c.reason})"
    return f"p {p_value(c.p_adjusted)} ({TEST_NAMES.get(c.test, c.test)})"


def effect_text(c, unit=""):
    """'Δ +0.12 [+0.05, +0.2] px' of a comparison's effect and its bootstrap interval."""
    if c is None or not finite(c.effect):
        return "–"
    lo, hi = c.effect_ci
    interval = f" [{signed(lo)}, {signed(hi)}]" if finite(lo) else ""
    return f"Δ {signed(c.effect)}{interval}" + (f" {unit}" if unit else "")


def band(median, lo, hi, bold=False):
    text = f"**{num(median)}**" if bold else num(median)
    return f"{text} [{num(lo, 2)}, {num(hi, 2)}]"
