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


def _free_response(name: str, kick: dict[str, float], seconds: float):
    """(time, recorded states) of ``name`` run from its operating point with the states named
    in ``kick`` moved by their values (the loop of ``simulate_branches``, started off its
    equilibrium), and the closed-loop model there."""
    from webline.model.web_graph import load_branched
    from webline.sim.branches.linear import fastest_rate, kept_states
    from webline.sim.branches.loop import layout as B
    from webline.sim.branches.loop.kernel import new_records

    plan = compile_branches(load_branched(name))
    point = operating_point(plan)
    model = branch_linear_model(plan, point, "closed")
    plan.df[:, B.D_FF] = point.ratio
    x = point.x.copy()
    keep = kept_states(plan)
    for state, delta in kick.items():
        x[keep[model.states.index(state)]] += delta
    istate = np.zeros((plan.di.shape[0], B.I_COLS))
    istate[:, B.I_SPEED] = point.torque
    n_ticks = round(seconds / plan.dt)
    substeps = int(np.ceil(plan.dt * fastest_rate(plan, point) / 0.5))
    rec = new_records(n_ticks, 1, plan.n_x, plan.di.shape[0])
    n, status, _ = plan.run(x, istate, plan.wound.copy(), np.zeros(len(plan.events)), rec,
                            point.torque.copy(), 0, n_ticks, substeps, 1)
    assert status == B.STATUS_OK
    return rec[:n, 0], rec[:n, 1:1 + plan.n_x], model, keep


def test_lanes_difference_decays_in_the_run_at_the_models_rate():
    one, two = "lane_1_span_tension", "lane_2_span_tension"
    time, x, model, keep = _free_response("slitter", {one: 1.0, two: -1.0}, 1.5)
    diff = x[:, keep[model.states.index(one)]] - x[:, keep[model.states.index(two)]]
    # fit log ΔT = log ΔT0 + λ t over the run (the mode is alone: the kick is its eigenvector)
    rate = np.polyfit(time, np.log(diff), 1)[0]
    values = np.linalg.eigvals(model.a)
    expected = values[np.argmin(np.abs(values + 2.5))].real
    # the lanes grow alike (equal thickness), so nothing else drives the difference; RK4 at
    # h|λ| ~ 1e-3 for this mode errs ~1e-12: 1e-4 covers the records' rounding
    assert abs(rate - expected) < 1e-4 * abs(expected), (rate, expected)


def test_idler_mode_rings_in_the_run_at_the_models_frequency_and_damping():
    from scipy.optimize import curve_fit

    time, x, model, keep = _free_response("laminator", {"guide_laminate_omega": 0.5}, 1.0)
    omega = x[:, keep[model.states.index("guide_laminate_omega")]]
    signal = omega - np.polyval(np.polyfit(time, omega, 3), time)  # the slow modes out
    values = np.linalg.eigvals(model.a)
    mode = values[np.argmax(np.abs(values))]  # the guide's span mode, |λ| ~ 1038 1/s
    spectrum = np.abs(np.fft.rfft(signal))
    guess = 2 * np.pi * np.fft.rfftfreq(len(signal), time[1] - time[0])[np.argmax(spectrum)]

    def ring(t, a, sigma, w, phase):
        return a * np.exp(-sigma * t) * np.cos(w * t + phase)

    (_, sigma, w, _), _ = curve_fit(ring, time, signal, p0=(signal[0], 1.0, guess, 0.0))
    # the frequency to 0.1 % (measured 3e-5): the RK4 step's phase error, ~(h λ)^4/120 = 1e-4
    # per step at h|λ| = 0.35, is what may show; the damping (|Re λ| 1.45 1/s, ζ 0.0014) to
    # 10 % (measured 2 %): it is 1e-3 of the frequency, so RK4's amplitude error (~(h λ)^6/720
    # per step, 0.01 1/s) and the fit's residual of the other modes weigh on it
    assert abs(abs(w) - abs(mode.imag)) < 1e-3 * abs(mode.imag), (w, mode)
    assert abs(sigma + mode.real) < 0.1 * abs(mode.real), (sigma, mode)
