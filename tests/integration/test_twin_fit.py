"""Fitting a line to measured traces (issue 24 item 3, "Must show"): a round trip recovers
changed parameters within their 95 % intervals, and friction from a run at one constant
speed is named not identifiable."""

from __future__ import annotations

import json

import numpy as np
import pytest

from webline.twin.fitting.fit import fit
from webline.twin.fitting.fit_files import fit_json, write_fit_files
from webline.twin.traces.synthetic import synthetic_csv

#: five parameters of the converter, changed from the line file's values (0.5, 3, 0.05,
#: 4 GPa, 500 N s/m) by 20-40 %
TRUTH = {"rollers.infeed.inertia": 0.7, "rollers.chill.inertia": 2.4,
         "rollers.drum.friction": 0.09, "web.modulus": 3.3e9,
         "rollers.dancer.dancer.damping": 700.0}
FREE = {"rollers.infeed.inertia": "0.1 .. 2 kg*m**2", "rollers.chill.inertia": "0.5 .. 8 kg*m**2",
        "rollers.drum.friction": "0.005 .. 0.5 N*m*s", "web.modulus": "2 .. 6 GPa",
        "rollers.dancer.dancer.damping": "100 .. 3000 N*s/m"}


@pytest.fixture(scope="module")
def round_trip(tmp_path_factory):
    """10 s of the start-up ramp of a converter with TRUTH, logged at 200 Hz with sensor
    noise (0.5 N, 2 mm/s, 0.02 N m) and a 3.7 s clock offset, fitted from the line file."""
    path = synthetic_csv(tmp_path_factory.mktemp("fit") / "log.csv", "converter",
                         changes=TRUTH, duration=10.0, scenario="startup", offset=3.7, seed=1)
    return fit("converter", path, FREE, scenario="startup")


def test_round_trip_every_parameter_within_its_95_percent_interval(round_trip):
    result = round_trip
    assert result.converged, result.message
    assert result.identifiable.all(), result.identifiability.reasons
    for i, p in enumerate(result.parameters):
        lo, hi = result.ci95[i]
        assert lo <= TRUTH[p.path] <= hi, (p.path, TRUTH[p.path], lo, hi)
        # an interval that says something: narrower than a tenth of the bounds
        assert hi - lo < 0.1 * (p.high - p.low), p.path
    # white noise of the levels the fit estimated: residuals at the noise level (the
    # estimate from second differences is within ~15 % of the true σ at 200 Hz)
    assert 0.8 < result.residual_scale < 1.2


def test_fit_files_have_the_shape_tune_reads(round_trip, tmp_path):
    toml_path, json_path = write_fit_files(round_trip, tmp_path)
    data = json.loads(json_path.read_text())
    assert set(data) == {"line", "data", "verdict", "reasons", "residual_scale", "parameters",
                         "records", "correlation", "correlation_order", "simulations",
                         "cost", "converged", "starts", "effective_points",
                         "correlation_time", "checks", "findings"}
    # one record: its residual scale is the fit's (n parameters act on it alone), no
    # parameter of its own
    [record] = data["records"]
    assert record["label"] == "log.csv" and record["parameters"] == {}
    assert record["scenario"] == "startup" and data["data"] == [record["data"]]
    assert record["residual_scale"] == pytest.approx(data["residual_scale"], rel=1e-12)
    assert data["correlation_order"] == list(TRUTH)
    assert data["verdict"] == "good" and data["reasons"] == []
    # the model is right: every signal's residuals white at its noise
    assert data["findings"] == [] and len(data["checks"]) == 17
    assert all(0.8 < c["rms"] < 1.2 and c["p_white"] > 1e-3 for c in data["checks"])
    assert data["starts"]["count"] == 8 and data["starts"]["reached_best"] >= 1
    assert set(data["parameters"]) == set(TRUTH)
    for entry in data["parameters"].values():
        assert set(entry) == {"value", "unit", "stderr", "ci95", "interval", "at_bound",
                              "bounds", "identifiable"}
        assert entry["ci95"][0] <= entry["value"] <= entry["ci95"][1]
        assert entry["interval"] == "two-sided" and entry["at_bound"] is None
    assert data["parameters"]["web.modulus"]["unit"] == "Pa"
    assert np.array(data["correlation"]).shape == (5, 5)
    assert data == fit_json(round_trip)
    import webline

    fitted = webline.load_line(toml_path)  # the annotated file is a valid line file
    assert fitted.spec.web.modulus == pytest.approx(round_trip.value[3])
    text = toml_path.read_text()
    assert "# fitted to log.csv" in text and "95 % interval" in text
    assert "# VERDICT: GOOD" in text and "POOR" not in text


def test_friction_from_one_constant_speed_is_not_identifiable(tmp_path):
    """At one speed, viscous (b ω) and Coulomb friction each only add a constant torque: the
    data cannot separate them, and neither gets a confident value."""
    path = synthetic_csv(tmp_path / "steady.csv", "converter",
                         changes={"rollers.infeed.friction": 0.08}, duration=3.0, seed=2)
    result = fit("converter", path, {"rollers.infeed.friction": "0.005 .. 0.5 N*m*s",
                                     "rollers.infeed.coulomb_friction": "0 .. 5 N*m"})
    assert not result.identifiable.any()
    for i, p in enumerate(result.parameters):
        assert "not identifiable" in repr(result)
        assert tuple(result.ci95[i]) == (p.low, p.high)  # no interval narrower than the bounds
        assert result.value[i] == p.start  # the line's value, not the optimiser's
    assert abs(result.correlation[0, 1]) > 0.95


def test_replay_of_a_runs_own_results_reproduces_it(tmp_path):
    """A run's own results.nc replayed on its line: the logged speed reference drives the
    same run, so every signal matches to rounding (float64 file: 1e-9 of its scale)."""
    import webline
    from webline.twin.traces.replay import replay

    run = webline.simulate("converter", 3.0, scenario="startup")
    path = run.to_netcdf(tmp_path / "results.nc")
    result = replay("converter", path, scenario="startup")
    assert "line speed from speed_ref[drum]" in result.notes[0]
    frame = result.metrics.set_index("signal")
    assert frame.loc["tension[process_span]", "max_abs"] < 1e-6  # N
    assert frame.loc["torque[unwind]", "max_abs"] < 1e-6  # N m
    assert frame["r2"].dropna().min() > 1 - 1e-9


def test_replay_without_a_logged_speed_reference_follows_the_measured_master(tmp_path):
    """A log without ``speed_ref`` (skipped here with an empty mapping): the master roller's
    measured speed, averaged over 50 ms, drives the line; its noise (0.5 N, 2 mm/s) must not
    reach the references (noisy speed references, differentiated by the inertia
    compensation, would swamp the torques)."""
    from webline.twin import load_measurements
    from webline.twin.traces.replay import replay

    line = webline_line_startup()
    path = synthetic_csv(tmp_path / "log.csv", "converter", changes={}, duration=6.0,
                         scenario="startup", seed=3)
    data = load_measurements(path, line, mapping={"speed_ref[drum]": ""})
    result = replay(line, data)
    assert "speed[drum]" in result.notes[0]
    frame = result.metrics.set_index("signal")
    # the simulation is the truth up to the smoothed reference: residuals at the noise level
    assert frame.loc["speed[rewind]", "rms"] < 1.5 * 2e-3
    assert frame.loc["tension[process_span]", "rms"] < 1.5 * 0.5


def webline_line_startup():
    import webline

    return webline.load_line("converter").with_scenario("startup")
