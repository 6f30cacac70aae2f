#!/usr/bin/python3
"""How `calibench report` finds its Python: python3 on PATH with the package of a build tree that
was copied elsewhere, an installed package (pip install into a venv with the system's modules),
and the errors that name what is missing (the package, the interpreter).

Run: /usr/bin/python3 tests/bench/report_python_test.py build/bench/calibench
(ctest: calibench_bench_report_python_test, labels bench and report; about 15 s).
"""
import os
import shutil
import stat
import subprocess
import sys
import tempfile
import unittest

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
CALIBENCH = None  # The binary, from the command line.


def clean_env(**extra):
    """The environment without any setting that points calibench at a package or interpreter."""
    env = {k: v for k, v in os.environ.items()
           if k not in ("PYTHONPATH", "CALIBENCH_PYTHON", "CALIBENCH_REPORT_PYTHONPATH")}
    env.update(extra)
    return env


class ReportPythonTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        cls.run_dir = os.path.join(cls.tmp.name, "run")
        subprocess.run([CALIBENCH, "run", os.path.join(ROOT, "tests/bench/report/tiny.yaml"),
                        "--out", cls.run_dir, "--quiet"], check=True, capture_output=True)
        # The binary alone, with no package beside it.
        cls.bare = os.path.join(cls.tmp.name, "bare", "calibench")
        os.makedirs(os.path.dirname(cls.bare))
        shutil.copy2(CALIBENCH, cls.bare)

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def report(self, calibench, out, *options, env=None):
        out = os.path.join(self.tmp.name, out)
        result = subprocess.run([calibench, "report", self.run_dir, "--out", out, *options],
                                capture_output=True, text=True, env=env or clean_env())
        return result, os.path.join(out, "report.md")

    def test_python3_on_path_and_a_copied_build_tree(self):
        # BUILD/bench/calibench and BUILD/python (CMake's copy of the package), moved elsewhere.
        build = os.path.dirname(os.path.dirname(os.path.abspath(CALIBENCH)))
        copy = os.path.join(self.tmp.name, "moved_build")
        os.makedirs(os.path.join(copy, "bench"))
        shutil.copy2(CALIBENCH, os.path.join(copy, "bench", "calibench"))
        shutil.copytree(os.path.join(build, "python"), os.path.join(copy, "python"))
        # A python3 first on PATH that leaves a mark, then runs the system's.
        bin_dir = os.path.join(self.tmp.name, "path_bin")
        os.makedirs(bin_dir)
        mark = os.path.join(self.tmp.name, "python3_ran")
        wrapper = os.path.join(bin_dir, "python3")
        with open(wrapper, "w", encoding="utf-8") as f:
            f.write(f"#!/bin/sh\ntouch '{mark}'\nexec {sys.executable} \"$@\"\n")
        os.chmod(wrapper, os.stat(wrapper).st_mode | stat.S_IXUSR)
        env = clean_env(PATH=bin_dir + os.pathsep + os.environ.get("PATH", "/usr/bin:/bin"))
        result, md = self.report(os.path.join(copy, "bench", "calibench"), "out_path", env=env)
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertTrue(os.path.exists(mark), "python3 on PATH was not used")
        with open(md, encoding="utf-8") as f:
            self.assertTrue(f.read().startswith("# calibench report\n"))

    def test_installed_package(self):
        venv = os.path.join(self.tmp.name, "venv")
        subprocess.run([sys.executable, "-m", "venv", "--system-site-packages", venv], check=True,
                       capture_output=True)
        source = os.path.join(self.tmp.name, "python_src")  # pip builds in its source folder.
        shutil.copytree(os.path.join(ROOT, "python"), source,
                        ignore=shutil.ignore_patterns("__pycache__", "build", "*.egg-info"))
        pip = subprocess.run([os.path.join(venv, "bin", "pip"), "install", "--no-deps",
                              "--no-build-isolation", "--no-index", source],
                             capture_output=True, text=True)
        self.assertEqual(pip.returncode, 0, pip.stdout + pip.stderr)
        python = os.path.join(venv, "bin", "python")
        result, md = self.report(self.bare, "out_venv", "--python", python)
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertTrue(os.path.exists(md))

    def test_missing_package_is_named(self):
        result, _ = self.report(self.bare, "out_none", "--python", sys.executable)
        self.assertEqual(result.returncode, 2, result.stderr)
        self.assertIn("cannot import calibench_report", result.stderr)
        self.assertIn("pip install --no-deps ./python", result.stderr)

    def test_missing_interpreter_is_named(self):
        result, _ = self.report(self.bare, "out_none",
                                env=clean_env(CALIBENCH_PYTHON="/nonexistent/python3"))
        self.assertEqual(result.returncode, 2, result.stderr)
        self.assertIn("/nonexistent/python3 (cannot be run)", result.stderr)


if __name__ == "__main__":
    CALIBENCH = os.path.abspath(sys.argv.pop(1)) if len(sys.argv) > 1 else os.path.join(
        ROOT, "build", "bench", "calibench")
    unittest.main()
