"""Reading run directories and writing the report's files.

A run directory (`calibench run`) holds runs.csv, summary.csv, schema.json and the other files of
bench/run/run_dir.h; a directory of the corner study (`calibench corner-bias`) holds
corner_bias.csv. Paths shown in the report are relative to the report directory, never absolute.
"""
import dataclasses
import os
from typing import Optional

import pandas as pd

from calibench_report import schema as schema_io

CORNER_BIAS = "corner_bias.csv"
GAIN_COST = "gain_cost.txt"  # scripts/gain_cost.sh's note on a gain sweep's cost.


@dataclasses.dataclass
class RunData:
    dirs: list  # The directories as given.
    schema: schema_io.Schema
    runs: pd.DataFrame  # runs.csv of every directory.
    summary: pd.DataFrame  # summary.csv of every directory.
    timings: pd.DataFrame
    curves: pd.DataFrame
    events: pd.DataFrame
    tracks: pd.DataFrame
    bands: pd.DataFrame  # track_bands.csv.
    configs: list  # config.resolved.yaml texts.
    corner_bias: Optional[pd.DataFrame] = None
    corner_bias_path: str = ""  # As given (see display_path).
    notes: list = dataclasses.field(default_factory=list)  # gain_cost.txt texts.

    def methods(self):
        """Every method instance in the order of first appearance."""
        return list(dict.fromkeys(self.runs.method)) if len(self.runs) else []


def _csv(path, **kwargs):
    if not os.path.exists(path):
        return pd.DataFrame()
    frame = pd.read_csv(path, keep_default_na=False, na_values=["nan"], **kwargs)
    return frame


def _runs(path):
    runs = _csv(path, dtype={"params": str, "message": str, "scenario": str, "sweep": str})
    if len(runs):
        runs["params"] = runs["params"].fillna("")
    return runs


def read(dirs):
    """RunData of the directories; ValueError naming a directory that cannot be read."""
    schemas, frames, configs, notes = [], {}, [], []
    corner, corner_path = None, ""
    names = ("runs", "summary", "timings", "curves", "events", "tracks", "bands")
    files = {"runs": "runs.csv", "summary": "summary.csv", "timings": "timings.csv",
             "curves": "curves.csv", "events": "events.csv", "tracks": "tracks.csv",
             "bands": "track_bands.csv"}
    for d in dirs:
        if not os.path.isdir(d):
            raise ValueError(f"{d}: not a directory")
        if os.path.exists(os.path.join(d, CORNER_BIAS)) and corner is None:
            corner_path = os.path.join(d, CORNER_BIAS)
            corner = _csv(corner_path)
        if not os.path.exists(os.path.join(d, "runs.csv")):
            if corner is not None:
                continue  # A directory of the corner study only.
            raise ValueError(f"{d}: no runs.csv (not a calibench run directory)")
        try:
            schemas.append(schema_io.read(d))
            for name in names:
                reader = _runs if name == "runs" else _csv
                frames.setdefault(name, []).append(reader(os.path.join(d, files[name])))
        except (OSError, pd.errors.ParserError, schema_io.SchemaError) as e:
            raise ValueError(f"{d}: {e}") from e
        config = os.path.join(d, "config.resolved.yaml")
        if os.path.exists(config):
            with open(config, encoding="utf-8") as f:
                configs.append(f.read())
        cost = os.path.join(d, GAIN_COST)
        if os.path.exists(cost):
            with open(cost, encoding="utf-8") as f:
                notes.append(f.read().strip())

    def concat(name):
        parts = [f for f in frames.get(name, []) if len(f)]
        return pd.concat(parts, ignore_index=True) if parts else pd.DataFrame()

    return RunData(dirs=list(dirs), schema=schema_io.merge(schemas), runs=concat("runs"),
                   summary=concat("summary"), timings=concat("timings"), curves=concat("curves"),
                   events=concat("events"), tracks=concat("tracks"), bands=concat("bands"),
                   configs=configs, corner_bias=corner, corner_bias_path=corner_path,
                   notes=notes)


def display_path(path, out):
    """`path` as the report shows it: relative to the report directory `out`."""
    return os.path.relpath(os.path.abspath(path), os.path.abspath(out))


def write_text(path, text):
    """Writes `text` to `path` atomically (PATH.tmp, then rename)."""
    tmp = path + ".tmp"
    with open(tmp, "w", encoding="utf-8") as f:
        f.write(text)
    os.replace(tmp, path)
