"""schema.json of a run directory (bench/run/schema.h): the quantities, the sweeps' roles and
what the method types declare.

The report knows no quantity, column, sweep or method type by name: it takes them from here. A
quantity is one entry of calibench's metric table (metrics/metric_table.h) or an output a method
type declares (methods/method.h); a sweep is one swept scenario of the configuration with the role
its config gave it (`report: {role: ...}`); a method type lists its outputs and its windup law.
"""
import dataclasses
import json
import os
from typing import Optional

SCHEMA_FILE = "schema.json"
# The columns that hold names or free text, wherever a file has them: read as text even when a
# value looks like a number (schema.json names each file's columns and units, not their types).
TEXT_COLUMNS = ("scenario", "sweep", "params", "message")


@dataclasses.dataclass(frozen=True)
class Quantity:
    name: str  # Unit included: fku_px.
    unit: str  # "px", "deg", "m", "s"; "" when dimensionless.
    label: str  # f·ku
    doc: str
    columns: tuple  # ((kind, column), ...): kind value | error | std | crlb.
    tracked: bool
    summary: Optional[str]  # None | "statistics" | "with_rmse".
    summary_metric: Optional[str]  # Its `metric` in summary.csv.
    ranked: bool  # Methods are compared on it.
    target: Optional[float]  # Algers 2018's bound (§1.2) on the 97.5th percentile of |error|.
    headline: bool  # The first page answers on it.
    # None | "error" (proj_err_px) | "ratio" (proj_err_ratio): the projection section reads it
    # (absent from run directories written before the projection error).
    projection: Optional[str] = None

    def column(self, kind):
        """Its runs.csv column of a kind (value, error, std, crlb), or None."""
        return dict(self.columns).get(kind)

    @property
    def compared(self):
        """The column the methods are compared on: its error, or its value (an error already)."""
        return self.column("error") or self.column("value")

    @property
    def unit_text(self):
        return {"deg": "°", "": ""}.get(self.unit, self.unit)

    @property
    def title(self):
        return f"{self.label} ({self.unit_text})" if self.unit else self.label

    @property
    def is_angle(self):
        return self.unit == "deg"


@dataclasses.dataclass(frozen=True)
class Sweep:
    name: str
    role: str  # noise | points | gain | dynamic | "" (none).
    detections: str  # oracle | rendered.
    axes: tuple  # The swept fields.
    points: int
    trials: int
    tracks: bool

    @property
    def swept(self):
        return bool(self.axes)


@dataclasses.dataclass(frozen=True)
class WindupLaw:
    """After a step of the truth at t0 the error decays as (t0/t)^a: a is the instance's option
    `exponent`; the law holds when its options `only_when_zero` are all 0."""
    exponent: str
    only_when_zero: tuple


@dataclasses.dataclass(frozen=True)
class MethodType:
    name: str  # As configs spell it (an instance's `type`).
    family: Optional[str]  # adaptive, batch, filter (methods/registry.h MethodFamily); None: not
    # declared (a run directory written before families were).
    outputs: tuple  # The names of the quantities it declares.
    windup: Optional[WindupLaw]


@dataclasses.dataclass(frozen=True)
class Schema:
    quantities: tuple
    sweeps: tuple
    files: dict  # file -> ((name, unit, doc), ...)
    methods: tuple = ()  # MethodType, in registry order.

    def method_type(self, name):
        return next((t for t in self.methods if t.name == name), None)

    def quantity(self, name):
        return next((q for q in self.quantities if q.name == name), None)

    def ranked(self):
        return [q for q in self.quantities if q.ranked]

    def tracked(self):
        return [q for q in self.quantities if q.tracked]

    def headline(self):
        return [q for q in self.quantities if q.headline]

    def bounded_headline(self):
        """The first headline quantity with a Cramér–Rao bound (f·ku): every method estimates
        it, and its efficiency is measured against the bound."""
        return next((q for q in self.headline() if q.column("crlb")), None)

    def projection(self, role):
        """The quantity of the projection section's role ("error", "ratio"), or None."""
        return next((q for q in self.quantities if q.projection == role), None)

    def targeted(self):
        return [q for q in self.quantities if q.target]

    def sweeps_of(self, role):
        return [s for s in self.sweeps if s.role == role and s.swept]

    def sweep(self, name):
        return next((s for s in self.sweeps if s.name == name), None)


class SchemaError(ValueError):
    pass


def _quantity(q):
    return Quantity(name=q["name"], unit=q["unit"], label=q["label"], doc=q["doc"],
                    columns=tuple(q["columns"].items()), tracked=q["tracked"],
                    summary=q["summary"], summary_metric=q["summary_metric"], ranked=q["ranked"],
                    target=q["target"], headline=q["headline"], projection=q.get("projection"))


def _sweep(s):
    return Sweep(name=s["sweep"], role=s["role"], detections=s["detections"],
                 axes=tuple(s["axes"]), points=s["points"], trials=s["trials"], tracks=s["tracks"])


def _method_type(t):
    law = t["windup"]
    return MethodType(name=t["type"], family=t.get("family"), outputs=tuple(t["outputs"]),
                      windup=WindupLaw(exponent=law["exponent"],
                                       only_when_zero=tuple(law["only_when_zero"]))
                      if law else None)


def read(directory):
    """The Schema of one run directory; SchemaError when it has none or it is malformed."""
    path = os.path.join(directory, SCHEMA_FILE)
    try:
        with open(path, encoding="utf-8") as f:
            data = json.load(f)
        return Schema(quantities=tuple(_quantity(q) for q in data["quantities"]),
                      sweeps=tuple(_sweep(s) for s in data["sweeps"]),
                      files={name: tuple((c["name"], c["unit"], c["doc"]) for c in columns)
                             for name, columns in data["files"].items()},
                      methods=tuple(_method_type(t) for t in data.get("methods", [])))
    except FileNotFoundError:
        raise SchemaError(f"{os.path.basename(os.path.normpath(directory))}: no {SCHEMA_FILE} "
                          "(written by `calibench run`; run the configuration again)") from None
    except (KeyError, TypeError, json.JSONDecodeError) as e:
        raise SchemaError(f"{path}: not a calibench schema ({e})") from None


def merge(schemas):
    """One Schema of several run directories: their quantities must agree (one calibench), their
    sweeps are concatenated, their method types united."""
    if not schemas:
        return Schema(quantities=(), sweeps=(), files={})
    first = schemas[0]
    for other in schemas[1:]:
        if other.quantities != first.quantities:
            raise SchemaError("the run directories were written by calibench versions with "
                              "different metric tables; report them separately")
    sweeps = tuple(s for schema in schemas for s in schema.sweeps)
    # Every directory's method types, each once (a directory written before types declared their
    # outputs lists none).
    methods = {}
    for schema in schemas:
        for t in schema.methods:
            methods.setdefault(t.name, t)
    return Schema(quantities=first.quantities, sweeps=sweeps, files=first.files,
                  methods=tuple(methods.values()))
