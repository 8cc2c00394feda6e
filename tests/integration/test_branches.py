"""Branched lines simulate with the physics of docs/branching.md: a lamination nip's force
continuity and tied strains, a tension upset reaching the other layer only through the nip,
lanes on one shaft drifting apart at the rate first principles give, web length conserved
per web and lane, and a run started at the operating point staying there."""

from __future__ import annotations

import math

import numpy as np
import pytest
from branch_support import foil_zone_check

import webline
from webline.sim.branches.equilibrium import operating_point
from webline.sim.branches.plan import compile_branches


@pytest.fixture(scope="module")
def upset():
    return webline.simulate("laminator", 5.0, scenario="layer-upset")


def test_laminator_starts_at_its_operating_point_and_stays_there():
    result = webline.simulate("laminator", 2.0)
    ds = result.dataset
    tension = ds["tension"]
    # the operating point is solved on the kernel's own rhs (relative tolerance 1e-13); what
    # moves is the rolls' radius (6.6): on the rewind the torque r T must grow at
    # dr/dt T = h v T / (2π r) = 0.029 N·m/s, a ramp the cascaded PI follows with a constant
    # error of 0.022 N at most (1.2e-4 of the tension; a wrong operating point moves it by
    # newtons: the layer upset's 30 N step moves the foil by 8.6 N)
    drift = np.abs(tension - tension.isel(time=0))
    assert float(drift.max()) < 0.05
    assert float(drift.isel(time=slice(0, 10)).max()) < 1e-3  # no jump at the start
    first = tension.isel(time=0)
    laminate = float(first.sel(span="laminate_zone"))
    layers = float(first.sel(span="film_zone")) + float(first.sel(span="foil_zone"))
    # force continuity at the nip: the laminate carries its layers' tensions (to the
    # operating point's tolerance, 1e-13 relative, with margin)
    assert laminate == pytest.approx(layers, rel=1e-9)
    frame = result.to_dataframe()
    # one row per record, every signal (webline.RunResult): each span's tension a column
    assert len(frame) == ds.sizes["time"]
    spans = [f"tension[{s.name}]" for s in result.plan.line.spans]
    assert [c for c in frame.columns if c.startswith("tension[")] == spans
    assert frame["tension[laminate_zone]"].iloc[0] == laminate
    # bonded layers (issue 35): each keeps the strain it came into the nip with, and with
    # no draw across the nip (180 N = 120 + 60) each layer's strain in the laminate is its
    # own zone's
    plan = result.plan
    ea = dict(zip([w.name for w in plan.line.spec.webs],
                  [m.ea for m in plan.line.materials], strict=True))
    for layer in ("film", "foil"):
        mine = ds["layer_tension"].sel(layer_span=f"laminate_zone/{layer}").values / ea[layer]
        own = ds["tension"].sel(span=f"{layer}_zone").values / ea[layer]
        np.testing.assert_allclose(mine[0], own[0], rtol=1e-9, atol=0.0)


def test_an_upset_on_one_layer_reaches_the_other_only_through_the_nip(upset):
    """The foil zone's deviation after the film's tension step is what the foil's own span
    equations (6.8) give from the recorded speeds of the foil's rollers and the nip alone,
    integrated here independently of the kernel (scipy, adaptive)."""
    ds = upset.dataset
    recorded, solved, deviation = foil_zone_check(ds)
    assert np.all(deviation > 5.0)  # the upset does reach the foil zone (~8.6 N)
    # the recorded speeds are samples every 1 ms, interpolated linearly: that errs by
    # dt²/8 |d²v/dt²| in speed, ~1e-4 of the deviation measured; 1e-3 leaves a margin of 10
    error = np.max(np.abs(solved - recorded), axis=1)
    assert np.all(error < 1e-3 * deviation), (error, deviation)


def test_lanes_on_one_shaft_drift_apart_at_the_rate_first_principles_give():
    """Two lanes on one shaft, lane_1 1 % thicker. Each lane's span is quasi-steady, exact
    mass conservation (docs/errata.md E-6.6): v_shaft,j/(1 + ε_j) = v_knife/(1 + ε_knife), so
    with v_shaft,j = r_j ω, (1 + ε_1)/(1 + ε_2) = r_1/r_2 and D = ε_1 - ε_2 = (1 + ε_2)
    (r_1/r_2 - 1); each radius grows as dr_j/dt = h_j ω / 2π (6.6), so dD/dt = (1 + ε_2) ω
    (h_1 r_2 - h_2 r_1) / (2π r_2²) (the thesis's first-order transport: (1 - ε_1), 0.2 %
    lower here). The drive holds T_1 + T_2, so
    d(T_1 - T_2)/dt = 2 EA_1 EA_2 / (EA_1 + EA_2) dD/dt. A span follows its quasi-steady
    strain with the lag L/v of its mass balance: the rate measured at t is the one of t - L/v.
    To first order (r_1 = r_2 = r, v = r ω): d(T_1 - T_2)/dt = EA v (h_1 - h_2) / (2π r²)."""
    result = webline.simulate("slitter", 12.0, scenario="thickness-profile")
    ds = result.dataset
    t = ds["time"].values
    diff = (ds["tension"].sel(span="lane_1_span") - ds["tension"].sel(span="lane_2_span")).values
    r1 = ds["radius"].sel(roll="rewind_shaft/lane_1").values
    r2 = ds["radius"].sel(roll="rewind_shaft/lane_2").values
    omega = ds["omega"].sel(node="rewind_shaft").values
    strain = ds["strain"].sel(span="lane_2_span").values
    h1, h2, ea = 50.5e-6, 50e-6, 90e3
    ea1 = ea * h1 / h2
    stiffness = 2 * ea1 * ea / (ea1 + ea)
    lag = 2.0 / 5.0  # L / v of the lane span [s]
    for start, end in ((3.0, 5.0), (5.0, 7.0), (8.0, 10.0), (10.0, 12.0)):
        window = (t >= start) & (t <= end)
        measured = np.polyfit(t[window], diff[window], 1)[0]
        c = int(np.argmin(np.abs(t - (0.5 * (start + end) - lag))))
        hand = stiffness * (1 + strain[c]) * omega[c] * (h1 * r2[c] - h2 * r1[c]) / (
            2 * math.pi * r2[c] ** 2)
        # second-order terms left out: strain² (1e-6), the lag's curvature (~1e-4 of the rate)
        assert measured == pytest.approx(hand, rel=2e-3)
    window = (t >= 3.0) & (t <= 5.0)  # first order, while r_1 - r_2 is still small
    measured = np.polyfit(t[window], diff[window], 1)[0]
    c = int(np.argmin(np.abs(t - 4.0 + lag)))
    speed = r1[c] * omega[c]
    first_order = ea * speed * (h1 - h2) / (2 * math.pi * r1[c] ** 2)
    # it leaves out h (r_1 - r_2) / (r Δh) (1.5 % here) and EA_1 / EA (0.5 %)
    assert measured == pytest.approx(first_order, rel=0.03)
    assert diff[-1] > 25.0  # they do diverge: ~30 N in 12 s


@pytest.mark.parametrize(("line", "scenario"), [("laminator", "roll-change"),
                                                ("slitter", "thickness-profile")])
def test_web_length_is_conserved_per_web_and_lane(line, scenario):
    ds = webline.simulate(line, 8.0, scenario=scenario).dataset
    balance = ds["web_stored"] + ds["web_out"] - ds["web_in"]
    assert float(ds["web_in"].isel(time=-1).min()) > 15.0  # tens of metres went through
    # 1e-7 m asked; rounding of ~40 m sums in float64 is ~1e-14 m per step
    assert float(np.max(np.abs(balance - balance.isel(time=0)))) < 1e-7


def test_the_operating_point_is_steady_on_the_kernels_rhs():
    from webline.sim.branches.loop import layout as B
    from webline.sim.branches.loop.plant import rhs

    for name in ("laminator", "slitter"):
        plan = compile_branches(webline.load_line(name))
        point = operating_point(plan)
        dx = np.zeros(plan.n_x)
        rhs(point.x, point.torque, plan.wound, *plan.tables(), dx,
            plan.scratch())
        n_s = len(plan.line.spans)
        # stretch rates relative to EA v / L (the scale of a span's rate): solver tolerance
        scale = plan.sf[:, B.SF_EA] * point.line_speed / plan.sf[:, B.SF_LENGTH]
        assert np.max(np.abs(dx[:n_s]) / scale) < 1e-10


def test_roll_change_gives_the_new_roll_the_old_surface_speed():
    ds = webline.simulate("laminator", 6.0, scenario="roll-change").dataset
    radius = ds["radius"].sel(roll="unwind_foil/foil")
    speed = radius * ds["omega"].sel(node="unwind_foil")
    before, after = radius.sel(time=4.99, method="nearest"), radius.sel(time=5.01,
                                                                         method="nearest")
    assert float(before) < 0.11 and float(after) == pytest.approx(0.3, abs=1e-4)
    # a flying splice: the surface speed is continuous across the change (within what the
    # controllers change it in one 10 ms step: < 1 %)
    v = speed.sel(time=[4.99, 5.01], method="nearest").values
    np.testing.assert_allclose(ds["speed"].sel(node="unwind_foil").values, speed.values)
    assert v[1] == pytest.approx(v[0], rel=1e-2)


def test_webline_run_writes_a_branched_lines_files(tmp_path):
    import json

    import xarray as xr
    from typer.testing import CliRunner

    from webline.cli import app

    out = tmp_path / "run"
    result = CliRunner().invoke(app, ["run", "laminator", "-s", "layer-upset", "-d", "3",
                                      "-o", str(out)])
    assert result.exit_code == 0, result.output
    summary = json.loads((out / "summary.json").read_text("utf-8"))
    assert summary["verdict"]["status"] == "ok"
    assert [w["web"] for w in summary["webs"]] == ["film", "foil", "laminate"]
    # the verdict's numbers are the run's: the film zone follows its step to 150 N
    film = summary["webs"][0]["spans"]["film_zone"]
    assert 149.0 < film["final_N"] < 151.0 and film["max_N"] > 150.0
    # the step itself: at its instant the tension is the old one (120.0003 N) against 150 N
    assert 30.0 <= film["max_deviation_N"] < 30.01
    foil = summary["webs"][1]["spans"]["foil_zone"]
    assert foil["max_deviation_N"] == pytest.approx(60.0 - foil["min_N"], abs=1e-9)
    with xr.open_dataset(out / "results.nc") as ds:
        assert float(ds["time"][-1]) == pytest.approx(3.0)
        assert "webs" in ds.attrs["line_spec_toml"]
    assert (out / "figures" / "tensions.png").stat().st_size > 10_000
    valid = CliRunner().invoke(app, ["validate", "slitter"])
    assert valid.exit_code == 0 and "branched line 'slitter' with 4 webs" in valid.output


def test_webline_run_refuses_a_bad_branched_file_in_one_line(tmp_path):
    from importlib import resources

    from typer.testing import CliRunner

    from webline.cli import app

    text = resources.files("webline.data.lines").joinpath("laminator.toml").read_text("utf-8")
    bad = tmp_path / "bad.toml"
    bad.write_text(text.replace('type = "idle"', 'type = "idle"\ncontact = { type = '
                                '"traction", friction = 0.2, viscous = "1e4 N*s/m" }', 1),
                   encoding="utf-8")
    result = CliRunner().invoke(app, ["run", str(bad), "-o", str(tmp_path / "o")])
    assert result.exit_code == 2, result.output
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1
    assert "rollers[1].wrap: a traction contact needs the wrap angle" in lines[0]
    assert "Traceback" not in result.output


def test_the_slitter_knife_carries_the_sum_of_its_lanes():
    """At the operating point the idle slitter roller is in torque balance (B4):
    r (T_1 + T_2 + T_3 - T_knife) = b ω, so T_knife = Σ T_lanes - b v / r² (0.2 N here)."""
    ds = webline.simulate("slitter", 0.01).dataset.isel(time=0)
    lanes = float(ds["tension"].sel(span=["lane_1_span", "lane_2_span", "lane_3_span"]).sum())
    knife = float(ds["tension"].sel(span="knife_span"))
    b, r, v = 1e-4, 0.05, 5.0
    assert knife == pytest.approx(lanes - b * v / r**2, rel=1e-9)


@pytest.mark.parametrize(("line", "scenario"), [
    ("laminator", "start-up"), ("laminator", "roll-change"), ("laminator", "layer-upset"),
    ("laminator", "flying-splice"), ("slitter", "start-up"), ("slitter", "thickness-profile")])
def test_every_scenario_of_the_branched_lines_runs_to_its_end(line, scenario):
    result = webline.simulate(line, scenario=scenario)
    duration = webline.load_line(line).spec.scenarios[scenario].duration
    assert result.failure is None and result.time[-1] == pytest.approx(duration)
    tension = result.dataset["tension"]
    assert float(tension.min()) > 0.0  # no span went slack
    if scenario == "start-up":  # from rest to line speed, the zones end at their references
        final = tension.isel(time=-1)
        for k, span in enumerate(result.plan.line.spans):
            ref = result.plan.line.span_tension_spec(k)
            if ref is not None:
                assert float(final.sel(span=span.name)) == pytest.approx(ref, rel=2e-3)


def test_a_drive_at_its_torque_limit_is_a_warning_of_the_verdict():
    line = webline.load_line("laminator")
    data = line.spec.model_dump(exclude_none=True)
    # the rewind needs r T + b ω = 0.08 x 180 + 0.05 x 2.5 / 0.08 = 15.96 N·m at 2.5 m/s
    data["rollers"][6]["drive"]["torque_limit"] = 16.2
    data["speed"] = {"type": "ramp", "initial": 2.0, "final": 2.5, "start": 0.5,
                     "duration": 0.5}  # accelerating it (0.3 kg m² at 12.5 rad/s²) needs more
    result = webline.simulate(webline.load_line(data), 2.0, raise_on_failure=False)
    found = [f for f in result.verdict.findings if f.kind == "torque_limit"]
    assert [f.where for f in found] == ["rewind"] and 0.5 <= found[0].time < 1.0
    assert result.verdict.status == "warning"
    ok = webline.simulate("laminator", 1.0).verdict
    assert ok.status == "ok" and not ok.findings


def test_a_run_in_chunks_is_the_run_in_one_piece(monkeypatch):
    """The loop returns to Python every ``CHUNK`` ticks (so that Ctrl-C is seen); each chunk
    leaves its last tick to the next, so the controllers sample every tick exactly once."""
    from webline.sim.branches import run

    whole = webline.simulate("laminator", 1.5, scenario="layer-upset")
    monkeypatch.setattr(run, "CHUNK", 377)
    chunked = webline.simulate("laminator", 1.5, scenario="layer-upset")
    assert np.array_equal(whole.rec, chunked.rec)
