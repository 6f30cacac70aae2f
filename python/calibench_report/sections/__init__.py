"""The report's sections. Each module's section(ctx, ...) returns a Section (or None when its data
are absent); a module that answers a question of the first page also has answer(ctx, ...): its
lines there, or None. answers.py writes the first page from those alone, never from another
section's helpers."""
import dataclasses
import os

from calibench_report import plots
from calibench_report.scores import Analysis


@dataclasses.dataclass
class Section:
    md: list = dataclasses.field(default_factory=list)  # Lines of report.md.
    pages: dict = dataclasses.field(default_factory=dict)  # Linked page (relative) -> its lines.


class Context:
    """What every section reads: the analysis of the run data, the palette, the report
    directory (figures are written there)."""

    def __init__(self, data, out):
        self.analysis = Analysis(data)
        self.data = data
        self.out = out
        self.palette = plots.Palette(data.methods())

    def path(self, name):
        return os.path.join(self.out, name)
