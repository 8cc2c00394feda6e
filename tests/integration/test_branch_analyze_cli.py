"""``webline analyze`` of a branched line: operating point, closed-loop modes and the verdict,
computed from the linear model (docs/branching.md, "Linear models")."""

from __future__ import annotations

import json

import numpy as np
import pytest
from typer.testing import CliRunner

import webline
from webline.cli import app
from webline.sim.branches.linear import linear_model


def _run(*args: str):
    return CliRunner().invoke(app, list(args))


def test_analyze_laminator_prints_its_modes_and_a_stable_verdict():
    result = _run("analyze", "laminator")
    assert result.exit_code == 0, result.output
    assert "Closed-loop modes" in result.output and "verdict: ok" in result.output
    assert "rewind_tension_integral" in result.output  # the slowest mode's dominant state


def test_analyze_json_modes_are_the_linear_model_eigenvalues():
    result = _run("analyze", "slitter", "--scenario", "start-up", "--json")
    assert result.exit_code == 0, result.output
    payload = json.loads(result.output)
    # a start from rest is analysed at the end of its ramp (1 s + 10 s), at top speed
    assert payload["analysis_time_s"] == 11.0
    speeds = {r["roller"]: r["speed"] for r in payload["operating_point"]["rollers"]}
    assert abs(speeds["pull"] - 5.0) < 1e-9  # the master at 300 m/min
    values = np.linalg.eigvals(linear_model("slitter").a)  # same references at top speed
    listed = [complex(m["eigenvalue_real"], m["eigenvalue_imag"])
              for m in payload["closed_loop_modes"]]
    upper = values[values.imag >= 0.0]
    assert len(listed) == len(upper)
    # the same matrix (at rest-then-ramped the line is the plain one at 300 m/min): each
    # printed mode is an eigenvalue to round-off (1e-9 of the largest, |λ| ~ 640 1/s)
    for value in listed:
        assert np.min(np.abs(upper - value)) < 1e-9 * np.max(np.abs(values))
    assert payload["verdict"]["status"] == "ok"


def test_analyze_controller_family_gives_that_familys_closed_loop_modes():
    """``--controller state-feedback`` analyses the line with every drive on that family (as
    ``run`` does): its listed modes are the eigenvalues of that line's closed loop, not the
    file's cascaded PI's."""
    from webline.control.select import with_branched_controller
    from webline.sim.branches.equilibrium import operating_point
    from webline.sim.branches.linear import analysis_time, branch_linear_model
    from webline.sim.branches.plan import compile_branches

    result = _run("analyze", "laminator", "--json", "--controller", "state-feedback")
    assert result.exit_code == 0, result.output
    listed = [complex(m["eigenvalue_real"], m["eigenvalue_imag"])
              for m in json.loads(result.output)["closed_loop_modes"]]

    def eigenvalues(line):
        plan = compile_branches(line)
        point = operating_point(plan, analysis_time(line))
        return np.linalg.eigvals(branch_linear_model(plan, point, "closed").a)

    family = eigenvalues(with_branched_controller(webline.load_line("laminator"),
                                                  "state_feedback"))
    plain = eigenvalues(webline.load_line("laminator"))
    scale = np.max(np.abs(family))
    # every listed mode is an eigenvalue of the state-feedback closed loop to round-off
    # (1e-9 of the largest), and some lie far (0.1 1/s, 1e8 times that) from every PI mode
    for value in listed:
        assert np.min(np.abs(family - value)) < 1e-9 * scale
    assert max(np.min(np.abs(plain - value)) for value in listed) > 0.1


LBF, FPM, LBF_FT, INCH = 4.4482216152605, 0.00508, 1.3558179483314004, 0.0254  # [SI]


def test_analyze_branched_in_imperial_units_is_the_si_point_converted():
    si = json.loads(_run("analyze", "slitter", "--json").output)["operating_point"]
    imperial = json.loads(_run("analyze", "slitter", "--json", "--units", "imperial").output)
    point = imperial["operating_point"]
    assert imperial["units"] == "imperial"
    assert point["units"] == {"tension": "lbf", "speed": "ft/min", "torque": "lbf*ft",
                              "width": "in"}
    # the same numbers in the other units: exact factors (1 lbf = 4.4482216152605 N, 1 ft/min
    # = 0.00508 m/s, 1 lbf·ft = 1.3558179483314004 N·m), so to round-off
    for a, b in zip(si["spans"], point["spans"], strict=True):
        assert b["tension"] == pytest.approx(a["tension"] / LBF, rel=1e-12)
    for a, b in zip(si["rollers"], point["rollers"], strict=True):
        assert b["speed"] == pytest.approx(a["speed"] / FPM, rel=1e-12)
        assert b["omega_rad_s"] == a["omega_rad_s"]
        assert (b["torque"] is None) == (a["torque"] is None)
        if a["torque"] is not None:
            assert b["torque"] == pytest.approx(a["torque"] / LBF_FT, rel=1e-12)


@pytest.mark.parametrize(("units", "factor"), [("si-per-width", 1.0),
                                               ("imperial-per-width", INCH / LBF)])
def test_analyze_branched_per_width_divides_each_span_by_its_own_web(units, factor):
    # the slitter's base web is 1.25 m wide, its lanes 0.4 m each: the lanes' 100 N is
    # 250 N/m (1.4275 pli), the base web's 299.8 N is 239.8 N/m
    point = json.loads(_run("analyze", "slitter", "--json", "--units", units).output)[
        "operating_point"]
    spans = {r["span"]: r for r in point["spans"]}
    assert spans["lane_1_span"]["tension"] == pytest.approx(100.0 / 0.4 * factor, rel=1e-9)
    assert spans["unwind_zone"]["tension"] == pytest.approx(300.0 / 1.25 * factor, rel=1e-9)
    widths = {r["web"]: r["web_width"] for r in point["spans"]}
    assert widths["lane_3"] == pytest.approx(400.0 if units.startswith("si") else 0.4 / INCH)
    table = _run("analyze", "slitter", "--units", units)
    assert table.exit_code == 0, table.output
    assert "web width" in table.output
    assert ("[pli]" if units.startswith("imperial") else "[N/m]") in table.output


def _overtuned(kp: float) -> dict:
    import tomllib
    from pathlib import Path

    from webline.data import lines

    data = tomllib.loads((Path(lines.__file__).parent / "laminator.toml").read_text())
    data.pop("scenarios")
    rewind = next(r for r in data["rollers"] if r["name"] == "rewind")
    rewind["controller"]["tension_kp"] = kp  # [(m/s)/N]; tuned: 7.6e-5
    return data


@pytest.mark.parametrize(("kp", "sampled"), [(3e-3, False), (1.8e-3, True)])
def test_analyze_finds_an_overtuned_tension_loop_unstable_as_the_run_does(tmp_path, kp,
                                                                          sampled):
    import tomli_w

    from webline.model.web_graph import load_branched
    from webline.sim.branches.equilibrium import operating_point
    from webline.sim.branches.linear import sampled_unstable_modes
    from webline.sim.branches.plan import compile_branches
    from webline.sim.branches.run import simulate_branches

    data = _overtuned(kp)
    path = tmp_path / "overtuned.toml"
    path.write_bytes(tomli_w.dumps(data).encode())
    result = _run("analyze", str(path))
    assert result.exit_code == 3, result.output
    assert "verdict: unstable" in result.output
    # at 1.8e-3 only the sampled loop grows: the continuous model's modes all decay
    assert ("controllers sampled at 1000 Hz" in result.output) == sampled
    plan = compile_branches(load_branched(data))
    mode = sampled_unstable_modes(plan, operating_point(plan))[0]
    # the run from the operating point: the laminate zone rings at the mode's frequency and
    # its envelope (half the swing over each period) grows at the sampled loop's Re λ while
    # between 1e-3 and 3 N (above round-off, below the torque limit and slack)
    seconds = 12.0 / mode.eigenvalue.real
    ds = simulate_branches(data, seconds, raise_on_failure=False).dataset
    time, tension = ds["time"].values, ds["tension"].sel(span="laminate_zone").values
    period = 2 * np.pi / mode.eigenvalue.imag
    starts = np.arange(0.0, seconds - period, period)
    envelope = np.array([np.ptp(tension[(time >= a) & (time < a + period)]) / 2
                         for a in starts])
    small = (envelope > 1e-3) & (envelope < 3.0)
    assert small.sum() >= 5
    rate = np.polyfit(starts[small] + period / 2, np.log(envelope[small]), 1)[0]
    # the sampled model is the run's loop exactly but for RK4 (h|λ| < 0.4 here: ~1e-4) and
    # second-order terms (ΔT Δv at a few N: ~1e-3); 2 % (measured 0.1 %, 0.01 %) also
    # allows the envelope's one-sample jitter
    assert abs(rate - mode.eigenvalue.real) < 0.02 * mode.eigenvalue.real, (rate, mode)
