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


TEST_NAMES = {"t": "paired t", "W": "Wilcoxon", "S": "sign test"}


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


def error_words(quantity):
    """'f·ku error', 'geodesic rotation error': a quantity's label as an error."""
    return quantity.label if quantity.label.endswith("error") else f"{quantity.label} error"


def ratio_versus_text(adaptive, batch, c, what):
    """Plain words for a comparison of log ratios ln(|adaptive error| / |batch error|):
    'ceres beats adaptive by 2.1× [1.8, 2.5] in f·ku error, p < 0.001 (paired t)'."""
    if c is None or not finite(c.effect):
        return f"{adaptive} against {batch}: no common trials"
    ratio, (lo, hi) = math.exp(c.effect), c.effect_ci
    interval = (f" [{math.exp(lo):.2g}, {math.exp(hi):.2g}]" if finite(lo) else "")
    if ratio >= 1:
        words = f"{batch} beats {adaptive} by {ratio:.2g}×{interval}"
    else:
        interval = (f" [{math.exp(-hi):.2g}, {math.exp(-lo):.2g}]" if finite(lo) else "")
        words = f"{adaptive} beats {batch} by {1 / ratio:.2g}×{interval}"
    if c.tested and not c.significant:
        words = f"not significant: {words}"
    return f"{words} in {what}, {p_text(c)}"


def time_versus_text(adaptive, batch, c, what):
    """Plain words for a comparison of paired times, batch's minus adaptive's (s): 'adaptive-reset
    re-converges 3.2 s [1.1, 5] before ceres-w2 after the pitch step, p 0.002 (Wilcoxon)'."""
    if c is None or not finite(c.effect):
        return f"{adaptive} against {batch}: no common trials"
    if c.reason == "identical":
        return f"{adaptive} and {batch} tie: the same time in every trial ({c.n})"
    lo, hi = c.effect_ci
    if c.effect >= 0:
        interval = f" [{num(lo, 2)}, {num(hi, 2)}]" if finite(lo) else ""
        words = f"{adaptive} {what} {num(c.effect, 2)} s{interval} before {batch}"
    else:
        interval = f" [{num(-hi, 2)}, {num(-lo, 2)}]" if finite(lo) else ""
        words = f"{batch} {what} {num(-c.effect, 2)} s{interval} before {adaptive}"
    if c.tested and not c.significant:
        words = f"not significant: {words}"
    return f"{words}, {p_text(c)}"
