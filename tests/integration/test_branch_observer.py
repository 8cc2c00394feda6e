"""The section observer on a branched line's decentralized drives (docs/branching.md,
"Section observer"): ``tension_feedback = "observer"``, the chain's observer integrating the
span equation (B1) with measured speeds; its estimate against the true tension through the
layer upset, the linear model with it, and its bad input."""

from __future__ import annotations

import math
import tomllib
from importlib import resources
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from webline.cli import app
from webline.errors import LineFileError
from webline.model.web_graph import load_branched
from webline.sim.branches.drives.decentral import prepare, start_memory
from webline.sim.branches.drives.observer import start_observers
from webline.sim.branches.equilibrium import operating_point
from webline.sim.branches.linear import (
    branch_linear_model,
    fastest_rate,
    felt_tension_rows,
)
from webline.sim.branches.loop import layout as B
from webline.sim.branches.loop.kernel import new_records
from webline.sim.branches.plan import compile_branches


def _laminator(observer: bool = True, bandwidth: float | None = None,
               guide: bool = False) -> dict:
    """The laminator on state feedback everywhere; without ``guide`` its film runs straight
    from its unwind to the nip (one span of 3.5 m, the film zone: what the chain's observer
    needs, a zone of one span), the film unwind's tension from a section observer."""
    data = tomllib.loads(resources.files("webline.data.lines").joinpath(
        "laminator.toml").read_text("utf-8"))
    if not guide:
        data["rollers"] = [r for r in data["rollers"] if r["name"] != "guide_film"]
        data["webs"][0]["path"] = ["unwind_film", "nip"]
        data["webs"][0]["spans"] = [{"name": "film_zone", "length": "3.5 m",
                                     "tension": "120 N"}]
    for roller in data["rollers"]:
        if "controller" in roller:
            roller["controller"] = {"type": "state_feedback"}
    if observer:
        film = data["rollers"][0]["controller"]
        film["tension_feedback"] = "observer"
        if bandwidth is not None:
            film["observer_bandwidth"] = f"{bandwidth} rad/s"
    return data


def _estimates(data: dict, seconds: float) -> np.ndarray:
    """(time [s], true film-zone tension, observer's T̂ [N]) after every controller tick of
    the layer upset, stepping the compiled loop one tick at a time as ``run`` sets it up."""
    plan = compile_branches(load_branched(data).with_scenario("layer-upset"))
    prepare(plan)
    point = operating_point(plan)
    substeps = max(1, math.ceil(plan.dt * fastest_rate(plan, point) / 0.4))
    plan.df[:, B.D_FF] = point.ratio
    x = point.x.copy()
    istate = np.zeros((plan.di.shape[0], B.I_COLS))
    istate[:, B.I_SPEED], istate[:, B.I_RADIUS] = point.torque, plan.radius0
    istate[:, B.I_DETECT] = -1.0
    start_memory(plan, istate)
    start_observers(plan, istate, x)
    wound, done, cmd = plan.wound.copy(), np.zeros(len(plan.events)), point.torque.copy()
    k = plan.line.spans[0].index
    out = []
    for tick in range(round(seconds / plan.dt)):
        rec = new_records(1, 1, plan.n_x, plan.di.shape[0])
        plan.run(x, istate, wound, done, rec, cmd, tick, 1, substeps, 1, False)
        out.append(((tick + 1) * plan.dt, x[k], istate[0, B.I_THAT]))
    return np.array(out)


@pytest.mark.parametrize("bandwidth", [30.0, 12.0])
def test_the_estimate_follows_the_layer_upset_at_the_observers_bandwidth(bandwidth):
    """The film zone's reference steps 120 -> 150 N at 2 s. The observer's model of this
    zone is the plant's (one span, measured speeds, the motor torque, exact EA and
    wound-in), so its error obeys the error dynamics with both poles at -λ: after its peak
    it decays at least as (1 + λτ) e^{-λτ}; the Euler step (1 ms) leaves a floor."""
    out = _estimates(_laminator(bandwidth=bandwidth), 2.0 + 14.0 / bandwidth)
    time, error = out[:, 0], out[:, 2] - out[:, 1]
    before = time < 2.0
    # steady: the model is exact and the estimate sits on the tension (measured 1.5e-6 N)
    assert np.max(np.abs(error[before])) < 1e-5
    during = (time >= 2.0) & (time < 2.0 + 2.0 / bandwidth)
    peak_at = time[during][np.argmax(np.abs(error[during]))]
    peak = np.max(np.abs(error[during]))
    assert 0.5 < peak < 30.0  # the step shows (2.4 N at 30 rad/s), far below the 30 N
    later = time >= peak_at + 10.0 / bandwidth
    # (1 + 10) e^-10 of the peak, twice for the forcing that goes on while the loop settles
    # (measured at 30 rad/s: 9.8e-4 N against a bound of 2.4e-3 N)
    assert np.max(np.abs(error[later])) < 2 * 11 * math.exp(-10.0) * peak
    assert abs(out[-1, 1] - 150.0) < 0.01  # the loop on T̂ holds the new reference


def test_the_linear_model_with_the_observer_is_the_loadcell_loop_and_its_error_poles():
    """Separation: where the observer's model is the plant's, the closed loop on T̂ has the
    loadcell loop's modes (to round-off) plus the observer's error poles, the double pole at
    -λ (a double eigenvalue moves by √ of the matrix's round-off: 1e-3 λ); all stable, and
    the sampled loop (1 kHz, the observer's Euler step) too."""
    from webline.sim.branches.linear import sampled_closed_loop

    def modes(data: dict) -> tuple[np.ndarray, float, list[str]]:
        plan = compile_branches(load_branched(data))
        point = operating_point(plan)
        model = branch_linear_model(plan, point, "closed")
        radius = np.abs(np.linalg.eigvals(sampled_closed_loop(plan, point))).max()
        return np.linalg.eigvals(model.a), float(radius), model.states

    loadcell, _, _ = modes(_laminator(observer=False))
    observed, radius, states = modes(_laminator(bandwidth=20.0))
    assert states[-2:] == ["unwind_film_tension_estimate", "unwind_film_omega_estimate"]
    assert len(observed) == len(loadcell) + 2
    near = np.abs(observed + 20.0) < 0.02
    assert near.sum() == 2
    rest = observed[~near]
    for value in loadcell:
        assert np.min(np.abs(rest - value)) < 1e-6 * max(abs(value), 1.0), value
    assert observed.real.max() < 0.0 and radius < 1.0


def test_an_observer_on_a_zone_it_cannot_observe_is_one_line(tmp_path):
    import tomli_w

    data = _laminator(guide=True)  # the film zone: two spans round its guide
    with pytest.raises(LineFileError, match=r"rollers\[0\]\.controller\.tension_feedback"):
        prepare(compile_branches(load_branched(data)))
    path = Path(tmp_path) / "guided.toml"
    path.write_bytes(tomli_w.dumps(data).encode())
    result = CliRunner().invoke(app, ["analyze", str(path)])
    assert result.exit_code == 2, result.output
    assert "rollers[0].controller.tension_feedback" in result.output
    assert "a zone of one span" in result.output and "Traceback" not in result.output


def test_an_observer_behind_the_nip_reads_the_layers_references_and_is_unbiased():
    """The rewind's zone made one span (the laminate straight from the nip, 3.5 m): what it
    carries in is the layers' sum (B2), which the observer takes at their references. A step
    of any loadcell reference moves those references, so the linear model's observer rows
    take them as inputs: at steady state (DC gain, -A⁻¹B) T̂ is the laminate's tension for
    every reference input (to round-off; left out, a film step would bias T̂ by ~v_a/v_b
    per newton)."""
    data = _laminator(observer=False, guide=True)
    data["rollers"] = [r for r in data["rollers"] if r["name"] != "guide_laminate"]
    data["webs"][2]["path"] = ["nip", "rewind"]
    data["webs"][2]["spans"] = [{"name": "laminate_zone", "length": "3.5 m",
                                 "tension": "180 N"}]
    next(r for r in data["rollers"] if r["name"] == "rewind")["controller"][
        "tension_feedback"] = "observer"
    data.pop("scenarios")
    plan = compile_branches(load_branched(data))
    model = branch_linear_model(plan, operating_point(plan), "closed")
    assert np.linalg.eigvals(model.a).real.max() < 0.0
    dc = -np.linalg.solve(model.a, model.b)
    # the laminate's tension is its bonded layers' sum, T = s + Σ c o (loop.laminate), what
    # the rewind's loadcell feels: its row over the plant's states, not the stretch s alone
    point = operating_point(plan)
    felt = felt_tension_rows(plan, point)[model.states.index("laminate_zone_tension")]
    true = felt @ dc[:felt.size]
    estimate = model.states.index("rewind_tension_estimate")
    for name in ("film_zone_tension_ref", "foil_zone_tension_ref",
                 "laminate_zone_tension_ref"):
        j = model.inputs.index(name)
        # round-off: the layers' slow transport states (-v/L) weigh on -A⁻¹B; gains that
        # are 0 exactly come out at ~2e-8 N/N here, the bias left out is ~v_a/v_b ~ 1 N/N
        assert abs(dc[estimate, j] - true[j]) < 1e-8, name
