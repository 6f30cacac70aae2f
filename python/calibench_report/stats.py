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
reason instead of a p-value. Except for times on the frame grid of distinct trials (compare's
`grid`, trials_differ): there a constant d is a clear effect, tested by the exact sign test.
The power of a comparison: its standardized effect (Cohen's dz) and trials_for_power.
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
POWER = 0.8  # The power a trial count is chosen for (trials_for_power).
# A noncentrality beyond which a paired t-test's power is 1 to double precision at any level the
# report uses (its critical t is < 20 from 5 pairs at 1e-4); scipy's noncentral t fails far out.
NONCENTRALITY_CERTAIN = 40.0
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
    # Mean / standard deviation of the differences (Cohen's dz; infinite when every difference
    # is the same non-zero one, NaN when all are 0 or fewer than 2).
    standardized: float = math.nan
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


def first_against_first(times, tiebreak, family_of, grid=True):
    """The adaptive estimator against batch calibration on a re-convergence: per family the
    method whose median time (over its trials, a Series each) is smallest, ties broken by
    `tiebreak` (method -> number); the batch one's times minus the adaptive one's, paired by
    trial (times on the frame grid: compare's `grid`, true when the trials differ). (adaptive,
    batch, Comparison) or None when either family is absent; not Holm-adjusted. `family_of`:
    method -> family (io.RunData.families)."""
    def first(family):
        ranked = sorted((m for m in times if family_of.get(m) == family),
                        key=lambda m: (float(times[m].median()), tiebreak[m]))
        return ranked[0] if ranked else None

    a, b = first("adaptive"), first("batch")
    if a is None or b is None:
        return None
    return a, b, compare(paired_differences(times[b], times[a]), grid=grid)


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


def compare(d, grid=False):
    """The Comparison of paired differences d (NaNs already dropped: paired_differences).
    `grid`: d are differences of times on the frame grid (re-convergence) of trials that differ
    (their own noise; trials_differ): there the same difference in every trial is the usual outcome
    of a clear effect (both methods land on the same frames each time), tested by the exact sign
    test (every pair on one side: p = 2 / 2^n). Elsewhere it means the trials repeat one another
    and is not tested ("Δ constant")."""
    d = np.asarray(d, dtype=float)
    return dataclasses.replace(_compare(d.tobytes(), grid))  # A copy: holm() sets p_adjusted.


def trials_differ(per_trial):
    """Whether a scenario's trials are distinct draws: some per-trial figure on a continuous scale
    (e.g. each method's steady error, a Series or array per method in `per_trial`) takes more than
    one value. Trials that repeat one another (no noise, no random phase) give one value each."""
    for values in per_trial:
        v = np.asarray(values, dtype=float)
        v = v[np.isfinite(v)]
        if v.size > 1 and np.ptp(v) > 0:
            return True
    return False


def sign_test_p(d):
    """Two-sided exact p of the sign test of differences d (zeros dropped; H0: median 0)."""
    d = np.asarray(d, dtype=float)
    d = d[d != 0]
    return float(stats.binomtest(int(np.sum(d > 0)), d.size).pvalue) if d.size else 1.0


@functools.lru_cache(maxsize=4096)
def _compare(d_bytes, grid):
    """compare() of the differences in d_bytes, memoised: a gain sweep repeats the batch
    methods' rows, hence their comparisons, at every gain."""
    d = np.frombuffer(d_bytes, dtype=float)
    out = Comparison(n=int(d.size))
    if d.size:
        out.effect = float(np.median(d))
    if d.size >= 2 and np.any(d != 0):
        # The same difference every trial (sd 0, or rounding's ~1e-16 of it): dz infinite.
        mean, sd = float(np.mean(d)), float(np.std(d, ddof=1))
        out.standardized = mean / sd if sd > 1e-12 * abs(mean) else math.copysign(math.inf, mean)
    if d.size < MIN_PAIRS:  # The median alone: no interval, no test.
        out.reason = f"n<{MIN_PAIRS}"
        return out
    out.effect_ci = bootstrap_median_ci(d)
    if np.all(d == 0):
        out.reason = "identical"
        return out
    if np.ptp(d) == 0:  # The same difference in every trial.
        if grid:
            out.test, out.p = "S", sign_test_p(d)
        else:  # The trials repeat one another.
            out.reason = "Δ constant"
        return out
    out.test, out.normality_p, out.p = choose_and_test(d)
    return out


def trials_for_power(standardized, alpha, power=POWER, most=1000):
    """The fewest pairs at which a two-sided paired t-test at level `alpha` detects a mean
    difference of `standardized` standard deviations (Cohen's dz) with probability `power`
    (noncentral t), and at which a Wilcoxon signed-rank test can reach `alpha` at all (its smallest
    two-sided p with n pairs is 2 / 2^n); None beyond `most` or when dz is 0 or unknown."""
    dz = abs(standardized)
    if not dz > 0:  # 0 or NaN.
        return None
    floor = max(MIN_PAIRS, math.ceil(math.log2(2.0 / alpha)))
    if dz * math.sqrt(floor) > NONCENTRALITY_CERTAIN:
        return floor
    for n in range(floor, most + 1):
        t_crit = stats.t.ppf(1.0 - alpha / 2.0, n - 1)
        nc = dz * math.sqrt(n)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # A far tail of a large effect: 0, as it should be.
            reached = stats.nct.sf(t_crit, n - 1, nc) + stats.nct.cdf(-t_crit, n - 1, nc)
        if reached >= power:
            return n
    return None


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
