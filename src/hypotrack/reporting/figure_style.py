"""One matplotlib style for every figure of the report, drawn at the size it is printed.

The report (``paper/ms.tex``: ``a4paper``, ``geometry`` margins of 2.2 cm) places a figure with
``\\htfigure{path}{f}{caption}`` at ``f`` times the line width, never taller than 0.7 of the text
height. A figure drawn here is ``f × TEXT_WIDTH_IN`` wide and at most ``MAX_HEIGHT_IN`` tall, so
LaTeX never scales it down and a font size in points is the size on the page. :func:`save`
refuses a figure a referee could not read: text under ``MIN_FONT_PT`` at its placed size, a
title or label cut by the figure's edge, or a legend drawn over an axes' data area (legends go
outside the axes: beside them, or below with :func:`legend_below`).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

__all__ = ["TEXT_WIDTH_IN", "MAX_HEIGHT_IN", "MIN_FONT_PT", "RC", "use", "subplots", "legend_below",
           "legend_right", "legibility_problems", "placed_scale", "save", "wrap", "categorical_styles", "pow10"]

TEXT_WIDTH_IN = (210.0 - 2 * 22.0) / 25.4  #: \linewidth of paper/ms.tex: A4 (210 mm) less two 22 mm margins
TEXT_HEIGHT_IN = (297.0 - 2 * 22.0) / 25.4  #: \textheight of paper/ms.tex
MAX_HEIGHT_IN = 0.7 * TEXT_HEIGHT_IN  #: \htfigure caps the height at 0.7\textheight (keepaspectratio)
MIN_FONT_PT = 7.0  #: the smallest text a referee reads on a printed page

RC = {
    "font.size": 8.0,
    "axes.titlesize": 8.5,
    "axes.labelsize": 8.0,
    "xtick.labelsize": 7.5,
    "ytick.labelsize": 7.5,
    "legend.fontsize": 7.5,
    "legend.title_fontsize": 7.5,
    "figure.titlesize": 9.0,
    "lines.linewidth": 1.2,
    "lines.markersize": 4.0,
    "axes.linewidth": 0.6,
    "grid.linewidth": 0.5,
    "legend.framealpha": 0.9,
    "savefig.bbox": None,  # the saved page is exactly the figure size (no scaling in LaTeX)
    "pdf.fonttype": 42,
}


def use() -> None:
    """Select the non-interactive backend and the report's style (font sizes ≥ MIN_FONT_PT)."""
    import matplotlib

    matplotlib.use("Agg")
    matplotlib.rcParams.update(RC)


def subplots(nrows: int = 1, ncols: int = 1, *, width: float = 1.0, height: float, **kwargs):
    """``plt.subplots`` at ``width`` × the report's line width and ``height`` inches, constrained layout.

    ``width`` is the fraction of ``\\linewidth`` the figure is placed at (the ``\\htfigure`` width).
    """
    if not 0.0 < width <= 1.0:
        raise ValueError(f"width must be a fraction of the line width in (0, 1], got {width}")
    if not 0.0 < height <= MAX_HEIGHT_IN:
        raise ValueError(f"height must be in (0, {MAX_HEIGHT_IN:.2f}] inches (0.7 of the text height), got {height}")
    use()
    import matplotlib.pyplot as plt

    kwargs.setdefault("layout", "constrained")
    return plt.subplots(nrows, ncols, figsize=(width * TEXT_WIDTH_IN, height), **kwargs)


def legend_below(fig, handles=None, labels=None, *, ncol: int = 2, **kwargs):
    """A figure legend under the axes (constrained layout makes room for it), in at most ``ncol``
    columns: fewer when the labels of this run would make it wider than the figure."""
    if handles is None:
        handles, labels = _collect(fig)
    renderer = fig.canvas.get_renderer()
    for n in range(max(1, min(ncol, len(labels))), 0, -1):
        leg = fig.legend(handles, labels, loc="outside lower center", ncol=n, **kwargs)
        if n == 1 or leg.get_window_extent(renderer).width <= 0.98 * fig.bbox.width:
            return leg
        leg.remove()
    return leg


def legend_right(ax, handles=None, labels=None, *, label_chars: int = 26, **kwargs):
    """An axes legend just right of the axes, outside its data area, its labels wrapped at
    ``label_chars`` characters (so the legend column stays under a third of the page)."""
    import textwrap

    if handles is None:
        handles, labels = ax.get_legend_handles_labels()
    labels = ["\n".join(textwrap.fill(line, label_chars) for line in str(lab).split("\n")) for lab in labels]
    kwargs.setdefault("loc", "upper left")
    kwargs.setdefault("bbox_to_anchor", (1.01, 1.0))
    kwargs.setdefault("borderaxespad", 0.0)
    return ax.legend(handles, labels, **kwargs)


def _collect(fig):
    handles, labels, seen = [], [], set()
    for ax in fig.axes:
        for h, lab in zip(*ax.get_legend_handles_labels()):
            if lab not in seen:
                seen.add(lab)
                handles.append(h)
                labels.append(lab)
    return handles, labels


def placed_scale(fig, width: float = 1.0) -> float:
    """The factor LaTeX scales the figure by: ``width`` × line width over its width, capped by the height."""
    w, h = fig.get_size_inches()
    return min(width * TEXT_WIDTH_IN / w, MAX_HEIGHT_IN / h)


def _texts(fig):
    """Every visible, non-empty text of the figure that is drawn (tick labels only of the current ticks)."""
    from matplotlib.text import Text

    out = []
    for t in fig.findobj(Text):
        if not t.get_visible() or not t.get_text().strip():
            continue
        out.append(t)
    return out


def legibility_problems(fig, width: float = 1.0) -> list[str]:
    """What a referee could not read in ``fig`` placed at ``width`` × the line width (empty: none).

    Checks (after a draw): every text's size × the placed scale is at least ``MIN_FONT_PT``; every
    title, axis label, legend and free text lies inside the figure (not clipped); no legend
    overlaps an axes' area.
    """
    from matplotlib.legend import Legend

    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    scale = placed_scale(fig, width)
    problems = []
    fig_box = fig.bbox
    tol = 1.0  # pixels: anti-aliasing slack at the figure edge
    tick_labels = set()
    for ax in fig.axes:
        for axis in (ax.xaxis, ax.yaxis):
            for tick in axis.get_major_ticks() + axis.get_minor_ticks():
                tick_labels.update({tick.label1, tick.label2})
    small = {}
    for t in _texts(fig):
        size = t.get_fontsize() * scale
        if size < MIN_FONT_PT - 1e-9:
            small.setdefault(round(size, 2), t.get_text()[:40])
        if t in tick_labels:
            continue  # ticks outside the view are kept but not drawn; their size was checked
        bb = t.get_window_extent(renderer)
        if (bb.x0 < fig_box.x0 - tol or bb.x1 > fig_box.x1 + tol or bb.y0 < fig_box.y0 - tol
                or bb.y1 > fig_box.y1 + tol):
            problems.append(f"text {t.get_text()[:60]!r} is cut by the figure's edge")
    for size, text in sorted(small.items()):
        problems.append(f"text {text!r} is {size:.1f} pt at its placed size (< {MIN_FONT_PT:g} pt)")
    axes = [ax for ax in fig.axes if ax.get_visible() and ax.axison]
    for leg in fig.findobj(Legend):
        if not leg.get_visible():
            continue
        lb = leg.get_window_extent(renderer)
        for ax in axes:
            if lb.overlaps(ax.get_window_extent(renderer)):
                title = ax.get_title() or "untitled"
                problems.append(f"a legend ({lb.width:.0f}×{lb.height:.0f} px) covers the data area of the axes "
                                f"{title[:50]!r}")
                break
    return problems


def save(fig, pdf, png=None, *, width: float = 1.0, dpi: int = 150) -> None:
    """Check the figure is legible at ``width`` × the line width, save it (PDF, PNG), close it.

    Raises ``ValueError`` listing every problem of :func:`legibility_problems` (nothing is written).
    """
    import matplotlib.pyplot as plt

    problems = legibility_problems(fig, width)
    if problems:
        plt.close(fig)
        raise ValueError(f"figure {pdf} is not legible at width {width} × \\linewidth: " + "; ".join(problems))
    fig.savefig(pdf)
    if png is not None:
        fig.savefig(png, dpi=dpi)
    plt.close(fig)


def wrap(text: str, fig, fontsize: float | None = None, fraction: float = 0.95) -> str:
    """``text`` wrapped to ``fraction`` of the figure width (a title never runs off the page)."""
    import textwrap

    import matplotlib

    size = fontsize or matplotlib.rcParams["figure.titlesize"]
    if isinstance(size, str):
        size = 9.0
    chars = int(fraction * fig.get_figwidth() * 72 / (0.6 * float(size)))  # DejaVu Sans: ~0.6 em a character
    return "\n".join(textwrap.fill(line, max(chars, 20)) for line in text.split("\n"))


def categorical_styles(n: int) -> Sequence[dict]:
    """``n`` line styles that differ in colour, dash and marker (told apart in grey print too)."""
    colours = ["tab:blue", "tab:orange", "tab:green", "tab:red", "tab:purple", "tab:brown", "tab:pink", "tab:gray"]
    dashes = ["-", "--", "-.", ":"]
    markers = ["o", "s", "^", "D", "v", "P", "X", "*"]
    return [dict(color=colours[i % len(colours)], ls=dashes[i % len(dashes)], marker=markers[i % len(markers)])
            for i in np.arange(n)]


_SUPERSCRIPT = str.maketrans("0123456789-", "⁰¹²³⁴⁵⁶⁷⁸⁹⁻")


def pow10(exponent: float) -> str:
    """``10`` with the rounded exponent in superscript digits, e.g. ``pow10(6) == "10⁶"``."""
    return "10" + str(int(round(exponent))).translate(_SUPERSCRIPT)
