"""Thesis Appendix B (the ECP listing of Sec. 3.5), docs/errata.md E-B.1 to E-B.4: what the
printed code computes, emulated statement by statement, and its PI sampled at its ts."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

from webline.analysis.drivetrain.params import load_parameter_set
from webline.analysis.drivetrain.sampled import equivalent_eigenvalues, sampled_pi, spectral_radius

TS = 0.035360  # the listing's ts [s]
DEFINES = """#define kp q1
#define i q2
#define error q3
#define sum_error q4
#define vm q11
#define vd q5
#define ts q7
#define pi q8
#define time q9
#define i q20
#define past_pos q22"""  # the listing's user variables, as printed


def listing_tick(state: dict, enc1_pos: float, *, corrected: bool = False) -> None:
    """One pass of the listing's real-time block (its statement order; ``corrected`` moves
    ``past_pos=enc1_pos`` after ``vm``)."""
    if not corrected:
        state["past_pos"] = enc1_pos
    state["vd"] = 2266 * math.sin(2 * state["time"] * TS) / 2266.0
    state["time"] += 1
    if state["time"] > 5000:
        state["time"] = 0
    state["vm"] = (enc1_pos - state["past_pos"]) / TS / 2266.0 / 32
    if corrected:
        state["past_pos"] = enc1_pos


def test_speed_estimate_is_always_zero_as_printed():
    """E-B.2: with past_pos overwritten first, vm is 0 for any motion of mass 1; in the
    corrected order it is the backward difference (counts/sample / ts / 2266 / 32)."""
    counts = np.cumsum(np.random.default_rng(1).integers(-50, 200, 300)).astype(float)
    printed = {"time": 0, "past_pos": 0.0}
    fixed = {"time": 0, "past_pos": 0.0}
    for k, c in enumerate(counts):
        listing_tick(printed, c)
        listing_tick(fixed, c, corrected=True)
        assert printed["vm"] == 0.0
        if k:
            assert fixed["vm"] == pytest.approx((c - counts[k - 1]) / TS / 2266.0 / 32, rel=1e-12)


def test_reference_is_0_32_hz_and_jumps_at_the_wrap():
    """E-B.1: the listing's vd over 5000 samples peaks at 2/(2 pi) = 0.318 Hz in its spectrum,
    not the 3 Hz of Sec. 3.5; at the wrap it jumps from sin(353.6) = 0.985 to 0."""
    state = {"time": 0, "past_pos": 0.0}
    vd = []
    for _ in range(5001):
        listing_tick(state, 0.0)
        vd.append(state["vd"])
    n = 4096
    freq = np.fft.rfftfreq(16 * n, TS)
    peak = freq[np.argmax(np.abs(np.fft.rfft(np.asarray(vd[:n]) * np.hanning(n), 16 * n)))]
    assert peak == pytest.approx(1 / math.pi, rel=0.01)
    assert abs(peak - 3.0) > 2.5
    assert vd[5000] == pytest.approx(math.sin(2 * 5000 * TS)) and vd[5000] > 0.98
    listing_tick(state, 0.0)
    assert state["vd"] == 0.0


def test_ki_is_never_defined_and_i_twice():
    """E-B.3: the #define block has no ki and names i twice."""
    names = re.findall(r"#define (\w+) q\d+", DEFINES)
    assert "ki" not in names and names.count("i") == 2 and "kp" in names


def _ecp_loop(kp: float, ki_per_sample: float):
    p = load_parameter_set("ecp_rectilinear_sec3_5")["plant"]
    m1, m2, k = p["motor_mass"], p["load_mass"], p["stiffness"]
    b1, b2 = p["motor_damping"], p["load_damping"]
    a = np.array([[0, 1, 0, 0], [-k / m1, -b1 / m1, k / m1, 0], [0, 0, 0, 1],
                  [k / m2, 0, -k / m2, -b2 / m2]])
    return sampled_pi(a, np.array([0, 1 / m1, 0, 0]), 1, 0, kp, ki_per_sample / TS, TS,
                      "difference")


def test_kp_500_is_unstable_when_sampled():
    """E-B.4: kp = 500 N s/m, ki = 5 per sample, speed by backward difference, ts = 35.36 ms:
    largest |z| 1.98, i.e. s = +19.4 +- 68.3j 1/s; stable for 3.0 <= kp <= 117.5 N s/m (to the
    0.5 N s/m grid); webline's continuous ECP design (289.7 N s/m, 4347 N/m) also fails there."""
    loop = _ecp_loop(500.0, 5.0)
    assert spectral_radius(loop) == pytest.approx(1.98, abs=0.01)
    s = equivalent_eigenvalues(loop)
    worst = s[np.argmax(s.real)]
    assert worst.real == pytest.approx(19.4, abs=0.1)
    assert abs(worst.imag) == pytest.approx(68.3, abs=0.1)
    kps = np.arange(0.5, 200.0, 0.5)
    stable = [kp for kp in kps if spectral_radius(_ecp_loop(kp, 5.0)) <= 1 + 1e-9]
    assert min(stable) == pytest.approx(3.0) and max(stable) == pytest.approx(117.5)
    assert np.all(np.diff(stable) == 0.5)  # one interval
    assert spectral_radius(_ecp_loop(289.7, 4347.0 * TS)) == pytest.approx(1.88, abs=0.01)
