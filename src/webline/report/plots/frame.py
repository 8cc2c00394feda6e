"""Figures with fixed margins in inches instead of a layout engine.

A layout engine (``layout="constrained"``) makes matplotlib draw every figure twice when
saving it: once to measure the text, once to render. The report's time plots have the same
furniture every run (tick labels, a y label, a title per axes, legends inside the axes), so
margins fixed in inches fit them at a third less time per figure.
"""

from __future__ import annotations

from matplotlib.figure import Figure

#: margins [in]: left (tick labels and y label), right, bottom (tick labels and x label), top
LEFT, RIGHT, BOTTOM, TOP = 0.95, 0.2, 0.55, 0.3
#: vertical gap between stacked axes [in], room for the lower axes' title
GAP = 0.42
#: extra room at the top for a figure title [in] (``suptitle``)
TITLE = 0.3


def framed_figure(width: float, height: float, rows: int = 1) -> Figure:
    """A ``width`` x ``height`` [in] figure whose ``rows`` stacked axes leave the fixed
    margins; ``fig.subplots(rows, 1)`` then fills it."""
    axes_height = (height - BOTTOM - TOP - (rows - 1) * GAP) / rows
    fig = Figure(figsize=(width, height))
    # set after construction: ``Figure(subplotpars=...)`` is reset to the rc defaults by the
    # figure's own ``clear()`` in matplotlib 3.11 (the margins were silently the defaults)
    fig.subplots_adjust(left=LEFT / width, right=1 - RIGHT / width, bottom=BOTTOM / height,
                        top=1 - TOP / height, hspace=GAP / axes_height)
    return fig


def make_room_for_title(fig: Figure) -> None:
    """Lower the axes of ``fig`` (made by ``framed_figure``) to leave room for a suptitle."""
    height = fig.get_figheight()
    fig.subplots_adjust(top=1 - (TOP + TITLE) / height)
