"""The report's figures rendered on two processes: the same files, in the same order, as one
process; a copy that dies leaves its figures to this process (webline.report.render)."""

from __future__ import annotations

import os

import pytest
from matplotlib.figure import Figure

from webline.report import render
from webline.report.figures import ReportFigure


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
    monkeypatch.setattr(render.threading, "active_count", lambda: 1)
    monkeypatch.setattr(render.os, "cpu_count", lambda: 2)
    assert render._can_fork(), "this test needs the fork start method"


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
    monkeypatch.setattr(render, "_child", lambda *args: os._exit(1))
    forked = []
    monkeypatch.setattr(render, "_render", _spy(render._render, forked))
    keys = [r.key for r in render.render_figures(JOBS, 50, svg=True)]
    # here: its own share (jobs 0, 2, 4), then the dead copy's (jobs 1, 3)
    assert [list(call[0]) for call in forked] == [JOBS[0::2], JOBS[1::2]]
    assert keys == ["a0", "bb0", "bb1", "dddd0", "eeeee0", "eeeee1", "eeeee2"]


def _spy(function, calls: list):
    def wrapped(*args):
        calls.append(args)
        return function(*args)
    return wrapped


def test_svg_on_request() -> None:
    (only,) = render.render_figures([_job("a")], 50, svg=True)
    assert only.svg is not None and b"<svg" in only.svg
