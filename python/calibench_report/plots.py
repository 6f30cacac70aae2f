"""Figures of the report (matplotlib, Agg): the method palette and the shared panels.

The palette is built once from the methods of the run (Palette), and passed to whatever draws:
no query changes it.
"""
import math

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

TARGET_STYLE = dict(color="k", ls=":", lw=1)


class Palette:
    """A colour per method, in the order the methods first appear in the runs (read-only)."""

    def __init__(self, methods):
        methods = list(dict.fromkeys(methods))
        if len(methods) <= 10:  # matplotlib's default cycle.
            colours = [f"C{i}" for i in range(len(methods))]
        else:  # tab20, its dark shades first: up to 20 distinct colours, then they repeat.
            cmap = matplotlib.colormaps["tab20"]
            order = list(range(0, 20, 2)) + list(range(1, 20, 2))
            colours = [cmap(order[i % 20]) for i in range(len(methods))]
        self._colours = dict(zip(methods, colours))

    def __getitem__(self, method):
        return self._colours.get(method, "0.4")


def figure(nrows, ncols, width, height, **kwargs):
    return plt.subplots(nrows, ncols, figsize=(width * ncols, height * nrows), squeeze=False,
                        **kwargs)


def save(fig, path, dpi=90, tight=True):
    if tight:
        fig.tight_layout()
    fig.savefig(path, dpi=dpi)
    plt.close(fig)


def numeric(values):
    return [v for v in values if isinstance(v, (int, float, np.integer, np.floating))
            and math.isfinite(v)]


def axis_scale(ax, xs):
    """Log x when the swept values span a factor 20 or more; ticks at the swept values."""
    xs = sorted(set(numeric(xs)))
    if xs and min(xs) > 0 and max(xs) / min(xs) >= 20:
        ax.set_xscale("log")
    ax.minorticks_off()  # Minor log ticks on many panels make the layout slow.
    if xs:
        ax.set_xticks(xs, [f"{x:g}" for x in xs])


def band_lines(ax, lines, palette, crlb=None, target=None):
    """Median lines with their 95% bands: lines = {method: [(x, median, lo, hi)]} (sorted by x);
    crlb = {method: [(x, bound)]} dashed; target: a horizontal dotted line."""
    for m, pts in lines.items():
        pts = [p for p in pts if math.isfinite(p[1])]
        if not pts:
            continue
        x = [p[0] for p in pts]
        ax.plot(x, [p[1] for p in pts], "o-", ms=3, color=palette[m], label=m)
        ax.fill_between(x, [p[2] for p in pts], [p[3] for p in pts], alpha=0.12,
                        color=palette[m])
    for m, pts in (crlb or {}).items():
        ax.plot([p[0] for p in pts], [p[1] for p in pts], "--", color=palette[m],
                label=f"CRLB (std), {m}'s model")
    if target:
        ax.axhline(target, label=f"{target:g}° target", **TARGET_STYLE)
    if any(math.isfinite(p[1]) and p[1] > 0 for pts in lines.values() for p in pts):
        ax.set_yscale("log")
    ax.grid(True, which="both", alpha=0.3)
    ax.tick_params(labelsize=6)


def legend_of(axes):
    """{label: handle} of every labelled artist of `axes` (each label once)."""
    out = {}
    for ax in axes:
        for handle, label in zip(*ax.get_legend_handles_labels()):
            out.setdefault(label, handle)
    return out
