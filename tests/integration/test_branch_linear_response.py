"""The linear model of a branched line against its simulation: a small tension-reference step
on the laminator's film zone, run on the compiled kernel with the sampled controllers, and the
closed-loop linear model's step response (docs/branching.md, "Linear models")."""

from __future__ import annotations

import tomllib

import numpy as np
import pytest
from scipy.linalg import expm

from webline.data import lines
from webline.sim.branches.equilibrium import operating_point
from webline.sim.branches.linear import branch_linear_model
from webline.sim.branches.plan import compile_branches
from webline.sim.branches.run import simulate_branches

STEP_AT, STEP, DURATION = 1.0, 2.0, 4.0  # [s], [N], [s]
ZONES = ("film_zone", "foil_zone", "laminate_zone")


def _laminator(step: float) -> dict:
    from pathlib import Path

    data = tomllib.loads((Path(lines.__file__).parent / "laminator.toml").read_text())
    data.pop("scenarios")
    data["webs"][0]["spans"][1]["tension"] = {
        "type": "steps", "initial": "120 N", "steps": [{"time": f"{STEP_AT} s",
                                                        "value": f"{120 + step} N"}]}
    return data


@pytest.fixture(scope="module")
def responses():
    """(time, simulated deviation, linear deviation) per zone after the step."""
    runs = [simulate_branches(_laminator(step), DURATION) for step in (0.0, STEP)]
    ds0, ds1 = (r.dataset for r in runs)
    time = ds1["time"].values
    after = time >= STEP_AT
    plan = compile_branches(runs[1].plan.line)
    model = branch_linear_model(plan, operating_point(plan), "closed")
    n = model.a.shape[0]
    u = model.b[:, model.inputs.index("film_zone_tension_ref")] * STEP
    augmented = np.zeros((n + 1, n + 1))  # x(τ) = ∫ e^{Aσ} dσ B u: the corner of expm
    augmented[:n, :n], augmented[:n, n] = model.a, u
    out = {}
    for zone in ZONES:
        simulated = (ds1["tension"].sel(span=zone) - ds0["tension"].sel(span=zone)).values
        row = model.c[model.outputs.index(f"{zone}_tension")]
        linear = [row @ expm(augmented * (t - STEP_AT))[:n, n] for t in time[after]]
        out[zone] = (time[after], simulated[after], np.array(linear))
    return out


@pytest.mark.parametrize("zone", ZONES)
def test_linear_step_response_matches_the_simulation(responses, zone):
    _, simulated, linear = responses[zone]
    peak = np.max(np.abs(linear))
    assert peak > 0.05 * STEP  # each zone feels the film's step (the foil through the nip)
    # what differs: the controllers run sampled at 1 kHz with a held torque (a delay of
    # ~0.5 ms, 0.06 rad of phase at the fastest loop's 120 rad/s, ~1e-2 of a response that
    # loop shapes) and the plant's second-order terms (ΔT Δv, ~STEP/EA, 1e-5); 5 % of the
    # peak leaves room for the first and catches a wrong pole or gain (each moves the
    # response by tens of %)
    assert np.max(np.abs(simulated - linear)) < 0.05 * peak, np.max(np.abs(simulated - linear))


def test_the_film_zone_settles_at_its_new_reference(responses):
    _, simulated, linear = responses["film_zone"]
    # both end within 2 % of the step 3 s after it: the slowest film-zone pole has |Re λ| 6.6
    assert abs(simulated[-1] - STEP) < 0.02 * STEP and abs(linear[-1] - STEP) < 0.02 * STEP
