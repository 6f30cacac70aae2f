#!/usr/bin/python3
"""Tests of scripts/report_stats.py (the report's paired tests, bootstrap, Holm, coverage) and a
smoke test of scripts/report.py on a small synthetic run directory.

Run: /usr/bin/python3 tests/bench/report_stats_test.py   (ctest: calibench_bench_report_stats_test)
"""
import os
import subprocess
import sys
import tempfile
import unittest

import numpy as np
import pandas as pd
from scipy import stats
from statsmodels.stats.multitest import multipletests

SCRIPTS = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scripts")
sys.path.insert(0, SCRIPTS)
import report_stats as rs  # noqa: E402

EXACT = 1e-12  # The same computation through another route: equal up to rounding.


class PairedDifferencesTest(unittest.TestCase):
    def test_pairs_by_seed_and_drops_nan_and_unpaired(self):
        a = pd.Series([1.0, 2.0, np.nan, 4.0], index=[10, 11, 12, 13])
        b = pd.Series([0.5, 0.5, 0.5, 0.5], index=[13, 12, 11, 99])
        # Common seeds 11, 12, 13; seed 12 has a NaN in a.
        np.testing.assert_allclose(sorted(rs.paired_differences(a, b)), [1.5, 3.5])

    def test_same_index_fast_path(self):
        a = pd.Series([1.0, 2.0, 3.0], index=[1, 2, 3])
        b = pd.Series([1.0, 1.0, np.inf], index=[1, 2, 3])
        np.testing.assert_allclose(rs.paired_differences(a, b), [0.0, 1.0])


class CompareTest(unittest.TestCase):
    def test_too_few_pairs(self):
        c = rs.compare([0.1, 0.2, 0.3, 0.4])
        self.assertFalse(c.tested)
        self.assertEqual(c.reason, f"n<{rs.MIN_PAIRS}")
        self.assertEqual(c.n, 4)

    def test_identical_series(self):
        c = rs.compare(np.zeros(10))
        self.assertFalse(c.tested)
        self.assertEqual(c.reason, "identical")
        self.assertEqual(c.effect, 0.0)

    def test_constant_difference_is_not_tested(self):
        c = rs.compare(np.full(8, 0.25))
        self.assertFalse(c.tested)
        self.assertEqual(c.reason, "Δ constant")

    def test_normal_differences_use_the_paired_t_test(self):
        d = np.random.default_rng(3).normal(0.3, 1.0, size=40)
        c = rs.compare(d)
        self.assertEqual(c.test, "t")
        self.assertGreaterEqual(c.normality_p, rs.NORMALITY_LEVEL)
        # ttest_1samp on the differences equals ttest_rel on the pairs.
        b = np.random.default_rng(4).normal(size=40)
        self.assertAlmostEqual(c.p, stats.ttest_rel(d + b, b).pvalue, delta=1e-9)
        self.assertAlmostEqual(c.p, stats.ttest_1samp(d, 0).pvalue, delta=EXACT)

    def test_skewed_differences_use_wilcoxon(self):
        d = np.random.default_rng(5).exponential(1.0, size=40) ** 3
        c = rs.compare(d)
        self.assertEqual(c.test, "W")
        self.assertLess(c.normality_p, rs.NORMALITY_LEVEL)
        self.assertAlmostEqual(c.p, stats.wilcoxon(d).pvalue, delta=EXACT)

    def test_effect_is_the_median_inside_its_interval(self):
        d = np.random.default_rng(6).normal(1.0, 0.5, size=30)
        c = rs.compare(d)
        self.assertAlmostEqual(c.effect, np.median(d), delta=EXACT)
        self.assertLessEqual(c.effect_ci[0], c.effect)
        self.assertGreaterEqual(c.effect_ci[1], c.effect)

    def test_results_are_copies(self):
        d = np.random.default_rng(7).normal(size=12)
        first = rs.compare(d)
        first.p_adjusted = 0.5
        self.assertTrue(np.isnan(rs.compare(d).p_adjusted))


class BootstrapTest(unittest.TestCase):
    def test_deterministic_and_order_independent(self):
        d = np.random.default_rng(8).normal(size=20)
        other = np.random.default_rng(9).normal(size=20)
        first = rs.bootstrap_median_ci(d)
        rs.bootstrap_median_ci(other)
        self.assertEqual(first, rs.bootstrap_median_ci(d))

    def test_matches_a_plain_loop(self):
        d = np.random.default_rng(10).normal(size=9)
        rng = np.random.default_rng(rs.BOOTSTRAP_SEED)
        idx = rng.integers(0, d.size, size=(rs.BOOTSTRAP_RESAMPLES, d.size))
        medians = [np.median(d[row]) for row in idx]
        expected = np.quantile(medians, [0.025, 0.975])
        np.testing.assert_allclose(rs.bootstrap_median_ci(d), expected, rtol=0, atol=EXACT)

    def test_interval_narrows_with_more_data(self):
        rng = np.random.default_rng(11)
        small, large = rng.normal(size=10), rng.normal(size=400)
        width = lambda ci: ci[1] - ci[0]  # noqa: E731
        self.assertLess(width(rs.bootstrap_median_ci(large)), width(rs.bootstrap_median_ci(small)))


class HolmTest(unittest.TestCase):
    def test_known_values_and_untested_left_out(self):
        comparisons = [rs.Comparison(p=p, test="t") for p in (0.01, 0.04, 0.03)]
        untested = rs.Comparison(reason="n<5")
        rs.holm(comparisons + [untested])
        # Holm: sorted 0.01*3, 0.03*2, 0.04*1 -> 0.03, 0.06, max(0.06, 0.04) = 0.06.
        np.testing.assert_allclose([c.p_adjusted for c in comparisons], [0.03, 0.06, 0.06])
        self.assertTrue(np.isnan(untested.p_adjusted))

    def test_equals_statsmodels(self):
        p = np.random.default_rng(12).uniform(0, 0.2, size=15)
        comparisons = [rs.Comparison(p=x, test="W") for x in p]
        rs.holm(comparisons)
        expected = multipletests(p, method="holm")[1]
        np.testing.assert_allclose([c.p_adjusted for c in comparisons], expected, atol=EXACT)


class BandsTest(unittest.TestCase):
    def test_abs_band(self):
        med, lo, hi = rs.abs_band([-1.0, 2.0, np.nan, -3.0, 4.0, 5.0])
        self.assertEqual(med, 3.0)
        self.assertAlmostEqual(lo, np.quantile([1, 2, 3, 4, 5], 0.025), delta=EXACT)
        self.assertAlmostEqual(hi, np.quantile([1, 2, 3, 4, 5], 0.975), delta=EXACT)
        self.assertTrue(all(np.isnan(rs.abs_band([np.nan]))))

    def test_rmse(self):
        self.assertAlmostEqual(rs.rmse([3.0, -4.0, np.nan]), np.sqrt(12.5), delta=EXACT)

    def test_coverage(self):
        cover, n = rs.coverage([0.5, -1.0, 3.0, np.nan], [1.0, 1.0, 1.0, 1.0])
        self.assertEqual(n, 3)
        self.assertAlmostEqual(cover, 2 / 3, delta=EXACT)

    def test_coverage_band(self):
        lo, hi = rs.coverage_band(20)
        self.assertEqual((lo, hi), (17 / 20, 1.0))
        lo, hi = rs.coverage_band(1000)
        self.assertLess(lo, 0.95)
        self.assertGreater(hi, 0.95)
        self.assertLess(hi - lo, 0.03)  # ~ 2 * 1.96 * sqrt(0.95 * 0.05 / 1000) = 0.027.


def synthetic_runs(n_trials=6):
    """Two sweeps (noise_oracle; gain_oracle with axis methods.fast.alpha), methods 'slow' and
    'fast' and 'twin' (= slow's intrinsics), with n_frames_used / n_obs_used."""
    rng = np.random.default_rng(0)
    rows = []
    for sweep, field, values in (("noise_oracle", "noise.pixel_sigma_px", (0.1, 1.0)),
                                 ("gain_oracle", "methods.fast.alpha", (10.0, 1000.0))):
        for point, value in enumerate(values):
            for trial in range(n_trials):
                seed = 1000 * point + trial
                slow = rng.normal(0, value, size=12)
                for method, scale in (("slow", 1.0), ("fast", 3.0), ("twin", 1.0)):
                    e = slow * scale if method != "fast" else rng.normal(0, 3 * value, size=12)
                    if method == "twin":
                        e[5:] = rng.normal(0, 2 * value, size=7)  # Own extrinsics.
                    rows.append(dict(
                        scenario=f"{sweep}[{field}={value:g}]", sweep=sweep, point=point,
                        params=f"{field}={value:g}", n_points=100, trial=trial, seed=seed,
                        method=method, status="ok", err_fku=e[0], err_fkv=e[1], err_u0=e[2],
                        err_v0=e[3], err_phi_deg=0.0 if method != "fast" else e[4],
                        err_roll_deg=e[5], err_pitch_deg=e[6], err_yaw_deg=e[7],
                        rot_err_deg=abs(e[8]), err_xc_norm=abs(e[9]), rms_reproj_px=abs(e[10]),
                        converge_time_s=5.0 if method == "fast" and trial % 2 else np.nan,
                        corner_rms_px=np.nan,
                        std_fku=value if method != "fast" else np.nan, std_fkv=np.nan,
                        std_u0=np.nan, std_v0=np.nan, std_phi_deg=np.nan,
                        crlb_fku=value if method == "slow" else np.nan,
                        message="", n_frames_used=30 if method != "fast" else 240,
                        n_obs_used=30 * 100 if method != "fast" else 240 * 100))
    return pd.DataFrame(rows)


class ReportSmokeTest(unittest.TestCase):
    def run_report(self, runs):
        with tempfile.TemporaryDirectory() as tmp:
            run_dir, out = os.path.join(tmp, "run"), os.path.join(tmp, "report")
            os.makedirs(run_dir)
            runs.to_csv(os.path.join(run_dir, "runs.csv"), index=False, na_rep="nan")
            pd.DataFrame(columns=["scenario", "method", "wall_ms"]).to_csv(
                os.path.join(run_dir, "timings.csv"), index=False)
            result = subprocess.run(
                [sys.executable, os.path.join(SCRIPTS, "report.py"), "--out", out, run_dir],
                capture_output=True, text=True)
            self.assertEqual(result.returncode, 0, result.stderr)
            self.assertFalse(os.path.exists(os.path.join(out, "report.md.tmp")))
            for png in ("error_vs_noise.png", "error_vs_gain.png", "gain_tradeoff.png"):
                self.assertTrue(os.path.exists(os.path.join(out, png)), png)
            with open(os.path.join(out, "report.md")) as f:
                return f.read()

    def test_sections_and_data_used(self):
        md = self.run_report(synthetic_runs())
        for heading in ("## noise", "### noise_oracle", "#### noise_oracle: noise.pixel_sigma_px=1",
                        "## Gain trade-off", "## Reported uncertainty"):
            self.assertIn(heading, md)
        self.assertIn("| slow | 6 | 30 | 3000 |", md)  # Trials, median frames and observations.
        self.assertIn("= slow", md)  # twin's intrinsics repeat slow's.
        self.assertIn("Holm", md)
        self.assertIn("fast's rows have no CRLB; the bound is slow's", md)
        self.assertIn("| 50% |", md)  # fast converged in half of its trials.

    def test_small_n_without_data_used_columns(self):
        runs = synthetic_runs(n_trials=3).drop(columns=["n_frames_used", "n_obs_used"])
        md = self.run_report(runs)
        self.assertIn("| slow | 3 | not recorded | not recorded |", md)
        self.assertIn(f"n/a (n=3<{rs.MIN_PAIRS})", md)


if __name__ == "__main__":
    unittest.main()
