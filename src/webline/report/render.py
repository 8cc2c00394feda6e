"""Rendering a report's figures to PNG (and SVG on request), on two processes where it can.

Drawing and compressing the figures is the largest part of a run's report. On a machine with
more than one core, and where ``fork`` is available in a single-threaded process, a forked
copy of this process (which already holds the result: nothing is pickled but the images
coming back) and this process each take the next figure job not yet taken until none is left,
so the work divides evenly whatever each figure costs. If the copy fails in any way, the jobs
it had taken are rendered here: a figure is never dropped.
"""

from __future__ import annotations

import io
import multiprocessing
from collections.abc import Sequence
from dataclasses import dataclass
from multiprocessing.connection import Connection
from multiprocessing.sharedctypes import Synchronized

from webline.report.forking import can_fork
from webline.report.plots.figures import FigureJob, ReportFigure


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
        import matplotlib

        buffer = io.BytesIO()
        # no date, and element ids from a fixed salt: the same figure gives the same file
        with matplotlib.rc_context({"svg.hashsalt": "webline"}):
            fig.figure.savefig(buffer, format="svg", metadata={"Date": None})
        vector = buffer.getvalue()
    return Rendered(fig.key, fig.caption, png.getvalue(), vector)


def _take(jobs: Sequence[FigureJob], next_job: Synchronized, dpi: float,
          svg: bool) -> dict[int, list[Rendered]]:
    """Render the jobs not yet taken, one at a time (``next_job``: the index of the next one,
    shared by both processes), until none is left; their figures by job index."""
    out: dict[int, list[Rendered]] = {}
    while True:
        with next_job.get_lock():
            index = next_job.value
            next_job.value = index + 1
        if index >= len(jobs):
            return out
        out[index] = [_files(fig, dpi, svg) for fig in jobs[index]()]


def _child(jobs: Sequence[FigureJob], next_job: Synchronized, dpi: float, svg: bool,
           conn: Connection) -> None:
    try:
        conn.send(_take(jobs, next_job, dpi, svg))
    finally:
        conn.close()


def render_figures(jobs: Sequence[FigureJob], dpi: float, *, svg: bool = False,
                   parallel: bool = True) -> list[Rendered]:
    """Every figure of ``jobs`` rendered at ``dpi`` [dots per inch], in job order."""
    if not parallel or len(jobs) < 2 or not can_fork():
        return [r for part in _render(jobs, dpi, svg) for r in part]
    context = multiprocessing.get_context("fork")
    next_job = context.Value("q", 0)  # both processes take the next job: the faster does more
    receive, send = context.Pipe(duplex=False)
    child = context.Process(target=_child, args=(jobs, next_job, dpi, svg, send), daemon=True)
    child.start()
    send.close()
    done = _take(jobs, next_job, dpi, svg)
    try:
        done |= receive.recv()
    except (EOFError, OSError):  # the copy died: what it had taken is rendered below
        pass
    finally:
        receive.close()
        child.join()
    for index in range(len(jobs)):
        if index not in done:
            done[index] = _render([jobs[index]], dpi, svg)[0]
    return [r for index in range(len(jobs)) for r in done[index]]
