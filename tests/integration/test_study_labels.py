"""Any value type sweeps (issue 22): table-valued, string and boolean paths keep their labels
as coordinates through chunks, merges and resumes (a grid's: along the path's own dimension,
issue 23; flat, ``as_cases``, along ``case``), so grouping by a label gives each case's own
numbers."""

from __future__ import annotations

import numpy as np
import pytest

import webline
from webline.sim import chunks
from webline.sim.metrics import METRICS
from webline.sim.study_grid import as_cases

CONTROLLER = "rollers.process.controller"
PI = {"type": "cascaded_pi", "speed_bandwidth": 40.0, "tension_bandwidth": 8.0}
TABLES = [PI, {"type": "state_feedback"}, {"type": "adaptive"}]
#: 6 cases: three controller families (three line structures) by two web stiffnesses
VALUES = {CONTROLLER: TABLES, "web.ea": ["1900 lbf", "2100 lbf"]}
DURATION = 0.2  # [s] enough for each family's loops to act on the tension (records differ)


def assert_same_study(a, b) -> None:
    """Every variable and coordinate equal, along the same dimensions, of the same type."""
    assert set(a.variables) == set(b.variables)
    for name in a.variables:
        assert a[name].dims == b[name].dims, name
        assert a[name].dtype == b[name].dtype, name
        np.testing.assert_array_equal(a[name].values, b[name].values, err_msg=name)
    assert set(a.coords) == set(b.coords)


@pytest.fixture(scope="module")
def reference():
    """The study run at once, in memory (no chunks)."""
    return webline.sweep("hswl", VALUES, duration=DURATION, workers=1)


def test_a_table_valued_sweep_of_three_chunks_killed_and_resumed_equals_the_uninterrupted_one(
        reference, tmp_path, monkeypatch) -> None:
    monkeypatch.setattr(chunks, "CHUNK", 2)  # 3 chunks of 2 cases

    def killed(done: int, total: int) -> None:
        raise KeyboardInterrupt  # the run dies right after its first chunk is saved

    with pytest.raises(KeyboardInterrupt):
        webline.sweep("hswl", VALUES, duration=DURATION, workers=1, store=tmp_path / "s",
                      progress=killed)
    assert len(list((tmp_path / "s").glob("chunk-*.nc"))) == 1
    resumed = webline.sweep("hswl", VALUES, duration=DURATION, workers=1,
                            store=tmp_path / "s", resume=True)
    assert_same_study(resumed, reference)
    whole = webline.sweep("hswl", VALUES, duration=DURATION, workers=1, store=tmp_path / "w")
    assert_same_study(whole, reference)
    assert resumed[CONTROLLER].dims == (CONTROLLER,)
    assert as_cases(resumed)[CONTROLLER].dims == ("case",)


@pytest.mark.parametrize("chunk", [None, 2])  # one chunk file, or three
def test_grouping_by_a_table_label_gives_each_cases_own_numbers(chunk, tmp_path,
                                                                monkeypatch) -> None:
    """Per controller family, the mean RMS tension error over the two stiffnesses equals that
    of the two ``simulate`` runs of those cases (the batch equals simulate to 1e-12)."""
    if chunk is not None:
        monkeypatch.setattr(chunks, "CHUNK", chunk)
    ds = webline.sweep("hswl", VALUES, duration=DURATION, workers=1, store=tmp_path)
    grouped = as_cases(ds).tension_rms_error.groupby(CONTROLLER).mean()
    on_grid = ds.tension_rms_error.mean("web.ea")  # the same numbers read off the grid
    assert grouped.sizes[CONTROLLER] == len(TABLES)
    line = webline.load_line("hswl")
    for table in TABLES:
        runs = [webline.simulate(line.replace({CONTROLLER: table, "web.ea": ea}), DURATION)
                for ea in VALUES["web.ea"]]
        want = np.mean([r.metric_arrays()["tension_rms_error"] for r in runs], axis=0)
        label = next(str(v) for v in np.unique(ds[CONTROLLER].values)
                     if f'type = "{table["type"]}"' in str(v))
        got = grouped.sel({CONTROLLER: label}).values
        np.testing.assert_allclose(got, want, rtol=1e-12, equal_nan=True, err_msg=label)
        np.testing.assert_array_equal(on_grid.sel({CONTROLLER: label}).values, got)


def test_string_and_boolean_paths_keep_their_labels_through_chunks(tmp_path,
                                                                   monkeypatch) -> None:
    """A choice (a string) and a switch (a boolean) as a line file writes them, along case,
    the same whether the study ran at once or in two chunks."""
    values = {"rollers.process.drive.feedback": ["load", "motor"],
              f"{CONTROLLER}.inertia_adaptive": [True, False]}
    at_once = webline.sweep("hswl", values, duration=DURATION, workers=1)
    monkeypatch.setattr(chunks, "CHUNK", 2)
    chunked = webline.sweep("hswl", values, duration=DURATION, workers=1, store=tmp_path)
    assert_same_study(chunked, at_once)
    # each path's labels along its own dimension, as a line file writes them
    assert list(chunked["rollers.process.drive.feedback"].values) == ["load", "motor"]
    assert list(chunked[f"{CONTROLLER}.inertia_adaptive"].values) == ["true", "false"]
    flat = as_cases(chunked)  # grid order: the last path varies fastest
    assert list(flat["rollers.process.drive.feedback"].values) == [
        "load", "load", "motor", "motor"]
    assert list(flat[f"{CONTROLLER}.inertia_adaptive"].values) == [
        "true", "false", "true", "false"]
    for name in values:
        assert chunked[name].dims == (name,) and flat[name].dims == ("case",)
    for name in METRICS:  # the metrics over the grid, one cell per case
        assert chunked[name].dims[:2] == tuple(values)
