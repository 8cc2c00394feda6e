"""A centre winder's compensations under a decentralized drive on a branched line
(docs/branching.md, "Centre winders"): added to the law's torque, as the chain's tick adds
them; open loop, which replaces the controller, needs the cascaded PI."""

from __future__ import annotations

import numpy as np

import webline
from webline.model.web_graph import load_branched
from webline.sim.branches.drives import decentral
from webline.sim.branches.equilibrium import operating_point
from webline.sim.branches.linear import branch_linear_model
from webline.sim.branches.plan import compile_branches

B_ROLL = 0.05  # N·m·s: the laminator rewind's bearing friction


def _laminator(winder: bool) -> dict:
    """The laminator on state feedback; with ``winder`` the rewind's law models no friction
    (``friction_estimate = 0``) and its winder compensates the roll's viscous friction."""
    data = load_branched("laminator").spec.model_dump(exclude_none=True)
    for r in data["rollers"]:
        if "controller" in r:
            r["controller"] = {"type": "state_feedback"}
        if r["name"] == "rewind" and winder:
            r["controller"]["friction_estimate"] = 0.0
            r["winder"] = {"viscous_friction": B_ROLL}
    return data


def test_the_winders_friction_compensation_adds_to_the_state_feedback():
    """The law's u_eq carries b_model ω_ref / n; with b_model = 0 and the winder's b ω / n
    added to the torque the rewind gets the same friction torque, taken at the measured
    speed: the two laws differ by b (ω - ω_ref) / n, i.e. b / (r n) = 0.625 N·m/(m/s) more
    speed feedback on the rewind's K_V = 428 N·m/(m/s) (0.15 %). So in the layer upset (the
    film zone's reference 120 -> 150 N at 2 s) every tension of the two runs agrees to
    0.15 % of the run's largest excursion (measured 0.008 N of 31 N, 0.03 %), and at t = 0
    (ω = ω_ref) the torques are the same to rounding (without the addition the rewind would
    miss b ω / n = 1.56 N·m all along)."""
    runs = [webline.simulate(load_branched(_laminator(w)), scenario="layer-upset")
            for w in (False, True)]
    plain, wound = (r.dataset for r in runs)
    excursion = float(np.max(np.abs(plain.tension.values - plain.tension.values[0])))
    assert excursion > 25.0  # (the 30 N step)
    assert np.max(np.abs(wound.tension.values - plain.tension.values)) < 1.5e-3 * excursion
    first = np.abs(wound.torque_cmd.values[0] - plain.torque_cmd.values[0])
    assert np.max(first) < 1e-9


def test_the_linear_closed_loop_takes_the_winders_friction_on_the_measured_speed():
    """The linear law of the winder's line (b_c ω / n on the measured ω, the law's own
    friction model 0) against the plain one (b ω_ref / n in u_eq): the same 0.15 % more
    speed feedback on the rewind, so every closed-loop mode within 0.15 % of the plain
    line's (measured 0.066 %)."""
    modes = []
    for winder in (False, True):
        plan = compile_branches(load_branched(_laminator(winder)))
        decentral.prepare(plan)
        modes.append(np.linalg.eigvals(branch_linear_model(plan, operating_point(plan)).a))
    plain, wound = modes
    assert max(np.min(np.abs(wound - m)) / abs(m) for m in plain) < 1.5e-3


def test_open_loop_with_a_state_feedback_drive_is_refused_on_the_cli(tmp_path):
    """Open loop replaces the drive's controller (its speed limiter runs on the cascaded PI's
    speed gains, which a state-feedback drive does not have): one line naming the key,
    exit 2."""
    import tomli_w
    from typer.testing import CliRunner

    from webline.cli import app

    data = _laminator(False)
    rewind = next(r for r in data["rollers"] if r["name"] == "rewind")
    rewind["winder"] = {"mode": "open_loop"}
    bad = tmp_path / "bad.toml"
    bad.write_bytes(tomli_w.dumps(data).encode("utf-8"))
    result = CliRunner().invoke(app, ["run", str(bad), "-o", str(tmp_path / "o")])
    assert result.exit_code == 2, result.output
    lines = [line for line in result.output.splitlines() if line.strip()]
    assert len(lines) == 1 and "rollers[6].winder.mode" in lines[0], result.output
    assert "open_loop replaces the drive's 'state_feedback' controller" in lines[0]
