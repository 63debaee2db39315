"""One matplotlib style for every figure of the report, drawn at the size it is printed.

The report (``paper/ms.tex``: ``a4paper``, ``geometry`` margins of 2.2 cm) places a figure with
``\\htfigure{path}{f}{caption}`` at ``f`` times the line width, never taller than 0.7 of the text
height. A figure drawn here is ``f × TEXT_WIDTH_IN`` wide and at most ``MAX_HEIGHT_IN`` tall, so
LaTeX never scales it down and a font size in points is the size on the page. :func:`save`
refuses a figure a referee could not read: text under ``MIN_FONT_PT`` at its placed size, a
title or label cut by the figure's edge, a legend drawn over an axes' data area (legends go
outside the axes: beside them, or below with :func:`legend_below`), a mathtext sub- or
superscript under ``MIN_SCRIPT_PT`` (matplotlib draws a script at 0.7 of its base size, a
script of a script at 0.49), or two series a reader cannot tell apart: two labelled lines of one
axes (or two entries of one legend) in the same colour, marker and line style, or a labelled
line drawn exactly over another (every point on the other's) without a legend note saying so
(a label containing one of ``COINCIDENCE_NOTES``).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

__all__ = ["TEXT_WIDTH_IN", "MAX_HEIGHT_IN", "MIN_FONT_PT", "RC", "use", "subplots", "legend_below",
           "legend_right", "legibility_problems", "MIN_SCRIPT_PT", "COINCIDENCE_NOTES",
           "text_sizes", "series_problems", "enlarge_scripts", "coincident_lines", "placed_scale", "save", "wrap", "categorical_styles", "pow10"]

TEXT_WIDTH_IN = (210.0 - 2 * 22.0) / 25.4  #: \linewidth of paper/ms.tex: A4 (210 mm) less two 22 mm margins
TEXT_HEIGHT_IN = (297.0 - 2 * 22.0) / 25.4  #: \textheight of paper/ms.tex
MAX_HEIGHT_IN = 0.7 * TEXT_HEIGHT_IN  #: \htfigure caps the height at 0.7\textheight (keepaspectratio)
MIN_FONT_PT = 7.0  #: the smallest text a referee reads on a printed page
MIN_SCRIPT_PT = 6.0  #: the smallest mathtext sub- or superscript (glyph size) on a printed page
#: words in a legend label that tell the reader a series is drawn exactly over another
COINCIDENCE_NOTES = ("coincides with", "coincide", "identical to", "drawn on", "drawn under", "hidden under")

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


def note_coincident(fig) -> int:
    """Append "(coincides with <other>)" to the label of every labelled line drawn exactly over another labelled
    line of its axes (:func:`coincident_lines`, at the axes' current limits), so a legend built afterwards says
    which series hides which (e.g. two implementations timed alike on a small run). Returns the notes added."""
    notes = {}  # label -> the labels it is drawn over, in any axes: every line of that label gets one note
    for ax in fig.axes:
        ax.autoscale_view()
        for a, b in coincident_lines(ax):
            la, lb = str(a.get_label()), str(b.get_label())
            if _labelled(la) and _labelled(lb) and not _noted(la) and la != lb:
                notes.setdefault(la, []).append(lb) if lb not in notes.get(la, []) else None
    where = " in a panel" if len(fig.axes) > 1 else ""
    for ax in fig.axes:
        for line in ax.get_lines():
            label = str(line.get_label())
            if label in notes:
                line.set_label(f"{label} (coincides with {', '.join(notes[label])}{where})")
    return sum(len(v) for v in notes.values())


def legend_below(fig, handles=None, labels=None, *, ncol: int = 2, **kwargs):
    """A figure legend under the axes (constrained layout makes room for it), in at most ``ncol``
    columns: fewer when the labels of this run would make it wider than the figure. Collecting the
    axes' own handles, it first notes coinciding series in their labels (:func:`note_coincident`)."""
    if handles is None:
        note_coincident(fig)
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


def text_sizes(t) -> tuple[float, float]:
    """(base font size, smallest glyph size) of the Text ``t`` in points at the figure's own size.

    A text with mathtext (``$...$``) is laid out by matplotlib's mathtext parser at 72 dpi, which
    reports every glyph's font size: a sub- or superscript is 0.7 × the base size (a nested one
    0.49 ×), so ``$P_D$`` at 8 pt has a 5.6 pt ``D``. Plain text has one size.
    """
    from matplotlib import cbook
    from matplotlib.mathtext import MathTextParser

    base = float(t.get_fontsize())
    if not t.get_parse_math() or t.get_usetex():
        return base, base
    smallest = base
    parser = MathTextParser("path")
    for line in t.get_text().split("\n"):
        if not cbook.is_math_text(line):
            continue
        parsed = parser.parse(line, 72, t.get_fontproperties())
        sizes = [g[1] for g in parsed.glyphs]
        if sizes:
            smallest = min(smallest, min(sizes))
    return base, smallest


def _line_style(line) -> tuple:
    """What tells a line apart at a glance: colour (with alpha), line style, marker and its fill."""
    from matplotlib.colors import to_rgba

    marker = line.get_marker()
    marker = "None" if marker in (None, "", " ", "none", "None") else str(marker)
    ls = line.get_linestyle()
    if ls in (None, "", " ", "none", "None"):
        ls = "None"
    else:  # matplotlib reports every custom dash tuple as "--": compare the dash pattern itself
        offset, dashes = getattr(line, "_unscaled_dash_pattern", (0, None))
        ls = (ls, tuple(np.round(dashes, 3)) if dashes is not None else None)
    def rgba(c):
        return "none" if str(c).lower() == "none" else tuple(round(v, 3) for v in to_rgba(c, line.get_alpha()))

    colour = rgba(line.get_color()) if ls != "None" else "n/a"  # a line's colour, when it draws one
    edge, fill = ("n/a", "n/a") if marker == "None" else (rgba(line.get_markeredgecolor()),
                                                           rgba(line.get_markerfacecolor()))
    return (colour, ls, marker, edge, fill)


def _same_look(a, b) -> bool:
    """Same colour, line style and marker, and line widths within a factor 1.5 (a wider line reads apart)."""
    if _line_style(a) != _line_style(b):
        return False
    if _line_style(a)[1:3] == ("None", "None") or (_line_style(a)[2] == "None" and a.get_linewidth() == 0):
        return False  # draws nothing: a text-only legend row
    wa, wb = max(a.get_linewidth(), 1e-9), max(b.get_linewidth(), 1e-9)
    return max(wa, wb) / min(wa, wb) < 1.5 or _line_style(a)[1] == "None"


def _labelled(label) -> bool:
    return bool(label) and not str(label).startswith("_")


def _noted(label) -> bool:
    return any(note in str(label).lower() for note in COINCIDENCE_NOTES)


COINCIDENCE_PT = 0.25  #: two series closer than this on the printed page (a quarter of a line width) coincide


def _display_points(line) -> dict:
    """The line's finite points in display pixels: x rounded to 0.01 px -> the y values at that x."""
    xy = np.column_stack([np.asarray(line.get_xdata(), dtype=float), np.asarray(line.get_ydata(), dtype=float)])
    xy = xy[np.all(np.isfinite(xy), axis=1)] if len(xy) else xy
    if not len(xy):
        return {}
    with np.errstate(all="ignore"):
        px = line.get_transform().transform(xy)
    px = px[np.all(np.isfinite(px), axis=1)]
    out = {}
    for x, y in zip(np.round(px[:, 0] / 0.01).astype(np.int64), px[:, 1]):
        out.setdefault(int(x), []).append(float(y))
    return out


def _lies_on(a: dict, b: dict, tol: float) -> bool:
    """Every point of ``a`` is within ``tol`` pixels (vertically, at the same x) of a point of ``b``."""
    if not a or len(a) > len(b) or not a.keys() <= b.keys():
        return False
    return all(min(abs(y - yb) for yb in b[x]) <= tol for x, ys in a.items() for y in ys)


def _legend_names(fig, lines) -> dict:
    """Names of unlabelled lines drawn into a legend by handle: the text of the one legend entry
    with the same look (a legend built from handles and names leaves the lines' labels empty)."""
    from matplotlib.legend import Legend
    from matplotlib.lines import Line2D

    entries = [(h, t.get_text()) for leg in fig.findobj(Legend)
               for h, t in zip(leg.legend_handles, leg.get_texts()) if isinstance(h, Line2D)]
    names = {}
    for line in lines:
        if _labelled(line.get_label()):
            continue
        found = {text for h, text in entries if _line_style(h) == _line_style(line)
                 and abs(h.get_linewidth() - line.get_linewidth()) < 1e-6}
        if len(found) == 1:
            names[line] = found.pop()
    return names


def _series_lines(ax) -> list:
    """The lines of ``ax`` that draw something, less error-bar caps (they mark a series' spread)."""
    from matplotlib.container import ErrorbarContainer

    caps = {id(cap) for c in ax.containers if isinstance(c, ErrorbarContainer) for cap in c.lines[1]}
    return [ln for ln in ax.get_lines() if ln.get_visible() and len(np.atleast_1d(ln.get_xdata()))
            and _line_style(ln)[1:3] != ("None", "None") and id(ln) not in caps]


def coincident_lines(ax, lines=None, scale: float = 1.0) -> list[tuple]:
    """Pairs ``(a, b)`` of lines of ``ax`` where every point of ``a`` lies within ``COINCIDENCE_PT``
    (printed, at ``scale``) of ``b`` at the same x: ``a`` is drawn exactly over ``b`` or hidden
    behind it. An identical pair is given once, the later drawn first. Markers alone on the
    vertices of a line without markers, and hollow markers alone, are not counted (they mark
    points of what is under them). Figure code calls this (after setting the axes' limits) to
    note coinciding series in its legend."""
    if lines is None:
        lines = _series_lines(ax)
    points = [_display_points(ln) for ln in lines]
    tol = COINCIDENCE_PT / scale * ax.figure.dpi / 72.0
    pairs = []
    for i, a in enumerate(lines):
        for j, b in enumerate(lines):
            if j == i:
                continue
            if _line_style(a)[1] == "None" and (_line_style(b)[2] == "None" or _line_style(a)[4] == "none"):
                continue
            if not _lies_on(points[i], points[j], tol):
                continue
            if j > i and _lies_on(points[j], points[i], tol):
                continue  # an identical pair is reported once: the later drawn lies on the earlier
            pairs.append((a, b))
    return pairs


def series_problems(fig, width: float = 1.0) -> list[str]:
    """Series of ``fig`` a reader cannot tell apart (empty: none). Call after a draw.

    * two labelled lines of one axes with the same look (:func:`_same_look`);
    * two entries of one legend whose line handles have the same look but different labels;
    * a named line (labelled, or drawn in a legend by handle) every point of which lies on another
      line of its axes, within ``COINCIDENCE_PT`` on the printed page (identical data: it is drawn
      exactly over the other or hidden behind it), unless one of the two names says so (contains
      one of ``COINCIDENCE_NOTES``). Markers alone on the vertices of a line without markers, and
      hollow markers alone, hide nothing (they mark points of what is under them).
    """
    from matplotlib.legend import Legend
    from matplotlib.lines import Line2D

    problems = []
    scale = placed_scale(fig, width)
    for ax in fig.axes:
        lines = _series_lines(ax)
        names = {ln: str(ln.get_label()) for ln in lines if _labelled(ln.get_label())}
        names.update(_legend_names(fig, lines))
        names = {ln: name.replace("\n", " ") for ln, name in names.items()}
        where = repr((ax.get_title() or "untitled").replace("\n", " ")[:50])
        labelled = [ln for ln in lines if _labelled(ln.get_label())]
        for i, a in enumerate(labelled):
            for b in labelled[i + 1:]:
                if a.get_label() != b.get_label() and _same_look(a, b):
                    problems.append(f"series {a.get_label()[:40]!r} and {b.get_label()[:40]!r} of the axes {where} "
                                    "have the same colour, marker and line style")
        for a, b in coincident_lines(ax, lines, scale):
            if (a not in names and b not in names) or names.get(a) == names.get(b):
                continue  # e.g. one run's unlabelled lines among many
            if _noted(names.get(a, "")) or _noted(names.get(b, "")):
                continue
            name_a = repr(names[a][:40]) if a in names else "an unlabelled line"
            name_b = repr(names[b][:40]) if b in names else "an unlabelled line"
            problems.append(f"series {name_a} lies exactly on {name_b} in the axes {where} with no legend note "
                            "(e.g. 'coincides with ...')")
    for leg in fig.findobj(Legend):
        entries = [(h, t.get_text()) for h, t in zip(leg.legend_handles, leg.get_texts())
                   if isinstance(h, Line2D) and h.get_visible()]
        for i, (a, la) in enumerate(entries):
            for b, lb in entries[i + 1:]:
                if la != lb and _same_look(a, b):
                    problems.append(f"legend entries {la[:40]!r} and {lb[:40]!r} have the same colour, marker and "
                                    "line style")
    return list(dict.fromkeys(problems))


def legibility_problems(fig, width: float = 1.0) -> list[str]:
    """What a referee could not read in ``fig`` placed at ``width`` × the line width (empty: none).

    Checks (after a draw): every text's size × the placed scale is at least ``MIN_FONT_PT`` and
    every glyph of its mathtext (sub- and superscripts included, :func:`text_sizes`) at least
    ``MIN_SCRIPT_PT``; every title, axis label, legend and free text lies inside the figure (not
    clipped); no legend overlaps an axes' area; every series can be told apart
    (:func:`series_problems`).
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
    small, scripts = {}, {}
    for t in _texts(fig):
        base, smallest = text_sizes(t)
        if base * scale < MIN_FONT_PT - 1e-9:
            small.setdefault(round(base * scale, 2), t.get_text()[:40])
        if smallest < base and smallest * scale < MIN_SCRIPT_PT - 1e-9:
            scripts.setdefault(round(smallest * scale, 2), t.get_text()[:40])
        if t in tick_labels:
            continue  # ticks outside the view are kept but not drawn; their size was checked
        bb = t.get_window_extent(renderer)
        if (bb.x0 < fig_box.x0 - tol or bb.x1 > fig_box.x1 + tol or bb.y0 < fig_box.y0 - tol
                or bb.y1 > fig_box.y1 + tol):
            problems.append(f"text {t.get_text()[:60]!r} is cut by the figure's edge")
    for size, text in sorted(small.items()):
        problems.append(f"text {text!r} is {size:.1f} pt at its placed size (< {MIN_FONT_PT:g} pt)")
    for size, text in sorted(scripts.items()):
        problems.append(f"a sub- or superscript of {text!r} is {size:.1f} pt at its placed size "
                        f"(< {MIN_SCRIPT_PT:g} pt)")
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
    return problems + series_problems(fig, width)


def enlarge_scripts(fig, width: float = 1.0) -> None:
    """Raise the font size of every text whose mathtext scripts would print under ``MIN_SCRIPT_PT``.

    The usual case is a log axis: matplotlib labels its ticks ``$10^{k}$``, whose exponent is 0.7
    × the tick label size (5.25 pt at 7.5 pt). Such an axis's tick labels (and any other such
    text) are set to the size at which the smallest glyph prints at ``MIN_SCRIPT_PT`` exactly.
    """
    fig.canvas.draw()
    scale = placed_scale(fig, width)
    for ax in fig.axes:
        for name, axis in (("x", ax.xaxis), ("y", ax.yaxis)):
            for which, ticks in (("major", axis.get_major_ticks()), ("minor", axis.get_minor_ticks())):
                need = 0.0
                for tick in ticks:
                    for t in (tick.label1, tick.label2):
                        if t.get_visible() and t.get_text().strip():
                            base, smallest = text_sizes(t)
                            if smallest < base:
                                need = max(need, base * MIN_SCRIPT_PT / (smallest * scale))
                if need > 0 and need > ticks[0].label1.get_fontsize() + 1e-9:
                    ax.tick_params(axis=name, which=which, labelsize=np.ceil(need * 100) / 100)
    ticks = {t for ax in fig.axes for axis in (ax.xaxis, ax.yaxis)
             for tick in axis.get_major_ticks() + axis.get_minor_ticks() for t in (tick.label1, tick.label2)}
    for t in _texts(fig):
        if t in ticks:
            continue
        base, smallest = text_sizes(t)
        if smallest < base and smallest * scale < MIN_SCRIPT_PT:
            t.set_fontsize(np.ceil(base * MIN_SCRIPT_PT / (smallest * scale) * 100) / 100)


def save(fig, pdf, png=None, *, width: float = 1.0, dpi: int = 150) -> None:
    """Check the figure is legible at ``width`` × the line width, save it (PDF, PNG), close it.

    Mathtext scripts are first enlarged to ``MIN_SCRIPT_PT`` (:func:`enlarge_scripts`). Raises
    ``ValueError`` listing every problem of :func:`legibility_problems` (nothing is written).
    """
    import matplotlib.pyplot as plt

    enlarge_scripts(fig, width)
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
