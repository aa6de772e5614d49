"""Readable matplotlib figures: legends that cover no data, angles shown in degrees.

Shared by ``cosim figures``, the ``--plot`` option of ``simulate``/``run`` and the matrix heat
maps. It works on the figures and axes it is given; importing it does not load matplotlib.
"""
from __future__ import annotations

import numpy as np

#: Corners and edges tried for a legend inside its axes, in order of preference.
INSIDE = ("upper right", "upper left", "lower left", "lower right",
          "center right", "center left", "upper center", "lower center")

#: Display pixels kept free around a legend box.
MARGIN_PX = 2.0
#: Gap between the axes and a legend put beside them, in axes widths.
GAP = 0.015


def degrees(values):
    """Radians -> degrees, for display only (the written data stay in radians)."""
    return np.degrees(np.asarray(values, dtype=float))


def obstacles_hit(ax, box, renderer) -> bool:
    """Whether the display-coordinate box ``box`` touches a line, a point set or an annotation of ``ax``.

    Lines are tested segment by segment (a segment crossing the box counts even when none of
    its end points lies inside); reference lines spanning the whole axes (``axhline``,
    ``axvline``, grid) are ignored, as a legend over them hides nothing.
    """
    from matplotlib.collections import PathCollection

    padded = box.padded(MARGIN_PX)
    for line in ax.get_lines():
        if not line.get_visible() or _spans_axes(line):
            continue
        path = line.get_transform().transform_path(line.get_path())
        vertices = path.vertices[np.all(np.isfinite(path.vertices), axis=1)]
        if len(vertices) == 0:
            continue
        if len(vertices) == 1 or line.get_linestyle() in ("None", "none", " ", ""):
            if _inside(vertices, padded):
                return True
            continue
        if _segments_cross(path.vertices, padded):
            return True
    for collection in ax.collections:
        offsets = collection.get_offsets()
        if collection.get_visible() and isinstance(collection, PathCollection) and len(offsets):
            points = collection.get_offset_transform().transform(offsets)
            if _inside(points[np.all(np.isfinite(points), axis=1)], padded):
                return True
    for text in ax.texts:
        if text.get_visible() and text.get_text() and text.get_window_extent(renderer).overlaps(padded):
            return True
    return False


def _spans_axes(line) -> bool:
    """A line drawn in axes coordinates along one direction (axhline/axvline): a reference, not data."""
    from matplotlib.transforms import BlendedAffine2D, BlendedGenericTransform

    return isinstance(line.get_transform(), (BlendedAffine2D, BlendedGenericTransform))


def _inside(points: np.ndarray, box) -> bool:
    if len(points) == 0:
        return False
    x, y = points[:, 0], points[:, 1]
    return bool(np.any((x >= box.x0) & (x <= box.x1) & (y >= box.y0) & (y <= box.y1)))


def _segments_cross(vertices: np.ndarray, box) -> bool:
    """Whether the polyline (a non-finite vertex breaks it) passes through or lies in ``box``."""
    from matplotlib.path import Path

    finite = np.all(np.isfinite(vertices), axis=1)
    breaks = np.flatnonzero(~finite)
    for run in np.split(vertices, breaks):
        run = run[np.all(np.isfinite(run), axis=1)]
        if len(run) == 1 and _inside(run, box) or len(run) > 1 and Path(run).intersects_bbox(box, filled=False):
            return True
    return False


def place_legend(ax, outside: str = "right", **kwargs):
    """A legend of ``ax`` where it covers no data.

    The corners and edges of :data:`INSIDE` are tried in turn, each checked against the drawn
    lines, points and annotations (:func:`obstacles_hit`); if none is free, the legend goes
    outside the axes, to the right of it (``outside="right"``) or below the figure
    (``outside="below"``, for axes with a neighbour on their right). Call it after the layout
    is final (after ``tight_layout``), as it measures the drawing.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        The axes whose labelled artists the legend lists.
    outside : {"right", "below"}
        Where the legend goes when no place inside the axes is free.
    **kwargs
        Passed to :meth:`matplotlib.axes.Axes.legend` (``fontsize``, ``handles``, ...).

    Returns
    -------
    matplotlib.legend.Legend
    """
    ax.figure.canvas.draw()  # the data limits and the layout as they will be saved
    renderer = ax.figure.canvas.get_renderer()
    for loc in INSIDE:
        legend = ax.legend(loc=loc, **kwargs)
        if not obstacles_hit(ax, legend.get_window_extent(renderer), renderer):
            return legend
    legend.remove()
    if outside == "below":
        # under the axes' own tick labels and x label, in axes coordinates
        tight = ax.get_tightbbox(renderer).transformed(ax.transAxes.inverted())
        return ax.legend(loc="upper center", bbox_to_anchor=(0.5, tight.y0 - GAP), borderaxespad=0.0, **kwargs)
    return ax.legend(loc="upper left", bbox_to_anchor=(1.0 + GAP, 1.0), borderaxespad=0.0, **kwargs)
