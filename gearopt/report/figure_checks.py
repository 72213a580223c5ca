"""Readability checks of a finished matplotlib figure, from its artists (no pixel comparison).

:func:`readability_issues` lists what makes a figure hard to read at 100 % zoom: a text cut off by the figure's
edge, an annotation or bar label spilling out of its panel, texts of one panel drawn over each other (tick labels,
annotations, bar labels, the legend), a legend over a bar, a font below ``min_font_pt``, an axes with nothing drawn
in it, no title, a numeric axis whose tick labels show but which has no label or no unit in brackets at its end
(``"torque [N m]"``; a ratio is ``[-]``), a colour bar without a label and unit. An empty list: nothing found. The
report's figure tests run it on every figure the main job writes.
"""

from __future__ import annotations

import re

from matplotlib.container import BarContainer
from matplotlib.text import Text
from matplotlib.transforms import Bbox

_UNIT = re.compile(r"\[[^\]]+\]\s*$")
_NUMBER = re.compile(r"^[\s\u2212+\-0-9.,eE×]*$")
_MATHTEXT = re.compile(r"\\mathdefault|\\times|[${}^]")


def readability_issues(fig, *, min_font_pt: float = 6.5, tolerance_px: float = 1.0) -> list[str]:
    """What makes ``fig`` hard to read (see the module docstring); each entry names the axes and the artist."""
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    frame = fig.bbox.padded(tolerance_px)
    issues: list[str] = []
    every_tick_label = {id(t) for a in fig.axes for axis in (a.xaxis, a.yaxis)
                        for tick in axis.get_major_ticks() + axis.get_minor_ticks() for t in (tick.label1, tick.label2)}
    drawn_tick_labels = {id(t) for a in fig.axes for axis in (a.xaxis, a.yaxis) for t in _tick_labels(axis)}
    for text in fig.findobj(Text):
        if not _shown(text) or (id(text) in every_tick_label and id(text) not in drawn_tick_labels):
            continue
        box = text.get_window_extent(renderer)
        if not _inside(box, frame):
            issues.append(f"text {text.get_text()!r} is cut off by the figure's edge")
        if text.get_fontsize() < min_font_pt:
            issues.append(f"text {text.get_text()!r} is {text.get_fontsize():g} pt (< {min_font_pt:g} pt)")
    colorbars = [a for a in fig.axes if a.get_label() == "<colorbar>"]
    panels = [a for a in fig.axes if a not in colorbars and a.get_visible()]
    suptitle = getattr(fig, "_suptitle", None)          # Figure.get_suptitle needs matplotlib >= 3.8
    has_suptitle = suptitle is not None and suptitle.get_text().strip() != ""
    if not has_suptitle and not all(a.get_title().strip() for a in panels):
        issues.append("no title: neither a figure title nor a title on every panel")
    for i, ax in enumerate(panels):
        name = f"axes {i} ({ax.get_title() or 'untitled'})"
        if not (ax.lines or ax.collections or ax.patches or ax.images):
            issues.append(f"{name} is empty")
        for axis, label in ((ax.xaxis, ax.get_xlabel()), (ax.yaxis, ax.get_ylabel())):
            ticks = [t.get_text() for t in _tick_labels(axis)]
            if not ticks or not all(_NUMBER.match(_MATHTEXT.sub("", t)) for t in ticks):
                continue                           # tick labels hidden (shared axis) or categorical (they name it)
            if not label.strip():
                issues.append(f"{name}: its {axis.axis_name} axis has no label")
            elif not _UNIT.search(label):
                issues.append(f"{name}: {axis.axis_name} label {label!r} has no unit in brackets")
        issues += _overlaps(ax, name, renderer, tolerance_px)
    for cb in colorbars:
        label = cb.get_ylabel() or cb.get_xlabel()
        if not _UNIT.search(label):
            issues.append(f"colour bar label {label!r} has no unit in brackets")
    return issues


def _overlaps(ax, name: str, renderer, tol: float) -> list[str]:
    texts = [t for t in ax.texts if _shown(t)]
    texts += [t for axis in (ax.xaxis, ax.yaxis) for t in _tick_labels(axis)]
    boxes = [(t.get_text(), t.get_window_extent(renderer).padded(-tol)) for t in texts]
    legend = ax.get_legend()
    if legend is not None and legend.get_visible():
        boxes.append(("<legend>", legend.get_window_extent(renderer).padded(-tol)))
    issues = []
    panel = ax.get_window_extent(renderer).padded(tol)
    for text in ax.texts:                   # annotations and bar labels: inside their panel, not over the next one
        if _shown(text) and not _inside(text.get_window_extent(renderer), panel):
            issues.append(f"{name}: {text.get_text()!r} spills out of its panel")
    for a in range(len(boxes)):
        for b in range(a + 1, len(boxes)):
            if boxes[a][1].overlaps(boxes[b][1]):
                issues.append(f"{name}: {boxes[a][0]!r} and {boxes[b][0]!r} overlap")
    if legend is not None and legend.get_visible():
        box = boxes[-1][1]
        bars = [p for c in ax.containers if isinstance(c, BarContainer) for p in c.patches]
        for patch in bars:
            if patch.get_window_extent(renderer).overlaps(box):
                issues.append(f"{name}: the legend covers a bar")
                break
    return issues


def _tick_labels(axis) -> list[Text]:
    """The tick labels (major and minor) drawn: shown and inside the view interval."""
    lo, hi = sorted(axis.get_view_interval())
    span = 1e-9 * max(abs(lo), abs(hi), 1.0)
    out = []
    ticks = (axis.get_major_ticks(len(axis.get_majorticklocs()))
             + axis.get_minor_ticks(len(axis.get_minorticklocs())))
    for tick in ticks:
        if tick.get_visible() and lo - span <= tick.get_loc() <= hi + span:
            out += [label for label in (tick.label1, tick.label2) if _shown(label)]
    return out


def _shown(text: Text) -> bool:
    return text.get_visible() and text.get_text().strip() != "" and text.get_alpha() != 0


def _inside(box: Bbox, frame: Bbox) -> bool:
    return box.x0 >= frame.x0 and box.y0 >= frame.y0 and box.x1 <= frame.x1 and box.y1 <= frame.y1


__all__ = ["readability_issues"]
