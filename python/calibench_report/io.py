"""Reading run directories and writing the report's files.

A run directory (`calibench run`) holds schema.json and the files it lists (runs.csv, summary.csv,
...: bench/run/run_dir.h), read as it declares them; a directory of the corner study (`calibench
corner-bias`) holds corner_bias.csv. Paths shown in the report are relative to the report directory, never absolute.
"""
import dataclasses
import functools
import os
from typing import Optional

import pandas as pd
import yaml

from calibench_report import schema as schema_io

CORNER_BIAS = "corner_bias.csv"
GAIN_COST = "gain_cost.txt"  # scripts/gain_cost.sh's note on a gain sweep's cost.


@dataclasses.dataclass
class RunData:
    dirs: list  # The directories as given.
    schema: schema_io.Schema
    tables: dict  # Every file schema.json lists, by its name without .csv: its rows, all dirs.
    configs: list  # config.resolved.yaml texts.
    corner_bias: Optional[pd.DataFrame] = None
    corner_bias_path: str = ""  # As given (see display_path).
    notes: list = dataclasses.field(default_factory=list)  # gain_cost.txt texts.

    def table(self, name):
        """The rows of schema.json's file NAME.csv (empty when absent)."""
        return self.tables.get(name, pd.DataFrame())

    runs = property(lambda self: self.table("runs"))
    summary = property(lambda self: self.table("summary"))
    timings = property(lambda self: self.table("timings"))
    curves = property(lambda self: self.table("curves"))
    events = property(lambda self: self.table("events"))
    tracks = property(lambda self: self.table("tracks"))
    bands = property(lambda self: self.table("track_bands"))

    def methods(self):
        """Every method instance in the order of first appearance."""
        return list(dict.fromkeys(self.runs.method)) if len(self.runs) else []

    @functools.cached_property
    def families(self):
        """{method instance: its type's family} (adaptive, batch, filter: schema.json's
        methods), from the instances of config.resolved.yaml; an instance named twice keeps its
        first type."""
        out = {}
        for text in self.configs:
            for scenario in (yaml.safe_load(text) or {}).get("scenarios", []):
                for m in scenario.get("methods", []) or []:
                    t = self.schema.method_type(m.get("type"))
                    if t is not None and m.get("name") not in out:
                        out[m.get("name")] = t.family
        return out

    def of_family(self, methods, family):
        """The instances of `methods` whose type is of `family`, in their order."""
        return [m for m in methods if self.families.get(m) == family]


def _csv(path, **kwargs):
    if not os.path.exists(path):
        return pd.DataFrame()
    frame = pd.read_csv(path, keep_default_na=False, na_values=["nan"], **kwargs)
    return frame


def _table(path, columns):
    """A file schema.json lists (columns: its (name, unit, doc)); its text columns as text.
    Empty when absent."""
    text = [name for name, _, _ in columns if name in schema_io.TEXT_COLUMNS]
    frame = _csv(path, dtype={c: str for c in text})
    for c in text:
        if c in frame and frame[c].isna().any():
            frame[c] = frame[c].fillna("")
    return frame


def read(dirs):
    """RunData of the directories; ValueError naming a directory that cannot be read."""
    schemas, frames, configs, notes = [], {}, [], []
    corner, corner_path = None, ""
    for d in dirs:
        if not os.path.isdir(d):
            raise ValueError(f"{d}: not a directory")
        if os.path.exists(os.path.join(d, CORNER_BIAS)) and corner is None:
            corner_path = os.path.join(d, CORNER_BIAS)
            corner = _csv(corner_path)
        if not os.path.exists(os.path.join(d, schema_io.SCHEMA_FILE)):
            if corner is not None:
                continue  # A directory of the corner study only.
            raise ValueError(f"{d}: no {schema_io.SCHEMA_FILE} (not a calibench run directory, or "
                             "one written before it: run the configuration again)")
        try:
            schema = schema_io.read(d)
            schemas.append(schema)
            for file, columns in schema.files.items():
                frames.setdefault(file, []).append(_table(os.path.join(d, file), columns))
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

    def concat(parts):
        parts = [f for f in parts if len(f)]
        return pd.concat(parts, ignore_index=True) if parts else pd.DataFrame()

    tables = {os.path.splitext(file)[0]: concat(parts) for file, parts in frames.items()}
    return RunData(dirs=list(dirs), schema=schema_io.merge(schemas), tables=tables,
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
