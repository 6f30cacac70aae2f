#!/usr/bin/python3
"""The cost of a method-only sweep: N gains against 1 gain plus N - 1 adaptive-only runs.

Usage: gain_cost.py GAIN5_DIR GAIN5_WALL_S GAIN1_DIR GAIN1_WALL_S THREADS
(GAIN5_DIR: the sweep over N gains.) The N - 1 adaptive-only runs are the solves of the other
gains, as timed in GAIN5_DIR's timings.csv:
the rows of the points GAIN1_DIR does not have that were run, not copied (reused = 0): the gain's
instance only, since the others are copied from the first point. Their summed wall time is
divided by the worker threads. Writes GAIN5_DIR/gain_cost.txt
(read by the report) and prints it.
"""
import os
import sys

import pandas as pd

gain5, wall5, gain1, wall1, threads = sys.argv[1], float(sys.argv[2]), sys.argv[3], float(sys.argv[4]), int(sys.argv[5])
t5 = pd.read_csv(os.path.join(gain5, "timings.csv"))
t1 = pd.read_csv(os.path.join(gain1, "timings.csv"))
one_gain = set(t1.scenario.str.replace("gain1_", "gain_", regex=False))
others = t5[(t5.reused == 0) & ~t5.scenario.isin(one_gain)]
adaptive_s = others.wall_ms.sum() / 1000 / threads
reference = wall1 + adaptive_s
ratio = wall5 / reference
n = len(set(s.split("[")[-1] for s in t5.scenario if "oracle" in s))  # Gains per detection kind.
text = (f"Gain sweep, {n} values of alpha (oracle + rendered): {wall5:.1f} s wall. One value: "
        f"{wall1:.1f} s; the other {n - 1} values' adaptive solves: "
        f"{others.wall_ms.sum() / 1000:.1f} s of CPU on {threads} threads = {adaptive_s:.1f} s. "
        f"Ratio {n} gains / (1 gain + {n - 1} adaptive runs) = **{ratio:.2f}** (target <= 1.3): "
        "the frames are rendered and detected once per trial and the batch methods run once.")
open(os.path.join(gain5, "gain_cost.txt"), "w").write(text + "\n")
print(text)
