"""Studies in chunks (issue 14): a study stored chunk by chunk, killed and resumed, has every
case exactly once and the numbers of an uninterrupted run; on a 2-process Dask LocalCluster a
Monte Carlo study with the same seed equals the local one."""

from __future__ import annotations

import contextlib

import numpy as np
import pytest

import webline
from webline.errors import ArgumentError
from webline.sim.results.metrics import METRICS

DISTS = {"web.ea": "normal(2000 lbf, 10 %)", "rollers.idler.friction": "uniform(5e-5, 2e-4)"}
N = 10


@pytest.fixture(scope="module")
def reference():
    return webline.monte_carlo("hswl", DISTS, N, seed=11, duration=0.3, workers=1)


def assert_same(a, b) -> None:
    np.testing.assert_array_equal(a.case.values, np.arange(N))
    for name in ("web.ea", "status", "substeps", "case", "span", *METRICS):
        np.testing.assert_array_equal(a[name].values, b[name].values, err_msg=name)
        # the chunk files (NetCDF-3) give back 64-bit integers and numpy strings
        assert a[name].dtype == b[name].dtype, name


def test_killed_study_resumes_with_every_case_once(tmp_path, reference, monkeypatch) -> None:
    from webline.sim.sweeps import chunks

    monkeypatch.setattr(chunks, "CHUNK", 4)  # 3 chunks: 4 + 4 + 2 cases
    calls = []
    real = chunks._chunk_task

    def counting(run, line, cases, offset, options):
        calls.append(offset)
        return real(run, line, cases, offset, options)

    monkeypatch.setattr(chunks, "_chunk_task", counting)

    def killed(done: int, total: int) -> None:
        raise KeyboardInterrupt  # the run dies right after its first chunk is saved

    with pytest.raises(KeyboardInterrupt):
        webline.monte_carlo("hswl", DISTS, N, seed=11, duration=0.3, store=tmp_path,
                            progress=killed)
    assert sorted(p.name for p in tmp_path.glob("chunk-*.nc")) == ["chunk-000000.nc"]
    with pytest.raises(ArgumentError, match="resume"):
        webline.monte_carlo("hswl", DISTS, N, seed=11, duration=0.3, store=tmp_path)
    with pytest.raises(ArgumentError, match="different study"):
        webline.monte_carlo("hswl", DISTS, N, seed=12, duration=0.3, store=tmp_path,
                            resume=True)
    ds = webline.monte_carlo("hswl", DISTS, N, seed=11, duration=0.3, store=tmp_path,
                             resume=True)
    assert calls == [0, 4, 8]  # the first chunk was not run again
    assert_same(ds, reference)


@pytest.mark.dask
def test_dask_local_cluster_equals_local_run(reference, monkeypatch) -> None:
    from webline.sim.sweeps import chunks

    monkeypatch.setattr(chunks, "CHUNK", 4)  # 3 tasks over 2 worker processes
    monkeypatch.setattr(chunks, "TASK_RK4_STEPS", 0)  # (else one task: the cases are short)
    ds = webline.monte_carlo("hswl", DISTS, N, seed=11, duration=0.3, scheduler="local",
                             workers=2)
    assert_same(ds, reference)


def _die() -> None:
    import os

    os._exit(1)


@pytest.mark.dask
def test_killed_worker_chunks_are_recomputed(reference, monkeypatch) -> None:
    from distributed import Client, LocalCluster

    from webline.sim.sweeps import chunks

    monkeypatch.setattr(chunks, "CHUNK", 2)  # 5 tasks over 2 worker processes
    monkeypatch.setattr(chunks, "TASK_RK4_STEPS", 0)
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                      dashboard_address=None) as cluster, Client(cluster) as client:
        killed = []

        def kill_one(done: int, total: int) -> None:
            if not killed:  # after the first chunk, kill a worker (its nanny restarts it)
                victim = sorted(client.scheduler_info()["workers"])[0]
                killed.append(victim)
                with contextlib.suppress(Exception):  # its connection drops as it dies
                    client.run(_die, workers=[victim])

        ds = webline.monte_carlo("hswl", DISTS, N, seed=11, duration=0.3, scheduler=client,
                                 progress=kill_one)
    assert killed
    assert_same(ds, reference)


def test_a_scheduler_that_is_no_address_is_an_argument_error(tmp_path) -> None:
    """Not a traceback from distributed's address parser: one message naming the argument
    (the CLI prints it and exits 2)."""
    with pytest.raises(ArgumentError, match=r"^scheduler: cannot reach a Dask scheduler at "
                                            r"'bogus' \(missing port number"):
        webline.sweep("hswl", {"web.ea": ["8 kN"]}, duration=0.1, scheduler="bogus",
                      store=tmp_path)
