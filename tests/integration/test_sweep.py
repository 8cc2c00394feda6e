"""Sweeps and Monte Carlo (issue 14): the batched kernel gives each case the numbers a single
``simulate`` run of that case gives, whatever the number of threads, and a seed fixes a study."""

from __future__ import annotations

import numpy as np
import pytest

import webline
from webline.sim.results.metrics import METRICS
from webline.sim.sweeps.distributions import draw, parse_distribution
from webline.sim.sweeps.sweep import run_cases

LBF = 4.4482216152605  # [N]
#: cases covering a quiet run, a softer web and a drive that saturates (torque-limit events)
CASES = [{}, {"web.ea": "1800 lbf"},
         {"web.ea": "2200 lbf", "rollers.process.drive.torque_limit": "3 N*m"}]


@pytest.fixture(scope="module")
def batch() -> object:
    return run_cases("hswl", CASES, duration=2.0, scenario="tension-step",
                                       workers=2)


def test_batch_equals_simulate_per_case(batch) -> None:
    # metrics are reduced in compiled code in record order; the reference reduces the same
    # records with numpy (pairwise sums): they agree to rounding, far below 1e-12 relative
    line = webline.load_line("hswl").with_scenario("tension-step")
    statuses = set()
    for c, changes in enumerate(CASES):
        result = webline.simulate(line.replace(changes) if changes else line, 2.0,
                                  raise_on_failure=False)
        expected = result.metric_arrays()
        for name in METRICS:
            np.testing.assert_allclose(batch[name].values[c], expected[name], rtol=1e-12,
                                       atol=0, equal_nan=True, err_msg=f"case {c} {name}")
        assert batch.status.values[c] == expected["status"]
        # the batch chose its sub-steps from batched eigenvalues: the same as simulate's
        assert batch.substeps.values[c] == result.settings["substeps"]
        statuses.add(str(expected["status"]))
    assert statuses == {"ok", "warning"}  # the saturating case is a warning, the others ok
    assert batch.torque_limit_time.values[2].max() > 0.0


def test_a_sweep_across_controller_families_runs_each_structure_as_simulate_does() -> None:
    """Cases of different structures (a whole controller table swapped: other states, another
    compiled loop) in one study: each case's metrics are its own simulate run's (1e-12), and
    the coordinate labels each table as a line file writes it."""
    pi = {"type": "cascaded_pi", "speed_bandwidth": 40.0, "tension_bandwidth": 8.0}
    tables = [pi, {"type": "state_feedback"}]
    ds = webline.sweep("hswl", {"rollers.process.controller": tables}, duration=0.5)
    line = webline.load_line("hswl")
    for c, table in enumerate(tables):
        run = webline.simulate(line.replace({"rollers.process.controller": table}), 0.5)
        expected = run.metric_arrays()
        np.testing.assert_allclose(ds.tension_rms_error.values[c], expected["tension_rms_error"],
                                   rtol=1e-12, atol=0, equal_nan=True)
    labels = ds["rollers.process.controller"].values
    assert labels[0].startswith('{type = "cascaded_pi", speed_bandwidth = 40.0')
    assert "inertia_adaptive = true" in labels[0]
    assert 'type = "state_feedback"' in labels[1]


def test_threads_do_not_change_results(batch) -> None:
    one = run_cases("hswl", CASES, duration=2.0, scenario="tension-step",
                                      workers=1)
    for name in METRICS:
        np.testing.assert_array_equal(one[name].values, batch[name].values)


def test_grid_coordinates_are_si_and_traces_match_simulate() -> None:
    ds = webline.sweep("hswl", {"web.ea": ["1800 lbf", "2200 lbf"],
                                "rollers.process.controller.tension_bandwidth": [4.0, 8.0]},
                       duration=1.0, record="100 ms")
    assert ds.status.shape == (2, 2) and ds.attrs["shape"] == [2, 2]
    # a dimension per path, values in SI (lbf -> N)
    np.testing.assert_allclose(ds["web.ea"].values, np.array([1800, 2200]) * LBF, rtol=1e-9)
    np.testing.assert_array_equal(
        ds["rollers.process.controller.tension_bandwidth"].values, [4.0, 8.0])
    np.testing.assert_allclose(ds.time.values, np.arange(11) * 0.1, atol=1e-12)
    line = webline.load_line("hswl").replace({"web.ea": "2200 lbf"})
    result = webline.simulate(line.replace(
        {"rollers.process.controller.tension_bandwidth": 8.0}), 1.0)
    rows = np.searchsorted(result.time, ds.time.values - 1e-9)
    np.testing.assert_array_equal(ds.tension.values[1, 1], result.tension[rows])


def test_zip_needs_equal_lengths() -> None:
    with pytest.raises(webline.ArgumentError, match=r"web\.ea: 2"):
        webline.sweep("hswl", {"web.ea": ["1 kN", "2 kN"], "speed": ["1 m/s"]}, duration=0.1,
                      mode="zip")


def test_samples_the_line_refuses_stop_the_study_before_any_case_runs() -> None:
    """normal(9 kN, 60 %) draws negative moduli for some of 300 cases (z < -1.67, about 5 %):
    the study is refused up front, naming the path and the distribution, and no case runs."""
    calls: list[tuple[int, int]] = []
    with pytest.raises(webline.ArgumentError,
                       match=r"web\.ea: the samples of normal\(9 kN, 60 %\) include -.*must "
                             r"be > 0.*no case was run"):
        webline.monte_carlo("hswl", {"web.ea": "normal(9 kN, 60 %)"}, 300, seed=1,
                            duration=0.1, progress=lambda done, n: calls.append((done, n)))
    assert calls == []
    with pytest.raises(webline.ArgumentError, match=r"web\.ea: the values include '-1 kN'"):
        webline.sweep("hswl", {"web.ea": ["9 kN", "-1 kN"]}, duration=0.1)


@pytest.mark.parametrize("call, message", [
    (lambda: webline.monte_carlo("hswl", {"web.ea": "uniform(8 kN, 9 kN)"}, 0, seed=1),
     r"n: a Monte Carlo study needs a whole number of samples >= 1, got 0"),
    (lambda: webline.monte_carlo("hswl", {"web.ea": "uniform(8 kN, 9 kN)"}, 2.5, seed=1),
     r"got 2\.5"),
    (lambda: webline.sweep("hswl", {"web.ea": []}), r"web\.ea: no values to sweep"),
    (lambda: webline.sweep("hswl", {"web.ea": ["8 kN"]}, workers=0),
     r"workers: expected a whole number >= 1"),
    (lambda: run_cases("hswl", [{}], workers=-1), r"workers: .*got -1"),
])
def test_empty_or_impossible_studies_are_refused_naming_the_argument(call, message) -> None:
    """A study of no case or on no thread is a mistake, refused before anything runs (an
    empty Monte Carlo once came back as an empty Dataset, and the CLI's merge of no chunk
    as a traceback)."""
    with pytest.raises(webline.ArgumentError, match=message):
        call()


def test_monte_carlo_reads_units_as_the_line_does() -> None:
    """A distribution's values mean what they mean in the line file: a bandwidth in Hz is 2π
    rad/s (it was drawn as 1 rad/s per Hz), a tension per width of web is times the web's
    width (N/m was drawn as N), and a unit of another kind is refused, naming the path."""
    line = webline.load_line("hswl")
    bandwidth, tension = "rollers.process.controller.tension_bandwidth", "spans.1.tension"
    ds = webline.monte_carlo(line, {bandwidth: "uniform(1 Hz, 2 Hz)",
                                    tension: "normal(100 N/m, 1 %)"}, 3, seed=2,
                             duration=0.05)
    plain = draw({bandwidth: "uniform(1, 2)", tension: "normal(100, 1 %)"}, 3, seed=2)
    np.testing.assert_allclose(ds[bandwidth].values, 2 * np.pi * plain[bandwidth],
                               rtol=1e-15)
    np.testing.assert_allclose(ds[tension].values, line.spec.web.width * plain[tension],
                               rtol=1e-15)
    with pytest.raises(webline.ArgumentError,
                       match=r"^web\.ea: uniform\(8 m, 9 m\): the line refuses .*expected a "
                             r"force"):
        webline.monte_carlo(line, {"web.ea": "uniform(8 m, 9 m)"}, 2, seed=1)
    with pytest.raises(webline.ArgumentError, match=r"8 kN and 9 m are not of one kind"):
        webline.monte_carlo(line, {"web.ea": "uniform(8 kN, 9 m)"}, 2, seed=1)
    with pytest.raises(webline.ArgumentError, match=r"^seed: expected a whole number >= 0"):
        webline.monte_carlo(line, {"web.ea": "uniform(8 kN, 9 kN)"}, 2, seed=-1)


def test_distributions_parse_to_si() -> None:
    kind, mean, std = parse_distribution("normal(9 kN, 5 %)")
    assert (kind, mean) == ("normal", 9000.0) and std == pytest.approx(450.0, rel=1e-12)
    assert parse_distribution("uniform(0.1, 0.3)") == ("uniform", 0.1, 0.3)
    kind, low, high = parse_distribution("uniform(2 kN, 10 %)")
    assert (low, high) == pytest.approx((1800.0, 2200.0), rel=1e-12)
    with pytest.raises(ValueError, match="two arguments"):
        parse_distribution("normal(1)")
    # 20 000 draws: the sample mean lies within 5 standard errors of the mean
    samples = draw({"a": "normal(9 kN, 5 %)", "b": "lognormal(2 m, 10 %)"}, 20_000, seed=3)
    assert abs(samples["a"].mean() - 9000.0) < 5 * 450.0 / np.sqrt(20_000)
    assert abs(np.median(np.log(samples["b"])) - np.log(2.0)) < 5 * 0.1 / np.sqrt(20_000) * 1.26


def test_monte_carlo_same_seed_same_study_on_1_and_2_workers() -> None:
    dists = {"web.ea": "normal(2000 lbf, 10 %)", "rollers.idler.friction": "uniform(5e-5, 2e-4)"}
    one = webline.monte_carlo("hswl", dists, 6, seed=7, duration=0.5, workers=1)
    two = webline.monte_carlo("hswl", dists, 6, seed=7, duration=0.5, workers=2)
    other = webline.monte_carlo("hswl", dists, 6, seed=8, duration=0.5, workers=1)
    for name in ("web.ea", *METRICS):
        np.testing.assert_array_equal(one[name].values, two[name].values)
    assert not np.array_equal(one["web.ea"].values, other["web.ea"].values)
    np.testing.assert_allclose(one["web.ea"].values, draw(dists, 6, 7)["web.ea"], rtol=1e-12)


def test_blocks_overlapping_on_threads_give_the_one_thread_results(monkeypatch) -> None:
    # blocks of 1, 2, 2, 2 cases: each is built while the one before runs compiled, and
    # collected while the next runs; the numbers do not depend on that order
    from webline.sim.sweeps import blocks

    monkeypatch.setattr(blocks, "FIRST_BLOCK", 1)
    monkeypatch.setattr(blocks, "BLOCK", 2)
    cases = [{"web.ea": f"{ea} lbf"} for ea in (1800, 1900, 2000, 2100, 2200, 2300, 2400)]
    done: list[int] = []
    two = run_cases("hswl", cases, duration=0.5, workers=2,
                    progress=lambda d, n: done.append(d))
    one = run_cases("hswl", cases, duration=0.5, workers=1)
    assert done == [1, 3, 5, 7]
    assert run_cases("hswl", [], duration=0.5, workers=2).sizes["case"] == 0  # no block at all
    for name in ("web.ea", "status", *METRICS):
        np.testing.assert_array_equal(two[name].values, one[name].values, err_msg=name)


@pytest.mark.serial  # timed: needs the CPU to itself
def test_compiled_batch_releases_the_gil() -> None:
    # while a compiled batch runs in another thread, this thread keeps running Python. Were the
    # GIL held through a compiled call, this thread would stall for the whole call; released,
    # its pauses are the scheduler's slices
    import threading
    import time

    from webline.sim.sweeps.cases import build_cases
    from webline.sim.sweeps.sweep import _run_block

    built = build_cases(webline.load_line("hswl"), [{}] * 64, 10.0)
    started = time.perf_counter()
    _run_block(built, 0, 0, 1)  # alone, loaded compiled loop: the call's duration
    alone = time.perf_counter() - started
    finished = threading.Event()

    def run() -> None:
        _run_block(built, 0, 0, 1)
        finished.set()

    worker = threading.Thread(target=run)
    worker.start()
    last, longest = time.perf_counter(), 0.0
    while not finished.is_set():
        now = time.perf_counter()
        longest, last = max(longest, now - last), now
    worker.join()
    # run_batch makes each thread's share 4 compiled calls (load balance), with the GIL
    # taken back between them: held, the longest pause would be one call, a quarter of it all
    # (measured: 0.10 s of 0.30 s with nogil=False; 0.014 s with nogil=True)
    assert longest < 0.5 * alone / 4, (longest, alone)


def test_kelvin_voigt_spans_sweep_with_their_felt_tensions() -> None:
    """A viscoelastic span's rollers feel s + τ ds/dt (docs/winder.md): the batch reduces the
    felt tensions, as ``Result.tension`` gives them, and each case keeps its own tension
    limit (the 81.1 N limit is crossed only through the damper's overshoot of the step)."""
    line = webline.load_line("hswl").with_scenario("tension-step").replace(
        {"spans.span2.model": "kelvin-voigt", "spans.span2.retardation": "50 ms"})
    cases = [{}, {"spans.span2.retardation": "100 ms", "web.tension_limit": "81.1 N"}]
    ds = run_cases(line, cases, duration=3.0, record="50 ms", workers=1)
    statuses = []
    for c, changes in enumerate(cases):
        result = webline.simulate(line.replace(changes) if changes else line, 3.0)
        # the damper matters here: during the 14.35 -> 18 lbf step span 2 feels up to 7-10 N
        # more than its stretch, so metrics of the stretch would fail this comparison
        assert np.abs(result.tension[:, 1] - np.maximum(result.stretch[:, 1], 0.0)).max() > 5.0
        expected = result.metric_arrays()
        for name in METRICS:
            np.testing.assert_allclose(ds[name].values[c], expected[name], rtol=1e-12,
                                       atol=0, equal_nan=True, err_msg=f"case {c} {name}")
        rows = np.searchsorted(result.time, ds.time.values - 1e-9)
        np.testing.assert_allclose(ds.tension.values[c], result.tension[rows], rtol=1e-12)
        assert ds.status.values[c] == expected["status"]
        statuses.append(str(ds.status.values[c]))
    assert statuses == ["ok", "warning"]  # the second case's own limit, crossed by the damper
    assert ds.tension_max.values[1, 1] > 81.1 > np.maximum(result.stretch[:, 1], 0.0).max()


def test_one_run_names_the_metrics_a_sweep_gives_its_case() -> None:
    """``Result.metrics_by_element()``: the sweep's metrics of one run, by element name. The
    tension step of span2 lands on the last record (t = 2 s): its error is the step,
    18 - 14.35 lbf, and the settling time is inf (still outside the band at the end)."""
    result = webline.simulate("hswl", 2.0, scenario="tension-step")
    metrics = result.metrics_by_element()
    assert set(metrics) == {*METRICS, "status"} and metrics["status"] == "ok"
    step = (18.0 - 14.35) * LBF
    assert metrics["tension_peak_error"]["span2"] == pytest.approx(step, rel=1e-6)
    assert metrics["settling_time"]["span2"] == float("inf")
    assert np.isnan(metrics["tension_rms_error"]["span3a"])  # no loadcell on span3a
    assert metrics["torque_limit_time"] == {name: 0.0 for name in result.drive_names}
