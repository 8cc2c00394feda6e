"""Rendering a report's figures to PNG (and SVG on request), on two processes where it can.

Drawing and compressing the figures is the largest part of a run's report. On a machine with
more than one core, and where ``fork`` is available in a single-threaded process, half of the
figure jobs run in a forked copy of this process (which already holds the result: nothing is
pickled but the images coming back), the other half here. If the copy fails in any way, its
jobs are rendered here: a figure is never dropped.
"""

from __future__ import annotations

import io
import multiprocessing
import os
import threading
from collections.abc import Sequence
from dataclasses import dataclass
from multiprocessing.connection import Connection

from webline.report.figures import FigureJob, ReportFigure


@dataclass(frozen=True)
class Rendered:
    """A figure as files: PNG bytes, and SVG bytes when asked for."""

    key: str
    caption: str
    png: bytes
    svg: bytes | None


def _render(jobs: Sequence[FigureJob], dpi: float, svg: bool) -> list[list[Rendered]]:
    """The figures of each job, a list per job."""
    return [[_files(fig, dpi, svg) for fig in job()] for job in jobs]


def _files(fig: ReportFigure, dpi: float, svg: bool) -> Rendered:
    png = io.BytesIO()
    fig.figure.savefig(png, format="png", dpi=dpi)
    vector = None
    if svg:  # vector copies on request: saving them doubles the time spent on figures
        buffer = io.BytesIO()
        fig.figure.savefig(buffer, format="svg", metadata={"Date": None})
        vector = buffer.getvalue()
    return Rendered(fig.key, fig.caption, png.getvalue(), vector)


def _child(jobs: Sequence[FigureJob], dpi: float, svg: bool, conn: Connection) -> None:
    try:
        conn.send(_render(jobs, dpi, svg))
    finally:
        conn.close()


def _can_fork() -> bool:
    return ((os.cpu_count() or 1) > 1 and threading.active_count() == 1
            and "fork" in multiprocessing.get_all_start_methods())


def render_figures(jobs: Sequence[FigureJob], dpi: float, *, svg: bool = False,
                   parallel: bool = True) -> list[Rendered]:
    """Every figure of ``jobs`` rendered at ``dpi`` [dots per inch], in job order."""
    if not parallel or len(jobs) < 2 or not _can_fork():
        return [r for part in _render(jobs, dpi, svg) for r in part]
    mine, theirs = list(jobs[0::2]), list(jobs[1::2])
    context = multiprocessing.get_context("fork")
    receive, send = context.Pipe(duplex=False)
    child = context.Process(target=_child, args=(theirs, dpi, svg, send), daemon=True)
    child.start()
    send.close()
    here = _render(mine, dpi, svg)
    try:
        there = receive.recv()
    except (EOFError, OSError):  # the copy died: render its share here
        there = _render(theirs, dpi, svg)
    finally:
        receive.close()
        child.join()
    parts: list[list[Rendered]] = [[] for _ in jobs]
    parts[0::2], parts[1::2] = here, there
    return [r for part in parts for r in part]
