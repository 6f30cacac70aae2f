#!/usr/bin/python3
"""Tests of calibench_report.stats against known values: published textbook examples and cases
with a closed form, each computed here without the functions the code calls. Each test names the
mutation of the code it was seen to catch.

Run: PYTHONPATH=python /usr/bin/python3 tests/bench/report_stats_test.py
(ctest: calibench_bench_report_stats_test, labels bench and report).
"""
import io
import itertools
import math
import unittest

import numpy as np
import pandas as pd

from calibench_report import stats as rs
from calibench_report import tables
from calibench_report.sections import corner_bias


def signed_rank_exact_p(d):
    """Two-sided exact p of the Wilcoxon signed-rank statistic by enumerating the 2^n equally
    likely sign assignments of the ranks (no ties, no zeros)."""
    ranks = np.argsort(np.argsort(np.abs(d))) + 1
    w = ranks[np.asarray(d) > 0].sum()
    centre = len(d) * (len(d) + 1) / 4
    extreme = 0
    for signs in itertools.product((0, 1), repeat=len(d)):
        extreme += abs(np.dot(signs, ranks) - centre) >= abs(w - centre) - 1e-9
    return extreme / 2 ** len(d)


def binomial_cdf(k, n, p):
    return sum(math.comb(n, i) * p ** i * (1 - p) ** (n - i) for i in range(k + 1))


def normal_cdf(x):
    return 0.5 * (1 + math.erf(x / math.sqrt(2)))


def lilliefors_statistic(d):
    """Lilliefors' D: the largest distance between the empirical CDF and the normal CDF with the
    sample's mean and standard deviation (n - 1)."""
    x = np.sort(np.asarray(d, dtype=float))
    n = x.size
    z = (x - x.mean()) / x.std(ddof=1)
    f = np.array([normal_cdf(v) for v in z])
    return max(np.max(np.arange(1, n + 1) / n - f), np.max(f - np.arange(n) / n))


class SignedRankTest(unittest.TestCase):
    # Hollander & Wolfe, Nonparametric Statistical Methods (1973), p. 29: Hamilton depression scale
    # of 9 patients before (x) and after (y) a tranquilliser; T+ = 40, exact two-sided p = 0.0391.
    X = np.array([1.83, 0.50, 1.62, 2.48, 1.68, 1.88, 1.55, 3.06, 1.30])
    Y = np.array([0.878, 0.647, 0.598, 2.05, 1.06, 1.29, 1.06, 3.14, 1.29])

    def test_textbook_example_exact_p(self):
        # Mutation tried: stats.wilcoxon(d, method="approx") in signed_rank_p -> p 0.038, fails.
        d = self.X - self.Y
        self.assertAlmostEqual(signed_rank_exact_p(d), 20 / 512, delta=1e-15)  # 0.0390625.
        self.assertAlmostEqual(rs.signed_rank_p(d), 20 / 512, delta=1e-12)

    def test_all_positive_differences_have_p_two_over_two_to_the_n(self):
        # Every difference positive: only the all-plus and all-minus assignments are as extreme,
        # p = 2 / 2^n. A skewed sample, so that Lilliefors sends it to the Wilcoxon test.
        # Mutation tried: choose_and_test returning the t-test's p for "W" -> fails.
        d = np.array([0.01, 0.02, 0.03, 0.05, 0.04, 0.06, 0.07, 0.08, 5.0, 9.0])
        self.assertAlmostEqual(signed_rank_exact_p(d), 2 / 2 ** 10, delta=1e-15)
        c = rs.compare(d)
        self.assertEqual(c.test, "W")
        self.assertAlmostEqual(c.p, 2 / 2 ** 10, delta=1e-12)


class PairedTTest(unittest.TestCase):
    def test_students_sleep_data(self):
        # Student (1908) / Cushny & Peebles: extra sleep of 10 patients under two drugs. R's
        # t.test(extra ~ group, data = sleep, paired = TRUE): t = -4.0621, df = 9,
        # p-value = 0.002833. Mutation tried: an unpaired test in paired_t_p
        # (stats.ttest_ind(d, 0 * d)) -> fails.
        g1 = np.array([0.7, -1.6, -0.2, -1.2, -0.1, 3.4, 3.7, 0.8, 0.0, 2.0])
        g2 = np.array([1.9, 0.8, 1.1, 0.1, -0.1, 4.4, 5.5, 1.6, 4.6, 3.4])
        d = g2 - g1
        t = d.mean() / (d.std(ddof=1) / math.sqrt(d.size))
        self.assertAlmostEqual(t, 4.0621, delta=5e-5)
        self.assertAlmostEqual(rs.paired_t_p(d), 0.002833, delta=5e-7)
        self.assertAlmostEqual(rs.paired_t_p(-d), 0.002833, delta=5e-7)  # Two-sided.


class NormalityChoiceTest(unittest.TestCase):
    # Lilliefors (1967), table 1, n = 10: D's upper quantiles 0.215 (p = 0.20) and 0.258 (0.05).

    def test_a_sample_below_the_table_keeps_the_t_test(self):
        # Normal quantiles of 10 points: D far below 0.215, so p >= 0.20 (the table's top).
        # Mutation tried: lilliefors(d, dist="exp") in normality_p -> fails.
        d = np.array([-1.645, -1.036, -0.674, -0.385, -0.126, 0.126, 0.385, 0.674, 1.036, 1.645])
        self.assertLess(lilliefors_statistic(d), 0.215)
        self.assertGreaterEqual(rs.normality_p(d), 0.2)
        self.assertEqual(rs.choose_and_test(d)[0], "t")

    def test_a_sample_beyond_the_5_percent_point_goes_to_wilcoxon(self):
        d = np.array([0.0, 0.01, 0.02, 0.03, 0.04, 0.05, 0.06, 0.07, 0.08, 3.0])
        self.assertGreater(lilliefors_statistic(d), 0.258)
        self.assertLess(rs.normality_p(d), 0.05)
        self.assertEqual(rs.choose_and_test(d)[0], "W")


class HolmTest(unittest.TestCase):
    def test_hand_worked_example(self):
        # p = 0.01, 0.04, 0.03, 0.005 (m = 4). Sorted: 0.005, 0.01, 0.03, 0.04; times 4, 3, 2, 1:
        # 0.02, 0.03, 0.06, 0.04; running maximum (the step-down's monotonicity): 0.02, 0.03,
        # 0.06, 0.06. An untested comparison is not part of the family (m stays 4).
        # Mutation tried: method="simes-hochberg" (step-up) in holm() -> 0.03, 0.04, 0.04, 0.02,
        # fails; and the untested comparison counted in the family (m = 5) -> fails.
        comparisons = [rs.Comparison(p=p, test="t") for p in (0.01, 0.04, 0.03, 0.005)]
        untested = rs.Comparison(reason="n<5")
        rs.holm(comparisons + [untested])
        np.testing.assert_allclose([c.p_adjusted for c in comparisons], [0.03, 0.06, 0.06, 0.02],
                                   rtol=0, atol=1e-15)
        self.assertTrue(math.isnan(untested.p_adjusted))
        self.assertEqual([c.significant for c in comparisons], [True, False, False, True])

    def test_adjusted_p_is_capped_at_one(self):
        # 0.3 * 3 = 0.9; 0.8 * 2 = 1.6 -> 1; 0.9 * 1, raised to 1 by the running maximum.
        comparisons = [rs.Comparison(p=p, test="W") for p in (0.3, 0.9, 0.8)]
        rs.holm(comparisons)
        np.testing.assert_allclose([c.p_adjusted for c in comparisons], [0.9, 1.0, 1.0],
                                   rtol=0, atol=1e-15)


class BootstrapTest(unittest.TestCase):
    def exact_percentile_interval(self, x):
        """The percentile interval of the ideal bootstrap of the median of n (odd) distinct values:
        P(median* <= x_(k)) = P(Binomial(n, k / n) >= (n + 1) / 2); the 2.5% point is the first
        x_(k) whose probability reaches 0.025, the 97.5% point the first reaching 0.975."""
        x = np.sort(x)
        n = x.size
        cdf = [1 - binomial_cdf((n + 1) // 2 - 1, n, k / n) for k in range(1, n + 1)]
        lo = next(k for k in range(n) if cdf[k] >= 0.025)
        hi = next(k for k in range(n) if cdf[k] >= 0.975)
        return x[lo], x[hi]

    def test_median_interval_equals_the_exact_bootstrap_distribution(self):
        # n = 7: P(<= x_(1)) = 0.010, P(<= x_(2)) = 0.108 -> x_(2); P(<= x_(5)) = 0.892,
        # P(<= x_(6)) = 0.990 -> x_(6). n = 11: x_(3) and x_(9). 2000 resamples sit far from the
        # boundaries (their Monte Carlo error is ~0.003).
        # Mutation tried: method="basic" in bootstrap_median_ci -> (2 median - x_(6), ...), fails;
        # np.mean as the statistic -> fails.
        x7 = np.array([3.1, -0.4, 2.2, 7.5, 0.9, 1.6, 4.8])
        self.assertEqual(self.exact_percentile_interval(x7), (0.9, 4.8))  # x_(2), x_(6).
        self.assertEqual(rs.bootstrap_median_ci(x7), self.exact_percentile_interval(x7))
        x11 = np.array([0.5, 2.5, 1.0, 9.0, 4.0, 3.5, 6.0, 0.25, 8.0, 7.0, 5.0])
        self.assertEqual(self.exact_percentile_interval(x11), (1.0, 7.0))  # x_(3), x_(9).
        self.assertEqual(rs.bootstrap_median_ci(x11), (1.0, 7.0))

    def test_deterministic_and_order_independent(self):
        d = np.random.default_rng(8).normal(size=20)
        first = rs.bootstrap_median_ci(d)
        rs.bootstrap_median_ci(np.random.default_rng(9).normal(size=20))
        self.assertEqual(first, rs.bootstrap_median_ci(d))


class CompareTest(unittest.TestCase):
    def test_no_test_and_why(self):
        self.assertEqual(rs.compare([0.1, 0.2, 0.3, 0.4]).reason, f"n<{rs.MIN_PAIRS}")
        identical = rs.compare(np.zeros(10))
        self.assertEqual((identical.reason, identical.effect, identical.tested),
                         ("identical", 0.0, False))
        self.assertEqual(rs.compare(np.full(8, 0.25)).reason, "Δ constant")

    def test_effect_is_the_median_difference(self):
        d = np.array([0.3, -0.1, 0.5, 0.2, 0.9, 0.4, 0.1])
        self.assertEqual(rs.compare(d).effect, 0.3)

    def test_results_are_copies(self):
        d = np.random.default_rng(7).normal(size=12)
        first = rs.compare(d)
        first.p_adjusted = 0.5
        self.assertTrue(math.isnan(rs.compare(d).p_adjusted))

    def test_pairs_by_seed_and_drops_nan_and_unpaired(self):
        a = pd.Series([1.0, 2.0, np.nan, 4.0], index=[10, 11, 12, 13])
        b = pd.Series([0.5, 0.5, 0.5, 0.5], index=[13, 12, 11, 99])
        np.testing.assert_allclose(sorted(rs.paired_differences(a, b)), [1.5, 3.5])


class VersusTest(unittest.TestCase):
    """The adaptive estimator against a batch method: log ratios paired by seed, and the words."""

    def test_log_ratios_pair_by_seed_and_drop_what_has_no_logarithm(self):
        a = pd.Series([2.0, 4.0, 8.0, 0.0, 1.0], index=[1, 2, 3, 4, 5])
        b = pd.Series([1.0, 1.0, 1.0, 1.0, np.nan], index=[3, 2, 1, 4, 5])
        np.testing.assert_allclose(sorted(rs.log_ratios(a, b)), np.log([2.0, 4.0, 8.0]))

    def test_ratio_words_name_the_better_method_and_its_factor(self):
        # ln ratios of 4 and of 1/4: the batch method's error is 4x smaller, then the adaptive's.
        worse = rs.compare(np.log(np.array([3.0, 4.0, 5.0, 4.0, 4.0, 3.5, 4.5])))
        rs.holm([worse])
        text = tables.ratio_versus_text("adaptive", "ceres", worse, "f·ku error")
        self.assertTrue(text.startswith("ceres beats adaptive by 4× ["), text)
        self.assertIn("in f·ku error, p ", text)
        better = rs.compare(-np.log(np.array([3.0, 4.0, 5.0, 4.0, 4.0, 3.5, 4.5])))
        rs.holm([better])
        self.assertTrue(tables.ratio_versus_text("adaptive", "ceres", better, "e")
                        .startswith("adaptive beats ceres by 4× ["))
        few = rs.compare(np.log(np.array([2.0, 3.0])))
        self.assertIn("not testable (n=2<5)", tables.ratio_versus_text("a", "b", few, "e"))

    def test_time_words_say_who_re_converges_first(self):
        c = rs.compare(np.array([2.0, 3.0, 1.0, 2.0, 2.5, 1.5]))  # batch - adaptive (s).
        rs.holm([c])
        text = tables.time_versus_text("adaptive", "ceres-w2", c, "re-converges")
        self.assertTrue(text.startswith("adaptive re-converges 2 s ["), text)
        self.assertIn(" before ceres-w2, p ", text)
        c = rs.compare(-np.array([2.0, 3.0, 1.0, 2.0, 2.5, 1.5]))
        rs.holm([c])
        self.assertTrue(tables.time_versus_text("adaptive", "ceres-w2", c, "re-converges")
                        .startswith("ceres-w2 re-converges 2 s ["))


class GridTimesTest(unittest.TestCase):
    """Re-convergence times on the frame grid of distinct trials: a constant difference is tested
    by the exact sign test; of trials that repeat one another it is not."""

    def test_constant_difference_of_distinct_trials_gets_the_sign_test(self):
        # Ten trials, each 1.9 s apart: the sign test's two-sided p is 2 / 2^10 (binomial, all
        # ten on one side). Mutation tried: one-sided binomtest -> 1 / 2^10 fails.
        c = rs.compare(np.full(10, 1.9), grid=True)
        self.assertEqual((c.test, c.reason), ("S", ""))
        self.assertAlmostEqual(c.p, 2 / 2**10, places=15)
        other = rs.compare(np.array([0.5, 1.0, -0.2, 0.8, 1.1, 0.3, 0.9]))
        rs.holm([c, other])  # Holm: the smaller p times 2.
        self.assertAlmostEqual(c.p_adjusted, 2 * 2 / 2**10, places=15)
        self.assertEqual(rs.compare(np.full(10, 1.9)).reason, "Δ constant")
        self.assertEqual(rs.compare(np.zeros(10), grid=True).reason, "identical")
        self.assertEqual(rs.sign_test_p([1.0, -1.0, 0.0, 2.0]), 1.0)  # 2 of 3 on one side.

    def test_trials_differ_when_a_continuous_figure_does(self):
        copies = [pd.Series([0.01] * 5), np.full(5, 0.2)]
        self.assertFalse(rs.trials_differ(copies))
        self.assertTrue(rs.trials_differ(copies + [np.array([0.1, np.nan, 0.2])]))
        self.assertFalse(rs.trials_differ([np.array([np.nan, 0.3])]))  # One finite value.

    def test_tie_is_said_in_words(self):
        c = rs.compare(np.zeros(10), grid=True)
        text = tables.time_versus_text("adaptive-reset", "ceres-w2", c, "re-converges")
        self.assertEqual(text, "adaptive-reset and ceres-w2 tie: the same time in every trial (10)")


class PowerTest(unittest.TestCase):
    """The standardized effect and the trials a paired t-test needs for 80% power."""

    def test_standardized_effect_is_mean_over_sample_sd(self):
        # d = 1..5: mean 3, sample variance 10 / 4 = 2.5.
        # Mutation tried: np.std(d) (ddof 0) -> 3 / sqrt(2) fails.
        self.assertAlmostEqual(rs.compare(np.array([1.0, 2, 3, 4, 5])).standardized,
                               3 / math.sqrt(2.5), places=12)
        self.assertEqual(rs.compare(np.full(8, -0.25)).standardized, -math.inf)
        self.assertTrue(math.isnan(rs.compare(np.zeros(6)).standardized))

    def test_pairs_match_published_power_tables(self):
        # G*Power 3.1, "means: difference between two dependent means (matched pairs)", a priori,
        # two tails, alpha 0.05, power 0.80: dz 0.5 -> 34 pairs, 0.8 -> 15, 1.0 -> 10.
        # Mutation tried: a one-sided critical value (1 - alpha) -> 27, 12, 8 fail.
        for dz, pairs in ((0.5, 34), (0.8, 15), (1.0, 10), (-0.8, 15)):
            self.assertEqual(rs.trials_for_power(dz, 0.05), pairs, dz)

    def test_floor_is_where_a_rank_test_can_reach_the_level(self):
        # Wilcoxon's smallest two-sided p with n pairs is 2 / 2^n: at 0.05 / 4 = 0.0125 it takes
        # n = 8 (2 / 2^7 = 0.0156 > 0.0125 >= 2 / 2^8), however large the effect.
        self.assertEqual(rs.trials_for_power(math.inf, 0.05 / 4), 8)
        self.assertEqual(rs.trials_for_power(30.0, 0.05 / 4), 8)
        # At 0.05: 2 / 2^5 = 0.0625 is above it, 2 / 2^6 below: 6, one above stats.MIN_PAIRS.
        self.assertEqual(rs.trials_for_power(30.0, 0.05), 6)
        self.assertIsNone(rs.trials_for_power(0.0, 0.05))
        self.assertIsNone(rs.trials_for_power(math.nan, 0.05))


class CoverageTest(unittest.TestCase):
    def test_coverage_counts_the_trials_inside(self):
        cover, n = rs.coverage([0.5, -1.0, 3.0, np.nan], [1.0, 1.0, 1.0, 1.0])
        self.assertEqual((cover, n), (2 / 3, 3))

    def test_band_is_the_binomial_quantiles(self):
        # 20 trials at 95%: P(X <= 16) = 0.016 < 0.025 <= P(X <= 17) = 0.075, and the upper
        # quantile is 20 (P(X <= 19) = 0.64 < 0.975): [17/20, 1].
        # Mutation tried: stats.binom.interval(level, n, 1 - nominal) -> fails.
        self.assertLess(binomial_cdf(16, 20, 0.95), 0.025)
        self.assertGreaterEqual(binomial_cdf(17, 20, 0.95), 0.025)
        self.assertEqual(rs.coverage_band(20), (17 / 20, 1.0))
        lo = next(k for k in range(101) if binomial_cdf(k, 100, 0.95) >= 0.025)
        hi = next(k for k in range(101) if binomial_cdf(k, 100, 0.95) >= 0.975)
        self.assertEqual(rs.coverage_band(100), (lo / 100, hi / 100))


class NumberFormatTest(unittest.TestCase):
    def test_whole_numbers_read_from_a_csv_are_printed(self):
        # A CSV column of whole numbers reads as int64: the corner study's tag_px and tilt_deg.
        # Mutation seen: finite() accepting only Python's int and float printed them as "–".
        frame = pd.read_csv(io.StringIO("tag_px,tilt_deg,blur\n32,0,0.5\n"))
        self.assertEqual([tables.num(frame[c].iloc[0]) for c in frame], ["32", "0", "0.5"])
        self.assertEqual(tables.num(float("nan")), "–")
        self.assertEqual(tables.num(None), "–")


class CornerStudyMatchTest(unittest.TestCase):
    def test_the_matching_fit_is_lens_aware_then_photometric_never_the_saddle(self):
        # Mutation seen: "the last stage" picked the saddle on corner-square cases (57 of 91
        # cases within the study's bounds instead of 84).
        cases = pd.DataFrame({"case": [0, 0, 0, 1, 1, 1, 1, 2],
                              "stage": ["raw", "photometric", "saddle", "raw", "photometric",
                                        "lens_aware", "saddle", "raw"]})
        picked = corner_bias.matched(cases)
        self.assertEqual(list(zip(picked.case, picked.stage)),
                         [(0, "photometric"), (1, "lens_aware"), (2, "raw")])


if __name__ == "__main__":
    unittest.main()
