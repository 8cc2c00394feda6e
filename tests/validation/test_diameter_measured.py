"""The diameter calculator measures as the controllers do (issue 21, docs/winder.md W2):
speed noise reaches it through the controllers' own measurement (same noise samples), makes
diameter noise of the size first principles give, and its line-speed source (master, a
measuring roller, the reference) is chosen in the line file."""

from __future__ import annotations

import math

import numpy as np
import pytest

import webline
from webline.sim.core.plan import compile_plan
from webline.sim.elements import layout as L
from webline.sim.elements.signals import gaussian

SIGMA = 0.01  # speed noise [m/s]
TAU = 0.05  # the calculator's filter [s] (converter: 0.2 s; shorter: more samples per run)
DT = 1e-3  # converter's 1 kHz controllers [s]
SEED = 3
GUIDE_OUT = 6  # the idle roller before the rewind (node)


def noisy_converter(source: str) -> webline.Line:
    changes: dict[str, object] = {
        "rollers.rewind.diameter.filter": TAU,
        "disturbances": [{"type": "measurement_noise", "speed": SIGMA, "seed": SEED}]}
    if source != "master":  # the default
        changes["rollers.rewind.diameter.line_speed"] = source
    return webline.load_line("converter").replace(changes)


def run(source: str):
    """(result, ticks, recorded calculated radius, line speed the calculator divides without
    its noise, its noise [m/s], the spindle's true ω [rad/s], its noise [m/s]) over 8 s at
    300 m/min."""
    result = webline.simulate(noisy_converter(source), 8.0)
    line, plan = result.line, result.plan
    n_d = len(line.drives)
    rewind = line.drives.index(line.n_nodes - 1)
    ticks = np.rint(result.time / DT).astype(int)
    omega = result.states[:, plan.state_names.index("rewind.omega")]
    spindle_noise = SIGMA * np.array([gaussian(SEED, k, 2 * rewind) for k in ticks])
    if source == "reference":
        v_line, line_noise = np.full(len(ticks), 5.0), np.zeros(len(ticks))
    else:
        node = line.master if source == "master" else GUIDE_OUT
        channel = 2 * line.drives.index(node) if node in line.drives else 3 * n_d + node
        v_line = (line.spec.rollers[node].radius
                  * result.states[:, plan.state_names.index(f"{line.node_name(node)}.omega")])
        line_noise = SIGMA * np.array([gaussian(SEED, k, channel) for k in ticks])
    return result, result.control_radius[:, rewind], v_line, line_noise, omega, spindle_noise


def filtered(raw: np.ndarray, start: float) -> np.ndarray:
    """The calculator's filter R_j = R_{j-1} + α (raw_j - R_{j-1}), α = dt/τ, from ``start``."""
    out, value, alpha = np.empty(len(raw)), start, DT / TAU
    for j, x in enumerate(raw):
        value += alpha * (x - value)
        out[j] = value
    return out


def expected_std(radius: float, speed: float, noisy_speeds: int) -> float:
    """First principles: R_raw = v_line / ω with ω = ω_true + σ g / R and v_line = v + σ g'
    (independent, one or two noisy speeds): δR_raw / R = (σ / v) (g' - g), std R (σ/v) √n.
    The filter R += α (R_raw - R), α = dt/τ, passes a variance α / (2 - α) of white noise."""
    alpha = DT / TAU
    return radius * SIGMA / speed * math.sqrt(noisy_speeds) * math.sqrt(alpha / (2 - alpha))


@pytest.mark.parametrize(("source", "noisy_speeds"),
                         [("master", 2), ("reference", 1), ("guide_out", 2)])
def test_speed_noise_reaches_the_diameter_as_first_principles_give(source, noisy_speeds):
    result, calc, v_line, line_noise, omega, spindle_noise = run(source)
    # the same measurement as the controllers': the recorded diameter is the filter of
    # (v_line + noise') / (ω + noise / R) with the controllers' very noise samples, exactly
    previous = np.r_[calc[0], calc[:-1]]
    raw = (v_line + line_noise) / (omega + spindle_noise / previous)
    replay = previous + DT / TAU * (raw - previous)
    np.testing.assert_allclose(calc[1:], replay[1:], rtol=0.0, atol=1e-12)
    # its noise: the recorded diameter less the filter of the true speeds' ratio (what the
    # loops do to the true speeds is physics, not measurement noise) has the std of the
    # formula; 12 %: 8 s hold ~80 filter correlation times (sample std to ~8 %)
    noise = calc - filtered(v_line / omega, calc[0])
    after = result.time >= 0.5
    expected = expected_std(float(np.mean(calc)), 5.0, noisy_speeds)
    assert np.std(noise[after]) == pytest.approx(expected, rel=0.12)


def test_the_line_speed_source_column():
    for source, column in (("reference", L.DSOURCE_REFERENCE), ("master", L.DSOURCE_MASTER),
                           ("guide_out", GUIDE_OUT)):
        plan = compile_plan(noisy_converter(source))
        assert plan.drives[plan.line.drives.index(plan.line.n_nodes - 1), L.D_DSOURCE] == column


def test_a_source_that_is_no_roller_is_refused():
    from webline.errors import LineFileError

    with pytest.raises(LineFileError) as info:
        noisy_converter("drumm")
    assert info.value.key == "rollers[7].diameter.line_speed"


def test_speed_resolution_reaches_the_calculator_as_the_controllers():
    # no noise, an encoder resolution of 1 mm/s: every measured surface speed is a multiple
    # of it, the spindle's with the radius its drive knows; the recorded diameter replays
    # from the rounded speeds exactly
    q = 1e-3
    line = webline.load_line("converter").replace({
        "rollers.rewind.diameter.filter": TAU,
        "disturbances": [{"type": "measurement_noise", "speed_resolution": q}]})
    result = webline.simulate(line, 1.0)
    plan = result.plan
    calc = result.control_radius[:, line.drives.index(line.n_nodes - 1)]
    omega = result.states[:, plan.state_names.index("rewind.omega")]
    v_line = 0.2 * result.states[:, plan.state_names.index("drum.omega")]

    def rounded(v: np.ndarray) -> np.ndarray:
        return q * np.floor(v / q + 0.5)

    previous = np.r_[calc[0], calc[:-1]]
    raw = rounded(v_line) / (rounded(previous * omega) / previous)
    replay = previous + DT / TAU * (raw - previous)
    np.testing.assert_allclose(calc[1:], replay[1:], rtol=0.0, atol=1e-12)
    # the rounding is felt: the diameter differs from the one of exact speeds by up to
    # R q / v ~ 2e-5 m per sample before the filter
    exact = filtered(v_line / omega, calc[0])
    assert 1e-7 < np.abs(calc - exact).max() < 1e-4
