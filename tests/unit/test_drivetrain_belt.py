"""Belt drive: transfer functions, characteristic polynomials, sensitivities, natural frequencies
and the Lyapunov function of Theorem 2.2.1 (thesis 2.10-2.25, 2.35-2.41)."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import solve_ivp

from webline.analysis.drivetrain import belt
from webline.analysis.drivetrain import equivalent as eq
from webline.analysis.drivetrain.params import BeltDrive, SpeedPI

DRIVE = BeltDrive(j_motor=0.3, j_load=1.7, b_motor=0.02, b_load=0.15, r_motor=0.11,
                  r_load=0.06, stiffness=4e4)
GAINS = SpeedPI(kp=3.0, ki=40.0)
FREQS = np.array([0.3, 2.0, 9.0, 40.0, 250.0])  # rad/s, across the belt mode


def drives():
    return st.builds(
        BeltDrive,
        j_motor=st.floats(0.01, 10.0), j_load=st.floats(0.01, 10.0),
        b_motor=st.floats(1e-3, 1.0), b_load=st.floats(1e-3, 1.0),
        r_motor=st.floats(0.02, 0.5), r_load=st.floats(0.02, 0.5),
        stiffness=st.floats(1e2, 1e6))


def gains():
    return st.builds(SpeedPI, kp=st.floats(0.01, 100.0), ki=st.floats(0.01, 1000.0))


def _eig_with_tolerance(a: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Eigenvalues of ``a`` and the attainable accuracy of the coefficients of prod(s - λ).

    A backward-stable eig perturbs each λ_i by about u ‖A‖ κ_i (κ_i = 1/|y_iᴴ x_i|, the
    eigenvalue condition number); propagated through the elementary symmetric functions of the
    moduli, with a factor 100 of margin, plus 1e-12 relative."""
    lam, left, right = scipy.linalg.eig(a, left=True, right=True)
    kappa = 1.0 / np.abs(np.sum(left.conj() * right, axis=0))
    delta = 100 * np.finfo(float).eps * np.linalg.norm(a, 2) * kappa
    moduli = np.poly(-np.abs(lam)).real
    return lam, np.poly(-(np.abs(lam) + delta)).real - moduli + 1e-12 * moduli


@settings(max_examples=60, deadline=None)
@given(drives(), gains(), st.sampled_from(["motor", "load"]))
def test_char_poly_coefficients_equal_those_of_the_state_matrix_eigenvalues(drive, pi, feedback):
    """Must-show: (2.19) ('motor') and (2.17) ('load') equal the coefficients of
    prod(s - λ_i) over the eigenvalues of the full closed-loop state matrix, for random
    positive parameters. Two state matrices: the 4-state loop with the integral on the angle,
    and the 5-state loop with the PI integrator (whose extra eigenvalue is the rigid rotation, 0).
    Tolerance: what floating-point eigenvalues allow (``_eig_with_tolerance``).
    """
    expected = belt.char_poly(drive, pi, feedback)
    lam4, tol4 = _eig_with_tolerance(belt.homogeneous_matrix(drive, pi, feedback))
    assert np.all(np.abs(np.poly(lam4).real - expected) <= tol4)
    a5, _ = belt.closed_loop_matrices(drive, pi, feedback)
    lam5 = np.linalg.eigvals(a5)
    zero = np.argmin(np.abs(lam5))
    assert abs(lam5[zero]) <= 1e-9 * np.abs(lam5).max()
    rest = np.delete(lam5, zero)
    # the 5-state matrix has the same four non-zero eigenvalues: compare them to lam4
    assert np.all(np.abs(np.poly(rest).real - expected) <= 10 * tol4)


def _freq(sys, w):
    return np.asarray(sys(1j * w)).squeeze()


def test_open_loop_transfer_functions_match_the_state_space_model():
    """(2.14a), (2.14b) with D(s) of (2.15c) equal C(sI - A)⁻¹B of (2.10)."""
    ss = belt.open_loop_ss(DRIVE)
    g_m, g_l = belt.open_loop_tf(DRIVE)
    for w in FREQS:
        h = np.asarray(ss(1j * w))
        assert _freq(g_m, w) == pytest.approx(h[0, 0], rel=1e-10)
        assert _freq(g_l, w) == pytest.approx(h[1, 0], rel=1e-10)


def test_static_gain_needs_the_corrected_beq():
    """E-2.1: (2.15b) prints beq = R2² bm + R1² JL. The steady speed under a constant torque is
    τ/beq,m (the belt is then rigid), so ωm/τm at s = 0 must be R2²/(R2² bm + R1² bL)."""
    g_m, _ = belt.open_loop_tf(DRIVE)
    assert _freq(g_m, 0.0) == pytest.approx(1.0 / eq.damping_motor_side(DRIVE), rel=1e-12)
    printed_beq = DRIVE.r_load**2 * DRIVE.b_motor + DRIVE.r_motor**2 * DRIVE.j_load
    assert DRIVE.r_load**2 / printed_beq != pytest.approx(_freq(g_m, 0.0), rel=0.1)


@pytest.mark.parametrize("feedback", ["motor", "load"])
def test_closed_loop_transfer_function_matches_state_space(feedback):
    """(2.16)/(2.18)/(2.39): ωL/ω_ref from the printed numerator over (2.17)/(2.19) equals the
    response of the 5-state loop."""
    tf = belt.closed_loop_tf(DRIVE, GAINS, feedback)
    ss = belt.closed_loop_ss(DRIVE, GAINS, feedback)
    for w in FREQS:
        assert _freq(tf, w) == pytest.approx(np.asarray(ss(1j * w))[1, 0], rel=1e-9)


def _fd_sensitivity(make, w, rel=1e-6):
    up = _freq(make(DRIVE.stiffness * (1 + rel)), w)
    down = _freq(make(DRIVE.stiffness * (1 - rel)), w)
    return (up - down) / (2 * rel) / _freq(make(DRIVE.stiffness), w)


def test_sensitivities_to_belt_stiffness_match_finite_differences():
    """(2.38) and (2.41): S = (∂T/∂Kb)(Kb/T) against a central difference in Kb (step 1e-6,
    truncation ~1e-12, rounding ~1e-10 relative)."""
    s_vel = belt.velocity_mode_sensitivity(DRIVE)
    s_tor = belt.torque_mode_sensitivity(DRIVE, GAINS)
    for w in FREQS:
        fd_vel = _fd_sensitivity(lambda kb: belt.velocity_mode_tf(DRIVE.with_stiffness(kb)), w)
        fd_tor = _fd_sensitivity(
            lambda kb: belt.closed_loop_tf(DRIVE.with_stiffness(kb), GAINS, "motor"), w)
        assert _freq(s_vel, w) == pytest.approx(fd_vel, rel=1e-6, abs=1e-9)
        assert _freq(s_tor, w) == pytest.approx(fd_tor, rel=1e-6, abs=1e-9)


def test_natural_frequencies():
    """(2.37) and the two-inertia torque mode: exact without friction (the undamped poles of
    (2.36) and of D(s)), and the torque mode tends to the velocity mode as Jm → ∞ (a motor of
    infinite inertia is a perfect velocity source)."""
    frictionless = BeltDrive(0.3, 1.7, 0.0, 0.0, 0.11, 0.06, 4e4)
    nf = belt.natural_frequencies(frictionless)
    assert nf.velocity_mode == pytest.approx(np.sqrt(4e4 * 0.06**2 / 1.7))
    assert nf.velocity_mode_damped == pytest.approx(nf.velocity_mode, rel=1e-12)
    assert nf.torque_mode_damped == pytest.approx(nf.torque_mode, rel=1e-10)
    assert nf.velocity_mode_hz == pytest.approx(nf.velocity_mode / (2 * np.pi))
    heavy = BeltDrive(1e9, 1.7, 0.0, 0.0, 0.11, 0.06, 4e4)
    assert belt.natural_frequencies(heavy).torque_mode == pytest.approx(nf.velocity_mode,
                                                                        rel=1e-6)
    damped = belt.natural_frequencies(DRIVE)
    assert damped.velocity_mode_damped < damped.velocity_mode


def _simulate(drive, pi, omega_ref, x0, t_end=3.0):
    a, b = belt.closed_loop_matrices(drive, pi, "motor")
    t = np.linspace(0.0, t_end, 3001)
    sol = solve_ivp(lambda _t, x: a @ x + b * omega_ref, (0.0, t_end), x0, t_eval=t,
                    rtol=1e-11, atol=1e-12, method="DOP853")
    return t, sol.y.T


@settings(max_examples=12, deadline=None)
@given(drives(), gains(), st.floats(-50.0, 50.0), st.integers(0, 2**31 - 1))
def test_lyapunov_function_does_not_increase_with_motor_side_pi(drive, pi, omega_ref, seed):
    """Must-show: V of (2.23) is non-increasing along simulated closed-loop trajectories with
    motor-side PI (Theorem 2.2.1), from a random initial state and a speed step. Tolerance:
    1e-7 V(0) per sample for integrator error (rtol 1e-11)."""
    drive = drive.with_stiffness(min(drive.stiffness, 1e4))  # keeps the run short
    x0 = np.random.default_rng(seed).normal(size=5)
    _, xs = _simulate(drive, pi, omega_ref, x0, t_end=1.0)
    v = np.array([belt.lyapunov(drive, pi, omega_ref, x) for x in xs])
    assert np.all(np.diff(v) <= 1e-7 * v[0])
    assert v[-1] <= v[0]


def test_lyapunov_rate_is_the_time_derivative_of_v():
    """(2.24): dV/dt = -(bm + Kpm) ėm² - bL ėL² equals the numerical derivative of V along a
    trajectory (central differences on a 1 ms grid: error ~1e-6 relative)."""
    x0 = np.array([0.1, -2.0, 0.3, 1.0, 0.05])
    t, xs = _simulate(DRIVE.with_stiffness(4e3), GAINS, 10.0, x0, t_end=0.5)
    drive = DRIVE.with_stiffness(4e3)
    v = np.array([belt.lyapunov(drive, GAINS, 10.0, x) for x in xs])
    rate = np.array([belt.lyapunov_rate(drive, GAINS, 10.0, x) for x in xs])
    numeric = np.gradient(v, t)
    inner = slice(5, -5)
    assert np.allclose(numeric[inner], rate[inner], rtol=1e-3, atol=1e-4 * np.abs(rate).max())
    assert np.all(rate <= 0.0)
