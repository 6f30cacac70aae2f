#!/usr/bin/python3
"""The report end to end: `calibench run` on small runs with their roles
(tests/bench/report/all.yaml: a noise sweep, a gain sweep, a load step), then `calibench report`
(python3 -m calibench_report); checks what a reader sees first and what must never appear.

Run: /usr/bin/python3 tests/bench/report_test.py build/bench/calibench
(ctest: calibench_bench_report_test, labels bench and report).
"""
import os
import re
import subprocess
import sys
import tempfile
import unittest

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
CALIBENCH = None  # The binary, from the command line.


class ReportTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        run = os.path.join(cls.tmp.name, "run")
        cls.out = os.path.join(cls.tmp.name, "report")
        subprocess.run([CALIBENCH, "run", os.path.join(ROOT, "tests/bench/report/all.yaml"),
                        "--out", run, "--quiet", "--threads", "2"], check=True,
                       capture_output=True)
        cls.result = subprocess.run([CALIBENCH, "report", run, "--out", cls.out],
                                    capture_output=True, text=True)
        cls.pages = {}
        for base, _, files in os.walk(cls.out):
            for f in files:
                if f.endswith(".md"):
                    path = os.path.join(base, f)
                    with open(path, encoding="utf-8") as text:
                        cls.pages[os.path.relpath(path, cls.out)] = text.read()
        cls.md = cls.pages.get("report.md", "")

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def test_runs_and_warns_of_nothing(self):
        self.assertEqual(self.result.returncode, 0, self.result.stderr)
        # numpy's RuntimeWarnings (a median of an empty slice, ...) and any other warning.
        # Mutation tried: np.nanmedian in sections/dynamic.py median() -> "All-NaN slice
        # encountered" (the growing window's first segment), fails. Absolute paths: io.py's
        # display_path returning os.path.abspath fails test_no_absolute_path_of_the_machine.
        self.assertNotIn("Warning", self.result.stderr)
        self.assertFalse([f for f in os.listdir(self.out) if f.endswith(".tmp")])

    def test_opens_with_the_answers(self):
        headings = re.findall(r"^(#+) (.*)$", self.md, flags=re.M)
        self.assertEqual(headings[0], ("#", "calibench report"))
        self.assertEqual(headings[1], ("##", "Verdicts: the adaptive estimator against batch "
                                             "calibration"))
        self.assertEqual(headings[2], ("##", "The answers"))
        questions = [h for level, h in headings[3:9]]
        self.assertEqual([q.split(":")[0] for q in questions],
                         ["Pixel noise", "Feature points", "Adaptive gain",
                          "A calibration that changes", "A camera rig", "Detection"])
        answers = self.md.split("## How to read this report")[0]
        # Each question answered here is a table with a winner (or "none significantly") and a
        # figure; the absent ones say so.
        self.assertRegex(answers, r"\| noise +\| f·ku \(px\) +\| (\*\*\w+\*\*|none significantly)")
        self.assertRegex(answers, r"\| gain +\| adaptive +\| f·ku \(px\) +\| (\*\*alpha = |none)")
        self.assertRegex(answers, r"\| step +\| pitch at 5 s +\|")
        self.assertIn("not testable (n=2<5)", answers)
        self.assertIn("Not in these runs.", answers)  # Points, the rig and detection.
        # The verdicts: the adaptive estimator against the best batch method, in plain words,
        # with the ratio's interval and p; the load step's 2 trials are not testable.
        verdicts = self.md.split("## The answers")[0]
        self.assertRegex(verdicts, r"- \*\*Pixel noise\*\*: noise: (not significant: )?\w+ "
                                   r"beats \w+ by [0-9.]+× \[[0-9.]+, [0-9.]+\] in f·ku error, "
                                   r"(p [0-9.e-]+|p < 0.001) \(")
        self.assertRegex(verdicts, r"- \*\*Adaptive gain\*\*: gain: .*adaptive at alpha = ")
        self.assertRegex(verdicts, r"- \*\*A calibration that changes\*\*: step: .* "
                                   r"re-converges .*not testable \(n=2<5\)")
        self.assertNotIn("Feature points**", verdicts)  # No points sweep in these runs.
        # Under them the trials against the effects: a row per verdict comparison with its pairs
        # (the step's 2 trials; the noise sweep's trials pooled over its points).
        self.assertIn("| pairs for 80% power", verdicts)
        self.assertRegex(verdicts, r"\| Pixel noise +\| noise +\| [0-9]+ +\| [0-9.e∞-]+ +\| ")
        self.assertRegex(verdicts, r"\| A calibration that changes +\| step +\| 2 +\| ")
        self.assertRegex(answers, r"\| noise +\| f·ku \(px\) .* beats .* in f·ku error")
        for figure in ("answer_noise.png", "answer_gain.png", "tracking_pareto.png"):
            self.assertIn(f"]({figure})", answers)
            self.assertTrue(os.path.exists(os.path.join(self.out, figure)), figure)

    def test_per_point_tables_are_in_the_appendix(self):
        self.assertNotIn("\n## noise.pixel_sigma_px=", self.md)
        self.assertIn("](appendix/noise.md)", self.md)
        page = self.pages["appendix/noise.md"]
        self.assertIn("## noise.pixel_sigma_px=0.25", page)
        self.assertIn("[Back to the report](../report.md)", page)
        self.assertRegex(page, r"\| dlt +\| 6 +\| 20 +\| 600 ")  # Trials, frames, observations.
        self.assertLess(len(self.md.splitlines()), 200)

    def test_no_absolute_path_of_the_machine(self):
        for name, text in self.pages.items():
            self.assertNotIn(self.tmp.name, text, name)
            self.assertIsNone(re.search(r"(^|[\s(`])/(tmp|home|root|work|usr)/", text), name)
        self.assertIn("Run directories (relative to this report): ../run.", self.md)

    def test_tracking_figure_and_sections(self):
        for heading in ("## Error against the pixel noise", "## Gain trade-off",
                        "## Dynamic calibration", "## Appendix"):
            self.assertIn(heading, self.md)
        self.assertTrue(os.path.exists(os.path.join(self.out, "tracking_step.png")))


    def test_projection_section(self):
        # The noise sweep's methods: ceres predicts its projection error (a finite RMS ratio),
        # the adaptive estimator and the DLT report no covariance; the load step (its truth
        # changes) is not in it.
        section = self.md.split("## Where each method's image projects right")[1].split("\n## ")[0]
        self.assertRegex(section,
                         r"\| noise +\| ceres +\| [0-9.e-]+ +\| [0-9.]+ +\| \w+ +\| 12 +\|")
        self.assertRegex(section,
                         r"\| noise +\| adaptive +\| [0-9.e-]+ +\| – +\| no covariance +\|")
        self.assertNotIn("| step ", section)


class RigReportTest(unittest.TestCase):
    """A rig run (tests/bench/rig/short_rig.yaml: a knock of camera 1 at 15 s, 2 trials) reported
    with a sweep (tests/bench/report/noise.yaml's: summary.csv without the rig's camera column),
    as ./scripts/bench reports them: the first page answers the rig question from rig.csv, the rig
    section has its table, and the sweep's section reads camera 0's rows of the rig's summary."""

    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        run = os.path.join(cls.tmp.name, "rig")
        sweep = os.path.join(cls.tmp.name, "noise")
        out = os.path.join(cls.tmp.name, "report")
        subprocess.run([CALIBENCH, "run", os.path.join(ROOT, "tests/bench/rig/short_rig.yaml"),
                        "--out", run, "--quiet", "--threads", "2"], check=True,
                       capture_output=True)
        subprocess.run([CALIBENCH, "run", os.path.join(ROOT, "tests/bench/report/noise.yaml"),
                        "--out", sweep, "--quiet", "--threads", "2"], check=True,
                       capture_output=True)
        cls.result = subprocess.run([CALIBENCH, "report", sweep, run, "--out", out],
                                    capture_output=True, text=True)
        with open(os.path.join(out, "report.md"), encoding="utf-8") as f:
            cls.md = f.read()

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def test_answers_the_rig_question(self):
        self.assertEqual(self.result.returncode, 0, self.result.stderr)
        self.assertNotIn("Warning", self.result.stderr)
        answers = self.md.split("## How to read this report")[0]
        rig = answers.split("### A camera rig")[1].split("###")[0]
        # Its row: the scenario and camera, 2 trials, the first to re-converge with its median
        # (s) and the closest once settled with its steady error (deg), and why no p.
        self.assertRegex(rig, r"\| short_step, camera 1 +\| 2 +\| [\w-]+ \([\d.]+ s\) +\|")
        self.assertRegex(rig, r"\| [\w-]+ \([\d.e-]+ deg\) +\|")
        self.assertIn("not testable (n=2<5)", rig)

    def test_sweep_beside_the_rig(self):
        self.assertIn("## Error against the pixel noise", self.md)

    def test_rig_section_table(self):
        self.assertIn("## Camera rigs", self.md)
        self.assertIn("### short_step, camera 1 against camera 0 (2 trials)", self.md)
        self.assertIn("Not testable: 2 trials, a paired test needs 5.", self.md)


if __name__ == "__main__":
    CALIBENCH = os.path.abspath(sys.argv.pop(1)) if len(sys.argv) > 1 else os.path.join(
        ROOT, "build", "bench", "calibench")
    unittest.main()
