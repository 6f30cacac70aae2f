"""Statistics of the calibench report (imported by report.py; tests/bench/report_stats_test.py).

Seed 001's method for comparing two estimators on the same Monte Carlo trials:
  * the paired differences d = |error of A| - |error of B| over the seeds both have a finite value
    for (unpaired and NaN trials dropped);
  * Lilliefors test of the normality of d at the 5% level; not rejected: the paired t-test of d
    (scipy ttest_1samp(d, 0), equal to ttest_rel); rejected: the Wilcoxon signed-rank test;
  * effect size: the median of d with a percentile bootstrap 95% interval (resampled trial indices
    from a fixed seed, a function of the number of pairs alone: the same data give the same
    interval, whatever the order of the comparisons);
  * Holm-Bonferroni adjustment of the p-values of a family (one report table).
Fewer than MIN_PAIRS pairs, d all zero ("identical") or d constant (the trials repeat one another,
e.g. rendered frames without noise) give no test: a reason instead of a p-value.
And the helpers of the report's other numbers: percentile bands of |error|, RMSE, the coverage of
reported standard deviations and the binomial band of a coverage.
"""
import dataclasses
import functools
import math
import warnings

import numpy as np
from scipy import stats
from statsmodels.stats.diagnostic import lilliefors
from statsmodels.stats.multitest import multipletests

NORMALITY_LEVEL = 0.05  # Lilliefors: below it the differences are taken as not normal.
MIN_PAIRS = 5  # Fewer paired trials: no test.
BOOTSTRAP_RESAMPLES = 2000
BOOTSTRAP_SEED = 1  # numpy Generator seed of every bootstrap (deterministic intervals).
Z95 = 1.959963984540054  # Two-sided 95% normal quantile: coverage of mean +- Z95 * std.


@dataclasses.dataclass
class Comparison:
    """One paired comparison: A - B on the same trials."""
    n: int = 0  # Pairs used.
    test: str = ""  # "t" (paired t-test) or "W" (Wilcoxon signed-rank); "" when not tested.
    normality_p: float = math.nan  # Lilliefors p-value of the differences.
    p: float = math.nan  # The test's two-sided p-value, unadjusted.
    p_adjusted: float = math.nan  # Holm-adjusted within the family (holm()).
    effect: float = math.nan  # Median of the paired differences.
    effect_ci: tuple = (math.nan, math.nan)  # Its bootstrap 95% interval.
    reason: str = ""  # Why there is no test: "n<5", "identical", "Δ constant".

    @property
    def tested(self):
        return math.isfinite(self.p)


def paired_differences(a, b):
    """a - b over the index values (seeds) both pandas Series have, NaN/inf pairs dropped."""
    if a.index.equals(b.index) and a.index.is_unique:  # The usual case: every trial in both.
        d = a.to_numpy(dtype=float) - b.to_numpy(dtype=float)
    else:
        common = a.index.intersection(b.index)
        d = a.loc[common].to_numpy(dtype=float) - b.loc[common].to_numpy(dtype=float)
    return d[np.isfinite(d)]


@functools.lru_cache(maxsize=64)
def resample_indices(n, resamples=BOOTSTRAP_RESAMPLES, seed=BOOTSTRAP_SEED):
    """The bootstrap's (resamples, n) trial indices: a function of n alone (fixed seed), so an
    interval depends on its data only, and is drawn once for all the comparisons of n trials."""
    indices = np.random.default_rng(seed).integers(0, n, size=(resamples, n))
    indices.setflags(write=False)
    return indices


def bootstrap_median_ci(d, level=0.95):
    """Percentile bootstrap interval of the median of d, all resamples in one array operation."""
    d = np.asarray(d, dtype=float)
    if d.size == 0:
        return math.nan, math.nan
    medians = np.median(d[resample_indices(d.size)], axis=1)
    tail = (1 - level) / 2
    lo, hi = np.quantile(medians, [tail, 1 - tail])
    return float(lo), float(hi)


def choose_and_test(d):
    """(test, normality p, p): Lilliefors on d, then the paired t-test or the Wilcoxon test."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # Lilliefors' table bounds, Wilcoxon's ties and zeros.
        _, normality_p = lilliefors(d, dist="norm", pvalmethod="table")
        if normality_p >= NORMALITY_LEVEL:
            return "t", float(normality_p), float(stats.ttest_1samp(d, 0.0).pvalue)
        return "W", float(normality_p), float(stats.wilcoxon(d).pvalue)


def compare(d):
    """The Comparison of paired differences d (NaNs already dropped: paired_differences)."""
    d = np.asarray(d, dtype=float)
    return dataclasses.replace(_compare(d.tobytes()))  # A copy: holm() sets p_adjusted.


@functools.lru_cache(maxsize=4096)
def _compare(d_bytes):
    """compare() of the differences in d_bytes, memoised: a gain sweep repeats the batch
    methods' rows, hence their comparisons, at every gain."""
    d = np.frombuffer(d_bytes, dtype=float)
    out = Comparison(n=int(d.size))
    if d.size < MIN_PAIRS:
        out.reason = f"n<{MIN_PAIRS}"
        return out
    out.effect = float(np.median(d))
    out.effect_ci = bootstrap_median_ci(d)
    if np.all(d == 0):
        out.reason = "identical"
        return out
    if np.ptp(d) == 0:  # The same difference in every trial: the trials repeat one another.
        out.reason = "Δ constant"
        return out
    out.test, out.normality_p, out.p = choose_and_test(d)
    return out


def holm(comparisons):
    """Sets p_adjusted of the tested comparisons of one family (Holm-Bonferroni)."""
    tested = [c for c in comparisons if c.tested]
    if not tested:
        return
    _, adjusted, _, _ = multipletests([c.p for c in tested], method="holm")
    for c, p in zip(tested, adjusted):
        c.p_adjusted = float(p)


def abs_band(values):
    """(median, 2.5th, 97.5th percentile) of |values| over the finite ones; NaNs if none."""
    v = np.abs(np.asarray(values, dtype=float))
    v = v[np.isfinite(v)]
    if v.size == 0:
        return math.nan, math.nan, math.nan
    return float(np.median(v)), float(np.quantile(v, 0.025)), float(np.quantile(v, 0.975))


def rmse(values):
    v = np.asarray(values, dtype=float)
    v = v[np.isfinite(v)]
    return float(np.sqrt(np.mean(v * v))) if v.size else math.nan


def coverage(errors, stds, z=Z95):
    """(fraction of trials with |error| <= z * std, trials), over the trials with both finite."""
    e, s = np.asarray(errors, dtype=float), np.asarray(stds, dtype=float)
    ok = np.isfinite(e) & np.isfinite(s)
    n = int(ok.sum())
    return (float(np.mean(np.abs(e[ok]) <= z * s[ok])) if n else math.nan), n


def coverage_band(n, nominal=0.95, level=0.95):
    """The central `level` band of the coverage fraction of n trials at true coverage `nominal`
    (binomial quantiles / n): a coverage outside it is off at that level."""
    if n <= 0:
        return math.nan, math.nan
    lo, hi = stats.binom.interval(level, n, nominal)
    return lo / n, hi / n
