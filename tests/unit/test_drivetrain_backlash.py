"""Solid-motion analysis of backlash (thesis 3.1-3.10) against a direct simulation with plastic
impacts, and the zero-gap limit of the backlash models (3.22), (3.31)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from webline.analysis.drivetrain import backlash as sm
from webline.analysis.drivetrain import belt
from webline.analysis.drivetrain.backlash_bounds import simulate_loop
from webline.analysis.drivetrain.params import BacklashDrive, BeltDrive, SpeedPI
from webline.physics import backlash as bl
from webline.physics import belt as belt_physics

BASE = sm.SolidMotionCase(m_motor=10.0, m_load=20.0, half_gap=2.5e-4, force=30.0,
                          omega=2 * math.pi)


def with_ratio(rho: float) -> sm.SolidMotionCase:
    """BASE with the half gap that gives ρ = br/Y."""
    return sm.SolidMotionCase(BASE.m_motor, BASE.m_load,
                              BASE.half_gap * rho / sm.gap_ratio(BASE), BASE.force, BASE.omega)


def test_reduced_gap():
    """(3.10): br = 2Δ Mm/(Mm + ML); ML >> Mm makes it vanish, ML << Mm gives the full 2Δ."""
    assert sm.reduced_gap(10.0, 20.0, 0.3) == pytest.approx(0.2)
    assert sm.reduced_gap(1.0, 1e9, 0.3) == pytest.approx(0.0, abs=1e-9)
    assert sm.reduced_gap(1e9, 1.0, 0.3) == pytest.approx(0.6)


@pytest.mark.parametrize("rho", [0.05, 1.0, 2.5, 8.0])
def test_construction_equals_direct_simulation_with_plastic_impacts(rho):
    """The solid-motion construction (Figs 3.5-3.8) reproduces a direct simulation of
    (3.1)-(3.2) in xm, xL with event-located plastic impacts, including the irregular regime
    ρ > π; agreement to 1e-8 of V and of Y (the direct run's rtol is 1e-11)."""
    case = with_ratio(rho)
    segments = sm.construct(case, 6)
    vamp, yamp = case.speed_amplitude, case.speed_amplitude / case.omega
    for t, y in sm.simulate_plastic(case, 6):
        if t.size < 3:
            continue
        inner = slice(1, -1)  # the end points sit on impacts, where speeds jump
        motion = sm.sample(case, segments, t[inner])
        assert np.abs(motion.x_motor - y[0][inner]).max() < 1e-8 * yamp
        assert np.abs(motion.x_load - y[2][inner]).max() < 1e-8 * yamp
        assert np.abs(motion.motor_velocity - y[1][inner]).max() < 1e-8 * vamp
        assert np.abs(motion.load_velocity - y[3][inner]).max() < 1e-8 * vamp


def test_deviations_from_the_solid_motion():
    """(3.6)-(3.8): Mm żm + ML żL = 0 (opposite deviations, Fig. 3.6), the centre of mass is the
    solid motion, and |xm - xL| never exceeds Δ; the load's speed is the solid's in contact and
    constant in between, separating at the solid speed's peaks (Fig. 3.5)."""
    case = with_ratio(1.0)
    segments = sm.construct(case, 3)
    t = np.linspace(segments[0].t0, segments[-1].t1, 4001)
    mo = sm.sample(case, segments, t)
    assert np.allclose(case.m_motor * mo.motor_deviation_velocity
                       + case.m_load * mo.load_deviation_velocity, 0.0, atol=1e-12)
    centre = (case.m_motor * mo.x_motor + case.m_load * mo.x_load) / case.mass
    assert np.allclose(centre, mo.y, atol=1e-15)
    assert np.abs(mo.x_motor - mo.x_load).max() <= case.half_gap * (1 + 1e-9)
    for s in segments:
        if s.kind == "free" and s.t0 > segments[0].t0:
            phase = (case.omega * s.t0) % (2 * math.pi)
            assert min(abs(phase - 0.5 * math.pi), abs(phase - 1.5 * math.pi)) < 1e-9


@pytest.mark.parametrize("rho", [1e-3, 0.3, 1.0, 2.0, 3.0])
def test_harmonic_gain_and_phase(rho):
    """Gain and phase of the load speed's fundamental (end of Sec. 3.2): the exact segment
    integrals of the construction equal the closed form, which has the limits M = 1, φ = 0 at
    ρ = 0 and the square wave's 4/π, -π/2 at ρ = π; the lag grows with the gap."""
    gain, phase = sm.harmonic_gain_phase(with_ratio(rho))
    closed_gain, closed_phase = sm.harmonic_gain_phase_closed_form(rho)
    assert gain == pytest.approx(closed_gain, rel=1e-10)
    assert phase == pytest.approx(closed_phase, abs=1e-10)
    assert 1.0 <= gain <= 4 / math.pi + 1e-12 and -math.pi / 2 <= phase <= 0.0
    assert sm.harmonic_gain_phase_closed_form(0.0) == (pytest.approx(1.0), pytest.approx(0.0))
    near_pi = sm.harmonic_gain_phase_closed_form(math.pi - 1e-9)
    assert near_pi == (pytest.approx(4 / math.pi), pytest.approx(-math.pi / 2, abs=1e-6))
    assert sm.harmonic_gain_phase_closed_form(rho)[1] > sm.harmonic_gain_phase_closed_form(
        min(rho * 1.1, 3.1))[1]


def test_zero_gap_solid_motion_is_the_rigid_pair():
    """With Δ = 0 the construction and the direct simulation both move the masses as one solid:
    load speed = motor speed = ẏ, gain 1, phase 0."""
    case = sm.SolidMotionCase(BASE.m_motor, BASE.m_load, 0.0, BASE.force, BASE.omega)
    assert sm.harmonic_gain_phase(case) == (pytest.approx(1.0), pytest.approx(0.0, abs=1e-12))
    for t, y in sm.simulate_plastic(case, 3):
        solid = case.speed_amplitude * np.sin(case.omega * t)
        assert np.allclose(y[1], solid, atol=1e-9) and np.allclose(y[3], solid, atol=1e-9)


def _run(rhs, x0, t_end=2.0):
    t = np.linspace(0.0, t_end, 401)
    return solve_ivp(rhs, (0.0, t_end), x0, t_eval=t, rtol=1e-10, atol=1e-12).y


def test_zero_gap_backlash_models_equal_their_linear_models_exactly():
    """Must-show: with a zero gap the shaft model (3.22) IS (3.46) and the belt-and-gear model
    (3.31) IS the belt model (2.10) with R2 -> α1: the right-hand sides return the same floats,
    so the simulated trajectories are bitwise identical; and the decomposed loop (3.52) with
    β = 1 is bitwise the backlash-free loop (3.54)."""
    mm, ml, bm, b_l, k = 2.28, 2.55, 0.05, 0.05, 200.0

    def force(t):
        return 3.0 * math.sin(7.0 * t), -1.0 * math.cos(3.0 * t)

    def shaft(spring):
        def rhs(t, s):
            fm, fl = force(t)
            psi = spring(s[0], s[2])
            return [s[1], (fm - bm * s[1] - psi) / mm, s[3], (fl - b_l * s[3] + psi) / ml]
        return rhs

    x0 = [0.01, 0.0, -0.02, 0.1]
    with_backlash = _run(shaft(lambda a, b: bl.shaft_backlash_force(a, b, k, 0.0, 0.0)), x0)
    linear = _run(shaft(lambda a, b: k * (a - b)), x0)
    assert np.array_equal(with_backlash, linear)

    drive = BeltDrive(0.2, 2.13, 0.02, 0.1, 0.1146, 0.0573, 4.716e4)
    r1, a1, a2 = drive.r_motor, drive.r_load, 0.7  # unit gear ratio: α1 = R2

    def belted(belt_force):
        def rhs(t, s):
            tm, tl = force(t)
            f = belt_force(s[0], s[2])
            return [s[1], (tm - drive.b_motor * s[1] - r1 * f) / drive.j_motor, s[3],
                    (tl - drive.b_load * s[3] + a1 * f) / drive.j_load]
        return rhs

    x0 = [0.0, 1.0, 0.0, 2.0]
    gear = _run(belted(lambda a, b: bl.belt_gear_backlash_force(a, b, drive.stiffness, r1, a1,
                                                                 a2, 0.0, 0.0)), x0, 0.5)
    plain = _run(belted(lambda a, b: belt_physics.tight_side_force(a, b, r1, a1,
                                                                    drive.stiffness)), x0, 0.5)
    assert np.array_equal(gear, plain)
    a, b = belt.open_loop_matrices(drive)  # (2.10) in matrix form, other rounding
    matrix = _run(lambda t, s: a @ s + b @ np.array(force(t)), x0, 0.5)
    assert np.allclose(gear, matrix, rtol=1e-7, atol=1e-9)

    plant = BacklashDrive.rectilinear(mm, ml, bm, b_l, k, 0.0)
    t = np.linspace(0.0, 2.0, 201)
    gains = SpeedPI(50.0, 300.0)
    ref = lambda s: 0.2 * math.sin(6.0 * s)  # noqa: E731
    assert np.array_equal(simulate_loop(plant, gains, ref, t, backlash=True),
                          simulate_loop(plant, gains, ref, t, backlash=False))
