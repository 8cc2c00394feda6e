"""The report's figures rendered on two processes: the same files, in the same order, as one
process; a copy that dies leaves its figures to this process (webline.report.render)."""

from __future__ import annotations

import os
import threading

import pytest
from matplotlib.figure import Figure

from webline.report import render
from webline.report.plots.figures import ReportFigure


def _job(key: str, n: int = 1):
    def make() -> list[ReportFigure]:
        out = []
        for k in range(n):
            fig = Figure(figsize=(3, 2))
            fig.subplots().plot([0, 1, 2], [0, len(key) + k, 1])
            out.append(ReportFigure(f"{key}{k}", f"caption {key}{k}", fig))
        return out
    return make


JOBS = [_job("a"), _job("bb", 2), _job("ccc", 0), _job("dddd"), _job("eeeee", 3)]


@pytest.fixture
def forkable(monkeypatch: pytest.MonkeyPatch) -> None:
    """The fork path, even where earlier tests left threads behind (the renderer forks only a
    single-threaded process; the figures here need no lock another thread could hold)."""
    monkeypatch.setattr(threading, "active_count", lambda: 1)
    monkeypatch.setattr(os, "cpu_count", lambda: 2)
    assert render.can_fork(), "this test needs the fork start method"


def test_two_processes_give_the_files_of_one_in_job_order(forkable: None) -> None:
    serial = render.render_figures(JOBS, 50, parallel=False)
    parallel = render.render_figures(JOBS, 50)
    assert [r.key for r in serial] == ["a0", "bb0", "bb1", "dddd0", "eeeee0", "eeeee1",
                                       "eeeee2"]
    assert [(r.key, r.caption, r.png) for r in parallel] == \
        [(r.key, r.caption, r.png) for r in serial]
    assert all(r.png.startswith(b"\x89PNG") and r.svg is None for r in serial)


def test_a_copy_that_dies_leaves_its_figures_here(forkable: None,
                                                 monkeypatch: pytest.MonkeyPatch) -> None:
    def die(jobs, next_job, dpi, svg, conn) -> None:  # takes the next job, never replies
        with next_job.get_lock():
            next_job.value += 1
        os._exit(1)

    monkeypatch.setattr(render, "_child", die)
    rescued = []
    monkeypatch.setattr(render, "_render", _spy(render._render, rescued))
    keys = [r.key for r in render.render_figures(JOBS, 50, svg=True)]
    assert keys == ["a0", "bb0", "bb1", "dddd0", "eeeee0", "eeeee1", "eeeee2"]
    # the job the copy took (whichever it was when it ran) was rendered here afterwards
    assert len(rescued) == 1 and rescued[0][0][0] in JOBS


def test_both_processes_take_jobs_until_none_is_left(forkable: None) -> None:
    """The share of each process follows the work: while one draws a slow job the other takes
    every quick one (a fixed half each made the run wait for the slower half)."""
    import time

    def drawn_by(key: str, seconds: float = 0.0):
        def make() -> list[ReportFigure]:
            time.sleep(seconds)
            (fig,) = _job(key)()
            return [ReportFigure(fig.key, str(os.getpid()), fig.figure)]  # who drew it
        return make

    jobs = [drawn_by("slow", 1.5), *(drawn_by(f"quick{i}") for i in range(4))]
    rendered = render.render_figures(jobs, 50)
    assert [r.key for r in rendered] == ["slow0"] + [f"quick{i}0" for i in range(4)]
    slow, *quick = (r.caption for r in rendered)
    assert set(quick) == {quick[0]} != {slow}  # one process drew the slow job, the other the rest


def _spy(function, calls: list):
    def wrapped(*args):
        calls.append(args)
        return function(*args)
    return wrapped


def test_svg_on_request() -> None:
    (only,) = render.render_figures([_job("a")], 50, svg=True)
    assert only.svg is not None and b"<svg" in only.svg
    # reproducible: no date, and the same element ids (matplotlib draws them at random)
    (again,) = render.render_figures([_job("a")], 50, svg=True)
    assert again.svg == only.svg
