"""A dancer on a branched line as its zone's tension sensor or passive (docs/branching.md,
"Dancers"; the chain's docs/winder.md D2-D3, Z1-Z4): the laminator's film guide made a dancer
of 5 kg on a 2 kN/m spring, its load 240 N held constant while the layer upset steps the film
zone's reference from 120 to 150 N at 2 s, so the carriage must move to a new place.

- ``use = "tension"``: the film unwind's loop reads T_meas = (load - k (y - y_set)) / G
  (G = g_in + g_out = 2), no loadcell. The carriage's D2 is M ÿ = load - T_in - T_out -
  k (y - y_set) - c ẏ, so T_meas - (T_in + T_out)/2 = (M ÿ + c ẏ)/G: what the sensor reads
  differs from the true mean span tension by the carriage's dynamic force over G, and by
  nothing at rest.
- ``use = "none"``: the loadcell on ``film_zone`` holds its reference; the carriage settles
  where its load balances the spans and its spring, y = y_set + (load - T_in - T_out)/k, with
  T_out = T_ref and T_in = T_ref - c_b ω / r (the dancer roller's bearing drag).
"""

from __future__ import annotations

import numpy as np
import pytest
from test_branch_dancers import MASS, POSITION, dancer_laminator

import webline
from webline.errors import LineFileError
from webline.model.web_graph import load_branched
from webline.sim.branches.equilibrium import operating_point
from webline.sim.branches.linear import branch_linear_model
from webline.sim.branches.loop import layout as B
from webline.sim.branches.plan import compile_branches
from webline.sim.branches.result import BranchResult

SPRING, LOAD, DAMPER = 2000.0, 240.0, 200.0  # [N/m], [N], [N·s/m]
BEFORE, AFTER = 120.0, 150.0  # [N]: the film zone's reference before and after 2 s
DURATION = 8.0  # [s]: 6 s after the upset, 48 time constants of the 8 rad/s tension loop


def _run(use: str, **extra: str) -> BranchResult:
    data = dancer_laminator(use=use, stiffness=f"{SPRING} N/m", load=f"{LOAD} N", **extra)
    return webline.simulate(load_branched(data), DURATION, scenario="layer-upset")


@pytest.fixture(scope="module")
def sensor():
    return _run("tension")


@pytest.fixture(scope="module")
def passive():
    return _run("none", damping=f"{DAMPER} N*s/m")


def _film(ds, span: str) -> np.ndarray:
    return ds["tension"].sel(span=span).values


def test_the_dancer_as_sensor_holds_its_zone_at_the_reference(sensor):
    ds = sensor.dataset
    assert sensor.failure is None
    y = ds["dancer_position"].values[:, 0]
    measured = (LOAD - SPRING * (y - POSITION)) / 2.0  # D3: G = 2 for a plain dancer
    mean = 0.5 * (_film(ds, "film[0]") + _film(ds, "film_zone"))
    time = ds["time"].values
    before = time < 2.0
    # the run starts at the operating point (solver 1e-13) and stays near it: the sensor
    # and the spans read the reference to 1e-4 N of 120 N, the carriage at its set position
    # to 1e-4 N / 1 kN/m (the unwinding film roll's radius and inertia shrink, which the
    # loop follows with a lag of ~2e-5 N)
    assert measured[0] == pytest.approx(BEFORE, abs=1e-9)
    assert np.max(np.abs(measured[before] - BEFORE)) < 1e-4
    assert np.max(np.abs(mean[before] - BEFORE)) < 1e-4
    assert np.max(np.abs(y[before] - POSITION)) < 1e-7
    # after the upset the fixed 240 N load no longer balances 2 x 150 N: the spring takes
    # the 60 N, the carriage runs in by 60 / 2000 = 30 mm, and the loop holds the sensor's
    # reading at 150 N; 6 s later (48 loop time constants) to 1e-3 N, the spans with it
    assert y[-1] == pytest.approx(POSITION - (2 * AFTER - LOAD) / SPRING, abs=1e-6)
    assert measured[-1] == pytest.approx(AFTER, abs=1e-3)
    assert mean[-1] == pytest.approx(AFTER, abs=1e-3)


def test_the_sensor_reads_the_true_tension_within_the_carriages_dynamic_force(sensor):
    ds = sensor.dataset
    time = ds["time"].values
    h = float(time[1] - time[0])
    y = ds["dancer_position"].values[:, 0]
    measured = (LOAD - SPRING * (y - POSITION)) / 2.0
    mean = 0.5 * (_film(ds, "film[0]") + _film(ds, "film_zone"))
    error = measured - mean
    # (M ÿ + c ẏ)/G with c = 0: ÿ from second differences of the 1 ms records
    dynamic = MASS * np.gradient(np.gradient(y, h), h) / 2.0
    inner = slice(2, -2)  # (one-sided differences at the ends)
    # the carriage swings tens of mm in a fraction of a second: the sensor is off by newtons
    assert np.max(np.abs(error)) > 1.0
    # and by exactly its dynamic force: second differences of samples 1 ms apart resolve the
    # carriage's ~200 rad/s mode to (ω h)² / 12 = 0.3 %: 1 % of the peak
    assert np.max(np.abs(error - dynamic)[inner]) < 0.01 * np.max(np.abs(error))
    # at rest (the last second) the sensor and the spans agree to 1e-3 N
    assert np.max(np.abs(error[time > DURATION - 1.0])) < 1e-3


def test_the_passive_carriage_settles_where_its_load_balances_the_spans(passive):
    ds = passive.dataset
    assert passive.failure is None
    y = ds["dancer_position"].values[:, 0]
    omega = ds["omega"].sel(node="guide_film").values
    drag = 1e-4 * omega / 0.05  # the dancer roller's bearing, c_b ω / r [N]
    # the loadcell on film_zone holds the reference; the span into the dancer carries the
    # drag less; D2 at rest: y = y_set + (load - T_in - T_out)/k (hand formula, 2 T = 2 T_ref
    # - drag); at the operating point to 1e-9 m, 6 s after the upset to 1e-6 m (the loop
    # error < 2e-3 N over 2 kN/m)
    for at, ref in ((0, BEFORE), (-1, AFTER)):
        expected = POSITION + (LOAD - (2 * ref - drag[at])) / SPRING
        assert y[at] == pytest.approx(expected, abs=1e-9 if at == 0 else 1e-6)
    assert y[-1] < POSITION - 0.02  # it moved ~30 mm
    assert _film(ds, "film_zone")[-1] == pytest.approx(AFTER, abs=2e-3)
    # web length: D1 conserves Σ L_k(y)(1 - s/EA) + out - in exactly; RK4 to ~1e-13 m
    balance = ds["web_stored"] + ds["web_out"] - ds["web_in"]
    assert float(np.max(np.abs(balance - balance.isel(time=0)))) < 1e-7


@pytest.mark.parametrize("use", ["tension", "none"])
def test_the_linear_closed_loop_moves_the_carriage_by_the_springs_share(use):
    # a fixed load: at DC a reference change ΔT moves the carriage by -G ΔT / k (D2 at rest,
    # G = 2), and the zone's tension follows it one to one (the loop's integrator): the rows
    # of the sensor's reading (k/G on y, 1 on the reference) or of the loadcell
    # (the damper: an undamped passive carriage rings against the loadcell's loop at its
    # ~180 rad/s mode, which the linear model shows growing at +4 1/s)
    data = dancer_laminator(use=use, stiffness=f"{SPRING} N/m", load=f"{LOAD} N",
                            damping=f"{DAMPER} N*s/m")
    plan = compile_branches(load_branched(data))
    model = branch_linear_model(plan, operating_point(plan), "closed")
    assert np.all(np.linalg.eigvals(model.a).real < 0.0)
    steady = -np.linalg.solve(model.a, model.b[:, model.inputs.index("film_zone_tension_ref")])
    dy = steady[model.states.index("guide_film_position")]
    assert dy == pytest.approx(-2.0 / SPRING, rel=1e-6)  # (the drag does not change with T)
    t_in, t_out = (model.c[model.outputs.index(f"{s}_tension")] @ steady
                   for s in ("film[0]", "film_zone"))
    # sensor: (T_in + T_out)/2 follows; loadcell: T_out does (each to 1e-6 relative)
    followed = 0.5 * (t_in + t_out) if use == "tension" else t_out
    assert followed == pytest.approx(1.0, rel=1e-6)


@pytest.mark.parametrize(("change", "key", "fragment"), [
    (lambda d: d["rollers"][1]["dancer"].update(use="tension", stiffness="0 N/m"),
     "rollers[1].dancer.stiffness", "needs a spring (stiffness > 0)"),
    (lambda d: d["rollers"][0].__setitem__("controller", {"type": "state_feedback"}),
     "rollers[1].dancer.use", "tension control trims the speed of a cascaded PI"),
])
def test_bad_sensor_keys_are_one_line_naming_the_key(change, key, fragment):
    data = dancer_laminator(use="tension", stiffness=f"{SPRING} N/m")
    change(data)
    with pytest.raises(LineFileError) as caught:
        compile_branches(load_branched(data))
    assert len(str(caught.value).splitlines()) == 1
    assert caught.value.key == key and fragment in caught.value.problem, caught.value


def test_two_dancers_read_by_one_drive_is_one_line_but_a_passive_one_beside_is_fine():
    data = dancer_laminator(use="tension", stiffness=f"{SPRING} N/m")
    data["rollers"].append({"name": "dancer_2", "type": "dancer", "radius": "50 mm",
                            "inertia": "0.002 kg*m**2", "dancer": {
                                "mass": "3 kg", "travel": "0.2 m", "position": "0.1 m",
                                "stiffness": "5 kN/m", "use": "position"}})
    data["webs"][0]["path"] = ["unwind_film", "guide_film", "dancer_2", "nip"]
    data["webs"][0]["spans"].insert(1, {"length": "1 m"})
    with pytest.raises(LineFileError) as caught:
        compile_branches(load_branched(data))
    assert caught.value.key == "rollers[7].dancer.use"
    assert len(str(caught.value).splitlines()) == 1
    data["rollers"][7]["dancer"]["use"] = "none"
    plan = compile_branches(load_branched(data))
    point = operating_point(plan)
    # the passive one settles where its spring balances its spans (D2 at rest): its default
    # load 2 x 120 N against T_in + T_out, which the sensor's bearing drag (0.1 N) lifts
    # above 240 N: y = y_set + (240 - T_in - T_out) / k, to the solver's 1e-12 m
    y = point.x[int(plan.offsets[B.O_DANCER_END]) - 2]  # (its states come last)
    t_in, t_out = point.x[1], point.x[2]  # film[1] and film_zone, the spans around it
    assert y == pytest.approx(0.1 + (240.0 - t_in - t_out) / 5000.0, abs=1e-12)
    assert y < 0.1 - 1e-5


def test_the_cli_names_the_key_of_a_sensor_without_a_spring(tmp_path):
    import tomli_w
    from typer.testing import CliRunner

    from webline.cli import app

    bad = tmp_path / "bad.toml"
    bad.write_text(tomli_w.dumps(dancer_laminator(use="tension")), encoding="utf-8")
    result = CliRunner().invoke(app, ["run", str(bad), "-o", str(tmp_path / "o")])
    assert result.exit_code == 2, result.output
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and "rollers[1].dancer.stiffness" in lines[0]
    assert "Traceback" not in result.output
