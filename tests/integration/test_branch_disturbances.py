"""Disturbances on a branched line (docs/branching.md, "Disturbances"): roller drag, wound-in
and speed ripple, measurement noise, through the branch kernel."""

from __future__ import annotations

import re

import numpy as np
import pytest

import webline
from webline.errors import LineFileError
from webline.model.web_graph import load_branched

DRAG = 1.0  # N·m on the slitter's guide roller (radius 50 mm): 20 N across it


def _slitter(*disturbances: dict) -> dict:
    data = load_branched("slitter").spec.model_dump(exclude_none=True)
    data["disturbances"] = list(disturbances)
    return data


def _peak_frequency(t: np.ndarray, signal: np.ndarray) -> float:
    """The frequency [Hz] of the largest spectral line of ``signal`` (its mean removed)."""
    spectrum = np.abs(np.fft.rfft((signal - signal.mean()) * np.hanning(len(signal))))
    return float(np.fft.rfftfreq(len(signal), t[1] - t[0])[np.argmax(spectrum)])


def test_a_drag_on_an_idle_roller_raises_the_tension_after_it_by_drag_over_radius():
    """Steady idle roller: r (T_out - T_in) = b ω + Q (B4 with dω/dt = 0), so a drag Q
    stepped in at 1 s raises T_out - T_in by Q / r = 20 N at the same speed. The zone's
    loadcell is after the guide (unwind_zone, held at 300 N), so the span before it drops."""
    drag = {"type": "roller_drag", "roller": "guide",
            "torque": {"type": "steps", "initial": 0.0, "steps": [{"time": 1.0,
                                                                     "value": DRAG}]}}
    result = webline.simulate(load_branched(_slitter(drag)), 6.0)
    ds = result.dataset
    across = (ds.tension.sel(span="unwind_zone") - ds.tension.sel(span="base[0]")).values
    t = ds.time.values
    before = across[np.searchsorted(t, 0.99)]
    after = across[-1]
    # the tension loop (8 rad/s) has settled 5 s after the step (e^-40); left: the guide's
    # acceleration J dω/dt / r with the line speed held (< 1e-6 N) and the unwind's changing
    # radius (which moves the span's tension, not the difference across the guide)
    assert after - before == pytest.approx(DRAG / 0.05, abs=1e-3 * DRAG / 0.05)
    assert ds.tension.sel(span="unwind_zone").values[-1] == pytest.approx(300.0, abs=0.05)


def test_a_drag_from_t0_is_in_the_operating_point():
    """A constant drag is part of the steady line: the run starts with it and stays."""
    drag = {"type": "roller_drag", "roller": "guide", "torque": DRAG}
    ds = webline.simulate(load_branched(_slitter(drag)), 0.05).dataset
    across = (ds.tension.sel(span="unwind_zone") - ds.tension.sel(span="base[0]")).values
    assert across[0] == pytest.approx(DRAG / 0.05 + 1e-4 * 100.0 / 0.05, rel=1e-6)
    assert np.ptp(across) < 1e-3  # 0.005 % of the 20 N: a steady start


def test_measurement_noise_is_reproducible_from_its_seed():
    """Counter-based noise (``signals.gaussian``): the same seed gives the same run bit for
    bit; another seed another run."""
    def run(seed: int) -> np.ndarray:
        noise = {"type": "measurement_noise", "tension": 2.0, "speed": 0.001, "seed": seed}
        return webline.simulate(load_branched(_slitter(noise)), 0.5).dataset.tension.values

    first, again, other = run(7), run(7), run(8)
    assert np.array_equal(first, again)
    assert np.max(np.abs(first - other)) > 0.01  # 2 N noise through 8 rad/s loops


def test_noise_and_ripples_in_chunks_are_the_run_in_one_piece(monkeypatch):
    """The noise is drawn per (seed, tick, channel) and the ripples at each tick's time, so a
    run split into chunks of the compiled loop (``run.CHUNK``) is the same run bit for bit."""
    from webline.sim.branches import run

    line = load_branched(_slitter(
        {"type": "measurement_noise", "tension": 2.0, "speed": 0.001, "seed": 5},
        {"type": "wound_in_ripple", "amplitude": 20.0, "frequency": 2.0},
        {"type": "speed_ripple", "roller": "pull", "amplitude": 0.01, "frequency": 5.0}))
    whole = webline.simulate(line, 0.8)
    monkeypatch.setattr(run, "CHUNK", 177)
    chunked = webline.simulate(line, 0.8)
    assert np.array_equal(whole.rec, chunked.rec)


def test_a_wound_in_ripple_enters_the_unwinds_span_as_its_equation_says():
    """The unwind's first span (B1) in the slitter's (default) exact transport,
    L ds/dt = (EA + s)² [v_b/(EA + s) - v_a/(EA + s_in)] (docs/errata.md E-6.6; the span is
    taut, T = s), with the wound-in tension s_in = 280 N + 20 N sin(2π 2 Hz t) at each RK4
    stage's time (the chain's rule, docs/errata.md "One loop"), integrated on its own from the
    recorded speeds of the unwind and the guide, gives the run's tension to 0.1 % of its
    ripple (measured 3e-5: the speeds are linear between records, the kernel's RK4 stages see
    its own; the first-order equation (6.8) is 2.5 % off); and the ripple is at 2 Hz."""
    ripple = {"type": "wound_in_ripple", "amplitude": 20.0, "frequency": 2.0}
    line = load_branched(_slitter(ripple))
    assert line.exact  # the equation below is the exact one
    ds = webline.simulate(line, 4.0).dataset
    t = ds.time.values
    first = ds.tension.sel(span="base[0]").values
    v_a, v_b = ds.speed.sel(node="unwind").values, ds.speed.sel(node="guide").values
    ea, length, dt = 281.25e3, 2.0, t[1] - t[0]
    own = np.empty_like(first)
    own[0] = first[0]
    for n in range(len(t) - 1):  # RK4 over each tick, speeds linear in between

        def rate(x: float, share: float, n: int = n) -> float:
            va = v_a[n] + share * (v_a[n + 1] - v_a[n])
            vb = v_b[n] + share * (v_b[n + 1] - v_b[n])
            s_in = 280.0 + 20.0 * np.sin(2 * np.pi * 2.0 * (t[n] + share * dt))
            grow = ea + x
            return grow * grow * (vb / grow - va / (ea + s_in)) / length

        k1 = rate(own[n], 0.0)
        k2 = rate(own[n] + 0.5 * dt * k1, 0.5)
        k3 = rate(own[n] + 0.5 * dt * k2, 0.5)
        k4 = rate(own[n] + dt * k3, 1.0)
        own[n + 1] = own[n] + dt / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
    late = t >= 1.0  # three whole periods of 1 s ... 4 s: 2 Hz on a 0.33 Hz grid
    assert np.max(np.abs(own - first)) < 1e-3 * np.ptp(first[late])
    assert _peak_frequency(t[late], first[late]) == pytest.approx(2.0, abs=0.34)


def test_a_speed_ripple_shows_in_the_rollers_speed_at_its_frequency():
    ripple = {"type": "speed_ripple", "roller": "pull", "amplitude": 0.01, "frequency": 5.0}
    ds = webline.simulate(load_branched(_slitter(ripple)), 2.0).dataset
    t = ds.time.values
    speed = ds.speed.sel(node="pull").values
    late = t >= 0.4
    assert _peak_frequency(t[late], speed[late]) == pytest.approx(5.0, abs=0.7)


def test_an_eccentric_roller_ripples_the_tension_at_its_rotation_frequency():
    """The guide (r = 50 mm) 0.1 mm out of round at 5 m/s turns at 100 rad/s: its surface
    arm r + e cos θ ripples at ω / 2π = 15.9 Hz (docs/winder.md E1), and so does the tension
    of the span it feeds. An idle roller this light (J / r² = 0.8 kg) mostly turns faster and
    slower under the web instead of moving it (measured 1.03 N peak to peak, where a driven
    roller's e ω ripple would give ~28 N); the round guide's is steady (< 0.05 N)."""
    eccentric = {"type": "eccentric_roller", "roller": "guide", "eccentricity": 1e-4}
    ds = webline.simulate(load_branched(_slitter(eccentric)), 2.0).dataset
    t = ds.time.values
    late = t >= 0.5
    zone = ds.tension.sel(span="unwind_zone").values[late]
    omega = float(np.mean(ds.omega.sel(node="guide").values[late]))
    assert _peak_frequency(t[late], zone) == pytest.approx(omega / (2 * np.pi), abs=0.7)
    assert np.ptp(zone) > 0.5  # 20 times the round guide's
    round_run = webline.simulate(load_branched(_slitter()), 2.0).dataset
    assert np.ptp(round_run.tension.sel(span="unwind_zone").values[late]) < 0.05


@pytest.mark.parametrize("item, key, problem", [
    ({"type": "roller_drag", "roller": "nowhere", "torque": 1.0}, "disturbances[0].roller",
     "no roller named"),
    ({"type": "speed_ripple", "roller": "guide", "amplitude": 0.1, "frequency": 1.0},
     "disturbances[0].roller", "driven roller"),
    ({"type": "wound_in_ripple", "amplitude": 300.0, "frequency": 1.0},
     "disturbances[0].amplitude", "wound-in tension"),
    ({"type": "eccentric_roller", "roller": "guide", "eccentricity": 0.05},
     "disturbances[0].eccentricity", "below the roller radius"),
])
def test_a_bad_disturbance_is_one_line_naming_its_key(item, key, problem):
    with pytest.raises(LineFileError, match=re.escape(key) + ".*" + problem):
        load_branched(_slitter(item))


def test_a_wound_in_ripple_names_its_unwind_where_there_are_several():
    data = load_branched("laminator").spec.model_dump(exclude_none=True)
    data["disturbances"] = [{"type": "wound_in_ripple", "amplitude": 5.0, "frequency": 1.0}]
    with pytest.raises(LineFileError, match=r"disturbances\[0\]\.roller.*several unwinds"):
        load_branched(data)
