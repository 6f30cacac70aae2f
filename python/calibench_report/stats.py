"""Statistics of the report that summary.csv does not hold: comparisons of paired trials.

summary.csv (written by `calibench run`) holds every per-(scenario, method, metric) statistic: the
medians, percentile bands, RMSE and bounds the report shows; this module computes none of them
again. What needs the trials themselves is here, Algers 2018's way (§3.7) of comparing two
estimators on the same Monte Carlo trials:
  * the paired differences d = |error of A| - |error of B| over the seeds both have a finite value
    for (unpaired and NaN trials dropped);
  * Lilliefors test of the normality of d at the 5% level (statsmodels); not rejected: the paired
    t-test of d (scipy ttest_1samp(d, 0), equal to ttest_rel); rejected: the Wilcoxon signed-rank
    test (scipy: exact for small samples without ties or zeros);
  * effect size: the median of d with a percentile bootstrap 95% interval (scipy.stats.bootstrap,
    BOOTSTRAP_RESAMPLES resamples from a Generator seeded with BOOTSTRAP_SEED for every interval:
    the same data give the same interval, whatever the order of the comparisons);
  * Holm-Bonferroni adjustment of the p-values of a family (statsmodels), e.g. one report table;
  * the coverage of reported standard deviations and the binomial band of a coverage.
Fewer than MIN_PAIRS pairs (the median of d alone, without an interval), d all zero ("identical")
or d constant (the trials repeat one another, e.g. rendered frames without noise) give no test: a
reason instead of a p-value.
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
SIGNIFICANCE = 0.05  # A difference is called significant below this Holm-adjusted p.
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

    @property
    def significant(self):
        return math.isfinite(self.p_adjusted) and self.p_adjusted < SIGNIFICANCE


def paired_differences(a, b):
    """a - b over the index values (seeds) both pandas Series have, NaN/inf pairs dropped."""
    if a.index.equals(b.index) and a.index.is_unique:  # The usual case: every trial in both.
        d = a.to_numpy(dtype=float) - b.to_numpy(dtype=float)
    else:
        common = a.index.intersection(b.index)
        d = a.loc[common].to_numpy(dtype=float) - b.loc[common].to_numpy(dtype=float)
    return d[np.isfinite(d)]


def log_ratios(a, b):
    """ln(a / b) over the index values (seeds) both Series have, pairs with a value that is not
    positive and finite dropped: the paired comparison of two |errors| at any scale (a sweep's
    points pooled), its median's exponential the typical ratio."""
    d = paired_differences(np.log(a.where(a > 0)), np.log(b.where(b > 0)))
    return d[np.isfinite(d)]


def first_against_first(times, tiebreak, family_of):
    """The adaptive estimator against batch calibration on a re-convergence: per family the
    method whose median time (over its trials, a Series each) is smallest, ties broken by
    `tiebreak` (method -> number); the batch one's times minus the adaptive one's, paired by
    trial. (adaptive, batch, Comparison) or None when either family is absent; not Holm-adjusted.
    `family_of`: method -> family (io.RunData.families)."""
    def first(family):
        ranked = sorted((m for m in times if family_of.get(m) == family),
                        key=lambda m: (float(times[m].median()), tiebreak[m]))
        return ranked[0] if ranked else None

    a, b = first("adaptive"), first("batch")
    if a is None or b is None:
        return None
    return a, b, compare(paired_differences(times[b], times[a]))


def normality_p(d):
    """Lilliefors' p-value for the normality of d (mean and variance estimated)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # The table's bounds (p clipped to [0.001, 0.2]).
        return float(lilliefors(d, dist="norm", pvalmethod="table")[1])


def paired_t_p(d):
    """Two-sided p of the paired t-test of differences d (H0: mean 0)."""
    return float(stats.ttest_1samp(d, 0.0).pvalue)


def signed_rank_p(d):
    """Two-sided p of the Wilcoxon signed-rank test of differences d (H0: symmetric about 0)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # Ties and zeros: scipy's normal approximation.
        return float(stats.wilcoxon(d).pvalue)


def choose_and_test(d):
    """(test, normality p, p): Lilliefors on d, then the paired t-test or the Wilcoxon test."""
    p_normal = normality_p(d)
    if p_normal >= NORMALITY_LEVEL:
        return "t", p_normal, paired_t_p(d)
    return "W", p_normal, signed_rank_p(d)


def bootstrap_median_ci(d, level=0.95):
    """Percentile bootstrap interval of the median of d (seeded: deterministic)."""
    d = np.asarray(d, dtype=float)
    if d.size < 2:
        return math.nan, math.nan
    result = stats.bootstrap((d,), np.median, n_resamples=BOOTSTRAP_RESAMPLES,
                             confidence_level=level, method="percentile", vectorized=True,
                             random_state=np.random.default_rng(BOOTSTRAP_SEED))
    return float(result.confidence_interval.low), float(result.confidence_interval.high)


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
    if d.size:
        out.effect = float(np.median(d))
    if d.size < MIN_PAIRS:  # The median alone: no interval, no test.
        out.reason = f"n<{MIN_PAIRS}"
        return out
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
    """Sets p_adjusted of the tested comparisons of one family (Holm-Bonferroni); the untested
    ones are not part of the family."""
    tested = [c for c in comparisons if c.tested]
    if not tested:
        return
    _, adjusted, _, _ = multipletests([c.p for c in tested], method="holm")
    for c, p in zip(tested, adjusted):
        c.p_adjusted = float(p)


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
