"""Backlash error bounds (thesis 3.33-3.66) and the shift of output statistics (4.9, 4.10)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from webline.analysis.drivetrain import backlash_bounds as bb
from webline.analysis.drivetrain.params import BacklashDrive, BeltDrive, SpeedPI
from webline.physics import backlash as bl

PLANT = BacklashDrive.rectilinear(2.28, 2.55, 0.05, 0.05, 200.0, 1e-3)
GAINS = SpeedPI(60.0, 600.0)


def reference(t: float) -> float:
    return 0.15 * math.sin(2 * math.pi * 1.5 * t)


def test_decomposed_model_is_the_backlash_model():
    """(3.63)-(3.65): A z + D φ equals the equations of motion (3.31) written with the force ψ
    of (3.32), for a belt-and-gear plant (α1 ≠ R2, α2 ≠ 1) at states on both sides of the gap."""
    drive = BeltDrive(0.2, 2.13, 0.02, 0.1, 0.1146, 0.0573, 4.716e4)
    plant = BacklashDrive.belt_and_gears(drive, rg1=0.05, rg2=0.08, half_gap=2e-4)
    loop = bb.backlash_loop(plant, SpeedPI(0.0, 0.0))
    rng = np.random.default_rng(3)
    for _ in range(50):
        z = np.append(rng.normal(scale=[1e-2, 1.0, 1e-2, 1.0]), 0.0)
        psi = bl.belt_gear_backlash_force(z[0], z[2], plant.stiffness, plant.r_motor,
                                          plant.lever_load, plant.gap_gain, plant.gap_neg,
                                          plant.gap_pos)
        phi = bl.belt_gear_backlash_deviation(z[0], z[2], plant.stiffness, plant.r_motor,
                                              plant.lever_load, plant.gap_gain, plant.gap_neg,
                                              plant.gap_pos)
        motion = np.array([
            z[1], (-drive.b_motor * z[1] - plant.r_motor * psi) / drive.j_motor,
            z[3], (-drive.b_load * z[3] + plant.lever_load * psi) / drive.j_load, -z[1]])
        assert np.allclose(loop.a @ z + loop.d * phi, motion, rtol=1e-9, atol=1e-9)


def test_deviation_is_the_convolution_of_phi():
    """(3.55)-(3.56): the backlash run minus the backlash-free run equals g(t) = ∫ e^{A(t-τ)} D φ
    dτ with φ taken along the backlash run (integrated jointly; agreement 1e-7 of the peak)."""
    loop = bb.backlash_loop(PLANT, GAINS)
    args = (PLANT.stiffness, 1.0, 1.0, 1.0, PLANT.gap_neg, PLANT.gap_pos)

    def rhs(t, s):
        z, g = s[:5], s[5:]
        phi = bl.belt_gear_backlash_deviation(z[0], z[2], *args)
        return np.concatenate([loop.a @ z + loop.w * reference(t) + loop.d * phi,
                               loop.a @ g + loop.d * phi])

    t = np.linspace(0.0, 4.0, 801)
    joint = solve_ivp(rhs, (0.0, 4.0), np.zeros(10), t_eval=t, rtol=1e-10, atol=1e-13,
                      method="DOP853").y
    linear = bb.simulate_loop(PLANT, GAINS, reference, t, backlash=False).T
    g = joint[5:]
    assert np.abs(joint[:5] - linear - g).max() < 1e-7 * np.abs(g).max()


def test_bound_ordering_and_validity_against_simulation():
    """For the load speed: printed (3.57) <= L1 bound (triangle inequality) and the simulated
    deviation <= L1 <= eigenvalue bound (3.62); the printed one is violated by the simulation:
    at t → ∞ it is ~0 because a constant φ leaves no steady speed error under PI control."""
    thesis, reduced = bb.backlash_loop(PLANT, GAINS), bb.backlash_loop(PLANT, GAINS, "reduced")
    c = thesis.load_speed
    printed, l1 = bb.printed_bound(thesis, output=c), bb.l1_bound(thesis, output=c)
    peak = bb.printed_bound_peak(thesis, output=c)
    eigen = bb.eigen_bound(reduced, output=reduced.load_speed)
    assert printed <= l1 and peak <= l1 <= eigen
    assert bb.l1_bound(reduced, output=reduced.load_speed) == pytest.approx(l1, rel=1e-6)
    t = np.linspace(0.0, 8.0, 2001)
    deviation = np.abs(bb.simulate_loop(PLANT, GAINS, reference, t)[:, 3]
                       - bb.simulate_loop(PLANT, GAINS, reference, t, backlash=False)[:, 3])
    assert deviation.max() <= l1
    assert deviation.max() > 2 * peak
    with pytest.raises(ValueError, match="Hurwitz"):
        bb.eigen_bound(thesis)


def test_worst_case_phi_attains_the_l1_bound_and_beats_the_printed_one():
    """φ = φmax sign(h(t - τ)) is admissible (|φ| <= φmax) and its response at t equals the L1
    bound (quadrature to 1e-4), which exceeds the printed bound (3.57) at the same t."""
    loop = bb.backlash_loop(PLANT, GAINS)
    t_end = 6.0
    tau, phi = bb.worst_case_phi(loop, t_end, loop.load_speed, samples=60000)
    assert np.abs(phi).max() <= loop.phi_max
    fine = bb._grid(loop.a, t_end, 60000)
    h = loop.load_speed @ bb._modal_response(loop.a, loop.d, fine, integrated=False)
    response = np.trapezoid(h[::-1] * phi, tau)
    l1 = bb.l1_bound(loop, t_end, loop.load_speed, samples=60000)
    assert response == pytest.approx(l1, rel=1e-4)
    assert response > 3 * bb.printed_bound(loop, t_end, loop.load_speed)


def test_printed_bound_is_exact_for_a_sign_definite_kernel():
    """When the kernel keeps one sign (an overdamped first-order loop) moving sup|φ| out of the
    integral is legitimate: printed = L1 bound (up to the trapezoid error, ~3e-7 here)."""
    loop = bb.BacklashLoop(a=np.array([[-2.0]]), w=np.zeros(1), f=np.zeros(1),
                           d=np.array([3.0]), load_speed=np.array([1.0]), phi_max=0.5)
    for t in (0.3, None):
        assert bb.printed_bound(loop, t, loop.load_speed) == pytest.approx(
            bb.l1_bound(loop, t, loop.load_speed), rel=1e-6)
    assert bb.printed_bound(loop, None) == pytest.approx(0.5 * 3.0 / 2.0)


def test_statistics_shift_of_4_9_and_4_10():
    """(4.9b), (4.10b) with the square and the sum restored reproduce the directly computed mean
    and standard deviation of T0 + Lp2 g; both shifts are below sup|Lp2 g|. The printed
    (4.10b), sqrt(σ0 + Σf/(n+1)), is not (E-4.2)."""
    rng = np.random.default_rng(11)
    t = np.arange(2000) * 1e-3
    t0 = 100.0 + 3.0 * np.sin(2 * np.pi * 5 * t) + rng.normal(scale=0.5, size=t.size)
    g = 0.8 * np.sin(2 * np.pi * 5 * t + 0.4) + 0.3
    shift = bb.statistics_shift(t0, g)
    assert shift.mean_with == pytest.approx(np.mean(t0 + g), rel=1e-13)
    assert shift.std_with == pytest.approx(np.std(t0 + g), rel=1e-12)
    assert shift.std_without == pytest.approx(np.std(t0), rel=1e-13)
    assert abs(shift.mean_shift) <= np.abs(g).max() and abs(shift.std_shift) <= np.abs(g).max()
    f = (g - g.mean()) ** 2 + 2 * (t0 - t0.mean()) * (g - g.mean())
    printed = math.sqrt(np.std(t0) + f.sum() / t.size)
    assert printed != pytest.approx(shift.std_with, rel=0.05)


def test_series_backlash_bound_3_41():
    """(3.36)-(3.41) for G1 = 1/(s + 1) and G2 = 4/(s² + 0.4 s + 4) (lightly damped, so its
    impulse response changes sign): a backlash y = u + f(u), |f| <= Δ, between them. The L1
    bound holds for the worst admissible f and the printed one does not."""
    loop = bb.series_backlash_loop(np.array([[-1.0]]), [1.0], [1.0],
                                   np.array([[0.0, 1.0], [-4.0, -0.4]]), [0.0, 4.0],
                                   [1.0, 0.0], half_gap=0.01)
    assert loop.a.shape == (3, 3) and loop.d.tolist() == [0.0, 0.0, 4.0]
    t_end = 15.0
    tau, phi = bb.worst_case_phi(loop, t_end, loop.load_speed, samples=60000)
    h = loop.load_speed @ bb._modal_response(loop.a, loop.d, t_end - tau[::-1],
                                             integrated=False)
    response = np.trapezoid(h[::-1] * phi, tau)
    assert response == pytest.approx(bb.l1_bound(loop, t_end, loop.load_speed), rel=1e-3)
    assert response > 2 * bb.printed_bound_peak(loop, t_end, loop.load_speed)
