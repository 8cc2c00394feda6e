"""Scalar physics of web slip over a roller (thesis 5.9-5.13, 5.35-5.47, re-derived;
docs/errata.md)."""

from __future__ import annotations

import math

import numba
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import quad, solve_ivp

from webline.physics import slip as sl
from webline.studies.slip_chain import printed_slip_velocity

tension = st.floats(1.0, 1000.0)
ratio = st.floats(0.3, 3.0)
mu = st.floats(0.01, 0.6)
wrap = st.floats(0.05, 2 * math.pi)
frac = st.floats(0.0, 1.0)
t_c_frac = st.floats(0.0, 0.5)
viscous = st.floats(1.0, 1e5)


@given(tension, ratio, mu, wrap, t_c_frac)
def test_stiction_band_is_the_capstan_relation_both_ways(t_in, r, m, a, c):
    """(5.41) x μ0 (5.43), generalised to both slip directions: |F| within the stiction limit
    in the direction of F <=> e^{-μα} <= (t_out - t_c)/(t_in - t_c) <= e^{μα} (5.12)."""
    t_c = c * t_in
    t_out = t_c + r * (t_in - t_c)
    f = t_in - t_out
    limit = sl.stiction_limit(t_in, a, m, t_c, 1.0 if f > 0 else -1.0)
    held = abs(f) <= limit
    capstan = math.exp(-m * a) <= r <= math.exp(m * a)
    if abs(abs(math.log(r)) - m * a) > 1e-9:  # away from the boundary itself
        assert held == capstan
    assert sl.slip_state(t_in, t_out, a, m, 0.5 * m, t_c, 0) == (0 if held else 1)
    # the same limit read as the largest tension the other side holds (capstan_limit)
    lo, hi = min(t_in, t_out), max(t_in, t_out)
    assert (hi <= sl.capstan_limit(lo, m, a, t_c) * (1 + 1e-12)) == held or \
        abs(abs(math.log(r)) - m * a) <= 1e-9


@settings(deadline=None)  # solve_ivp per example: slow on a loaded machine
@given(tension, ratio, mu, t_c_frac)
def test_slip_arc_reduces_to_capstan_and_solves_5_11(t_low, r, m, c):
    """(5.13) with t_c = 0 is T_h/T_l = e^{μφ}; with t_c, (5.12) solves dT/dθ = μ(T - t_c)
    (5.11) from T(0) = T_l and reaches T_h at φ."""
    t_high = t_low * (1.0 + r)
    phi = sl.slip_arc(t_low, t_high, m, 0.0)
    assert t_high / t_low == pytest.approx(math.exp(m * phi), rel=1e-12)
    assert sl.slip_arc(t_high, t_low, m, 0.0) == pytest.approx(phi, rel=1e-12)  # either side
    assert sl.capstan_ratio(m, phi) == pytest.approx(t_high / t_low, rel=1e-12)
    t_c = c * t_low
    phi_c = sl.slip_arc(t_low, t_high, m, t_c)
    sol = solve_ivp(lambda th, y: m * (y - t_c), (0.0, phi_c), [t_low], rtol=1e-11, atol=1e-9)
    assert sol.y[0, -1] == pytest.approx(t_high, rel=1e-8)
    assert sl.arc_tension(phi_c, t_low, m, t_c, 1.0) == pytest.approx(t_high, rel=1e-12)
    assert phi_c >= phi  # centrifugal force unloads the contact: a longer arc is needed


def test_slip_arc_lift_off_and_equal_tensions():
    assert sl.slip_arc(50.0, 50.0, 0.2, 60.0) == 0.0
    assert sl.slip_arc(50.0, 70.0, 0.2, 60.0) == math.inf
    assert sl.capstan_limit(50.0, 0.2, 1.0, 60.0) == 50.0


@settings(deadline=None)  # quad per example
@given(tension, mu, wrap, t_c_frac, st.sampled_from([1.0, -1.0]))
def test_normal_force_is_the_integral_of_the_capstan_profile(t_in, m, a, c, s):
    """(5.41), both directions: N = ∫ (T(θ) - t_c) dθ with T of (5.40)/(5.12) from the entry."""
    t_c = c * t_in
    n, _ = quad(lambda th: sl.arc_tension(th, t_in, m, t_c, -s) - t_c, 0.0, a,
                epsabs=0.0, epsrel=1e-12)
    assert sl.normal_force(t_in, a, m, t_c, s) == pytest.approx(n, rel=1e-9)
    assert sl.stiction_limit(t_in, a, m, t_c, s) == pytest.approx(m * n, rel=1e-9)
    # tends to (t_in - t_c) α as μ -> 0
    assert sl.normal_force(t_in, a, 1e-12, t_c, s) == pytest.approx((t_in - t_c) * a, rel=1e-9)


@settings(max_examples=300, deadline=None)
@given(tension, ratio, mu, frac, wrap, viscous, t_c_frac, st.sampled_from([0, 1]))
def test_second_law_friction_and_slip_never_oppose(t_in, r, m, p, a, b, c, state):
    """F·s >= 0 for every input and state: the slip power is never negative, and while the web
    slips the traction law (5.42) returns exactly the force the tensions impose (5.39)."""
    t_c = c * t_in
    t_out = t_c + r * (t_in - t_c)
    s = sl.slip_velocity(t_in, t_out, a, m, p * m, b, t_c, state)
    assert sl.slip_power(t_in, t_out, s) >= 0.0
    if s != 0.0:
        f = sl.friction_force(s, t_in, a, m, p * m, b, t_c)
        assert f == pytest.approx(t_in - t_out, rel=1e-9, abs=1e-9 * t_in)


def test_printed_5_47_breaks_the_second_law_and_the_general_form_does_not():
    """(5.47) as printed, Table 5.1's numbers: with t3 a little below t2 (0 < F < p t2(1 -
    e^{-μα}) = 1.22 lbf) it has the web overrun the roller (s < 0) while friction pushes it
    forward (F > 0): F·s < 0. The general-sign law sticks there."""
    lbf = 4.4482216152605
    t2, m, mk, a, b = 42 * lbf, 0.1, 0.02, math.pi / 2, 2000 * lbf / 0.3048
    t3 = t2 - 0.5 * lbf
    s_printed = printed_slip_velocity(t2, t3, a, m, mk, b)
    assert s_printed < 0.0 < t2 - t3
    assert sl.slip_power(t2, t3, s_printed) < 0.0
    assert sl.slip_velocity(t2, t3, a, m, mk, b, 0.0, 1) == 0.0
    # equal tensions: the printed law still slips (s = -6.1e-4 ft/s); the general law does not
    assert printed_slip_velocity(t2, t2, a, m, mk, b) / 0.3048 == pytest.approx(-6.11e-4,
                                                                                 rel=2e-3)
    assert sl.slip_velocity(t2, t2, a, m, mk, b, 0.0, 1) == 0.0


@given(tension, st.floats(0.0, 0.999), mu, frac, wrap, viscous)
def test_general_relation_is_5_47_forward_and_its_mirror_backward(t_in, x, m, p, a, b):
    """For forward slip (σ = +1) the general relation is (5.47) as printed; backward (σ = -1)
    it is (5.47) with μ -> -μ: s = (t_in/b)[1 - p(1 - e^{μα}) - t_out/t_in]."""
    fwd = t_in * (1.0 - p * (1.0 - math.exp(-m * a))) * x  # below the forward Coulomb band
    s = sl.slip_velocity(t_in, fwd, a, m, p * m, b, 0.0, 1)
    assert s == pytest.approx(printed_slip_velocity(t_in, fwd, a, m, p * m, b), rel=1e-9)
    assert s > 0.0
    back = t_in * (1.0 - p * (1.0 - math.exp(m * a))) / max(x, 1e-3)  # above the backward band
    s = sl.slip_velocity(t_in, back, a, m, p * m, b, 0.0, 1)
    mirrored = (t_in / b) * (1.0 - p * (1.0 - math.exp(m * a)) - back / t_in)
    assert s == pytest.approx(mirrored, rel=1e-9)
    assert s <= 0.0


def test_slip_velocity_is_continuous_and_monotone_in_the_tensions():
    """Within a held state, s is a continuous, non-increasing function of t_out and
    non-decreasing in t_in (a dead zone over b): no jump for a fixed-step integrator to hit."""
    t_in, m, mk, a, b, t_c = 100.0, 0.3, 0.2, 2.0, 50.0, 3.0
    t_out = np.linspace(1.0, 400.0, 40001)
    s = np.array([sl.slip_velocity(t_in, x, a, m, mk, b, t_c, 1) for x in t_out])
    assert np.all(np.diff(s) <= 0.0)
    kappa = 1.0 + (mk / m) * (math.exp(m * a) - 1.0)
    assert np.abs(np.diff(s)).max() <= (t_out[1] - t_out[0]) / b * (1 + 1e-9)
    t_ins = np.linspace(1.0, 400.0, 40001)
    s = np.array([sl.slip_velocity(x, 150.0, a, m, mk, b, t_c, 1) for x in t_ins])
    assert np.all(np.diff(s) >= 0.0)
    assert np.abs(np.diff(s)).max() <= kappa * (t_ins[1] - t_ins[0]) / b * (1 + 1e-9)


def test_hysteresis_switches_once_per_crossing_of_the_band():
    """Stiction (μ0 > μ'): a stuck web breaks away when F leaves the stiction band and sticks
    again only when F is back inside the Coulomb band; F wandering between the two bands
    changes nothing. With μ0 = μ' the state is a function of F alone."""
    t_in, m, mk, a, t_c = 100.0, 0.3, 0.1, 1.0, 0.0
    fs = sl.stiction_limit(t_in, a, m, t_c, 1.0)
    fc = mk / m * fs
    forces = np.concatenate([np.linspace(0, 1.2 * fs, 50), np.linspace(1.2 * fs, 0.5 * (fs + fc),
                             50), np.linspace(0.5 * (fs + fc), 0.9 * fs, 50),
                             np.linspace(0.9 * fs, 0.5 * fc, 50)])
    state, trace = 0, []
    for f in forces:
        state = sl.slip_state(t_in, t_in - f, a, m, mk, t_c, state)
        trace.append(state)
    trace = np.array(trace)
    switches = np.nonzero(np.diff(trace))[0]
    assert len(switches) == 2
    assert forces[switches[0] + 1] > fs and forces[switches[0]] <= fs
    assert forces[switches[1] + 1] <= fc < forces[switches[1]]
    for f in (0.5 * fc, 0.5 * (fs + fc), 1.1 * fs):  # no hysteresis when μ' = μ0
        assert sl.slip_state(t_in, t_in - f, a, m, m, t_c, 0) == sl.slip_state(
            t_in, t_in - f, a, m, m, t_c, 1)


@given(tension, st.floats(-0.3, 0.3), st.floats(1e3, 1e6), st.floats(0.1, 50.0))
def test_creep_power_is_the_exact_energy_balance_and_explains_the_exit_arc(t_u, d, ea, v):
    """Sec. 5.2 (E-5.1): control volume = roller + web on it, steady, linearly elastic web.
    P = τω + T_d V_d - T_u V_u + Q (T_u² - T_d²)/(2EA), τ = R(T_u - T_d), Q = V/(1 + ε) the
    unstrained flux. Web adhering at the entry (V_u = v_r) gives creep_power >= 0 for either
    sign of T_u - T_d; adhering at the exit (V_d = v_r) gives its negative."""
    t_d = t_u * (1.0 + d)
    eu, ed = t_u / ea, t_d / ea

    def loss(v_u: float, v_d: float) -> float:
        q = v_u / (1 + eu)
        return (t_u - t_d) * v + t_d * v_d - t_u * v_u + q * (t_u**2 - t_d**2) / (2 * ea)

    exit_arc = loss(v, v * (1 + ed) / (1 + eu))
    entry_arc = loss(v * (1 + eu) / (1 + ed), v)
    scale = v * t_u * 1e-12
    assert exit_arc == pytest.approx(sl.creep_power(t_u, t_d, v, ea), rel=1e-7, abs=scale)
    assert exit_arc >= -scale
    assert entry_arc <= scale


def test_slip_rate_bounds_the_eigenvalues_of_the_two_spans():
    """The eigenvalues of the spans round a slipping roller, by finite differences of (5.33)
    with the slip law (backward slip, the larger κ): real, negative, the fastest between the
    slip part of ``slip_rate`` and the whole bound (the trace)."""
    ea, b, l_in, l_out, m, mk, a, v = 9000.0, 300.0, 6.0, 10.0, 0.2, 0.15, 1.5, 5.0
    t1 = 60.0

    def f(x: np.ndarray) -> np.ndarray:
        t_in, t_out = x
        s = sl.slip_velocity(t_in, t_out, a, m, mk, b, 0.0, 1)
        w = v - s
        return np.array([(ea * (w - v) + t1 * v - t_in * w) / l_in,
                         (ea * (v - w) + t_in * w - t_out * v) / l_out])

    x0 = np.array([60.0, 100.0])  # t_out >> t_in: backward slip
    h = 1e-4
    jac = np.column_stack([(f(x0 + h * e) - f(x0 - h * e)) / (2 * h) for e in np.eye(2)])
    eig = np.linalg.eigvals(jac)
    assert np.all(np.abs(eig.imag) < 1e-9) and np.all(eig.real < 0)
    bound = sl.slip_rate(ea, b, l_in, l_out, m, mk, a, v)
    slip_part = sl.slip_rate(ea, b, l_in, l_out, m, mk, a, 0.0)
    assert slip_part * (1 - 1e-3) <= np.abs(eig).max() <= bound
    assert -eig.real.sum() == pytest.approx(bound, rel=0.02)  # the trace, to O(strain)


SCALAR = [
    (sl.centrifugal_tension, (0.05, 10.0)), (sl.capstan_ratio, (0.2, 1.5)),
    (sl.capstan_limit, (50.0, 0.2, 1.5, 1.0)), (sl.arc_tension, (0.5, 50.0, 0.2, 1.0, -1.0)),
    (sl.slip_arc, (50.0, 60.0, 0.2, 1.0)), (sl.normal_force, (50.0, 1.5, 0.2, 1.0, -1.0)),
    (sl.stiction_limit, (50.0, 1.5, 0.2, 1.0, 1.0)),
    (sl.friction_force, (-0.01, 50.0, 1.5, 0.2, 0.1, 100.0, 1.0)),
    (sl.slip_velocity, (50.0, 80.0, 1.5, 0.2, 0.1, 100.0, 1.0, 1)),
    (sl.slip_state, (50.0, 80.0, 1.5, 0.2, 0.1, 1.0, 0)),
    (sl.slip_power, (50.0, 80.0, -0.01)), (sl.creep_power, (50.0, 80.0, 5.0, 9000.0)),
    (sl.slip_rate, (9000.0, 100.0, 5.0, 8.0, 0.2, 0.1, 1.5, 5.0)),
]


@pytest.mark.parametrize(("func", "args"), SCALAR, ids=[f.__name__ for f, _ in SCALAR])
def test_numba_compiles_each_scalar_function_alone(func, args):
    """Plain scalar maths: numba compiles each function by itself, same numbers as Python."""
    compiled = numba.njit(cache=False)(func)
    assert compiled(*args) == pytest.approx(func(*args), rel=1e-14)


# --- a traction nip (docs/winder.md, Nip) -----------------------------------------------------


def test_a_nip_widens_the_stick_band_by_its_capacity_on_both_sides():
    """Capstan band of 100 N over μα = 0.3: Fs⁺ = 100 (1 - e^-0.3), Fs⁻ = 100 (e^0.3 - 1);
    a nip of 2 μ_n N = 12 N moves both edges out by exactly 12 N."""
    from webline.physics.slip import slip_state

    fs_fwd, fs_back = 100 * (1 - math.exp(-0.3)), 100 * (math.exp(0.3) - 1)
    for nip in (0.0, 12.0):
        for f, slipping in ((fs_fwd + nip - 1e-9, 0), (fs_fwd + nip + 1e-9, 1),
                            (-fs_back - nip + 1e-9, 0), (-fs_back - nip - 1e-9, 1)):
            assert slip_state(100.0, 100.0 - f, 1.0, 0.3, 0.2, 0.0, 0, nip, 0.0) == slipping


def test_a_slipping_nip_adds_its_coulomb_force():
    """While slipping, the nip's 2 μ_n' N adds to the Coulomb force: s = (F - Fc - 2μ_n'N)/b,
    the slip state returns to stuck inside the widened Coulomb band, and F·s stays >= 0."""
    from webline.physics.slip import friction_force, slip_state, slip_velocity

    t_in, wrap, mu, mu_k, b = 100.0, 1.0, 0.3, 0.2, 500.0
    fc = (mu_k / mu) * t_in * (1 - math.exp(-mu * wrap))
    nip_k = 8.0
    for f in (fc + nip_k + 5.0, fc + nip_k + 50.0):
        s = slip_velocity(t_in, t_in - f, wrap, mu, mu_k, b, 0.0, 1, nip_k)
        assert s == pytest.approx((f - fc - nip_k) / b, rel=1e-12)
        assert friction_force(s, t_in, wrap, mu, mu_k, b, 0.0, nip_k) == pytest.approx(f)
    assert slip_velocity(t_in, t_in - fc - nip_k + 1e-6, wrap, mu, mu_k, b, 0.0, 1, nip_k) == 0
    assert slip_state(t_in, t_in - fc - nip_k + 1e-6, wrap, mu, mu_k, 0.0, 1, 20.0, nip_k) == 0
    assert slip_state(t_in, t_in - fc - nip_k - 1e-6, wrap, mu, mu_k, 0.0, 1, 20.0, nip_k) == 1
