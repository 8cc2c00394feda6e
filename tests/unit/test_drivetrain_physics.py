"""Scalar physics of belts and backlash (thesis 2.10-2.12, 3.22-3.32, 3.47-3.48, 3.65)."""

from __future__ import annotations

import math

import numba
import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from webline.physics import backlash as bl
from webline.physics import belt

finite = st.floats(-1.0, 1.0, allow_nan=False)
positive = st.floats(0.01, 10.0)
gap = st.floats(0.0, 0.5)


@given(finite, finite, positive, positive, positive)
def test_belt_torques_are_minus_gradient_of_strain_energy(tm, tl, r1, r2, kb):
    """(2.10) from (2.12)-(2.13): the belt torque on each pulley is -∂V/∂θ (central difference;
    V is quadratic, so the difference is exact up to rounding)."""
    h = 1e-4
    tau_m, tau_l = belt.belt_torques(tm, tl, r1, r2, kb)
    dv_m = (belt.strain_energy(tm + h, tl, r1, r2, kb)
            - belt.strain_energy(tm - h, tl, r1, r2, kb)) / (2 * h)
    dv_l = (belt.strain_energy(tm, tl + h, r1, r2, kb)
            - belt.strain_energy(tm, tl - h, r1, r2, kb)) / (2 * h)
    scale = kb * (r1 + r2) ** 2
    assert tau_m == pytest.approx(-dv_m, abs=1e-7 * scale)
    assert tau_l == pytest.approx(-dv_l, abs=1e-7 * scale)
    force = belt.tight_side_force(tm, tl, r1, r2, kb)
    assert force == belt.damped_tight_side_force(belt.stretch(tm, tl, r1, r2), 0.3, kb, 0.0)


@given(finite, finite, positive, gap, gap)
def test_shaft_backlash_force_is_gradient_of_its_energy(xm, xl, k, gn, gp):
    """(3.21)-(3.23): ψ = ∂V/∂xm = -∂V/∂xL with V = ½ k dz(xm - xL)²; the dead zone is C¹ in V,
    so central differences are accurate to O(h) at the corners and exact elsewhere."""
    h = 1e-7

    def energy(a, b):
        z = bl.dead_zone(a - b, gn, gp)
        return 0.5 * k * z * z

    psi = bl.shaft_backlash_force(xm, xl, k, gn, gp)
    assert psi == pytest.approx((energy(xm + h, xl) - energy(xm - h, xl)) / (2 * h), abs=1e-6 * k)
    assert psi == pytest.approx(-(energy(xm, xl + h) - energy(xm, xl - h)) / (2 * h),
                                abs=1e-6 * k)


@given(finite, finite, positive, positive, positive, positive, gap, gap)
def test_deviation_decomposition_and_its_bound(tm, tl, kb, r1, a1, a2, gn, gp):
    """(3.47)-(3.48) and (3.63)-(3.65): backlash force = linear spring ∓ φ, |φ| <= K α2 max gap."""
    d = r1 * tm - a1 * tl
    psi = bl.belt_gear_backlash_force(tm, tl, kb, r1, a1, a2, gn, gp)
    phi = bl.belt_gear_backlash_deviation(tm, tl, kb, r1, a1, a2, gn, gp)
    assert psi == pytest.approx(kb * d + phi, abs=1e-12 * kb * (1 + abs(d)))
    assert abs(phi) <= kb * a2 * max(gn, gp) * (1 + 1e-12) + 1e-300
    psi_s = bl.shaft_backlash_force(tm, tl, kb, gn, gp)
    phi_s = bl.shaft_backlash_deviation(tm, tl, kb, gn, gp)
    assert psi_s == pytest.approx(kb * (tm - tl) - phi_s, abs=1e-12 * kb * (1 + abs(tm - tl)))
    assert abs(phi_s) <= kb * max(gn, gp) * (1 + 1e-12)


@given(finite, finite, positive, positive, positive, positive)
def test_zero_gap_is_exactly_the_linear_spring(tm, tl, kb, r1, a1, a2):
    """Must-show (force level): with a zero gap each backlash force IS the linear compliant
    force, bit for bit, and the deviation φ is zero: (3.23) -> (3.46), (3.32) -> (2.10)."""
    assert bl.shaft_backlash_force(tm, tl, kb, 0.0, 0.0) == kb * (tm - tl)
    assert bl.belt_gear_backlash_force(tm, tl, kb, r1, a1, a2, 0.0, 0.0) \
        == belt.tight_side_force(tm, tl, r1, a1, kb)
    assert bl.shaft_backlash_deviation(tm, tl, kb, 0.0, 0.0) == kb * 0.0
    assert bl.belt_gear_backlash_deviation(tm, tl, kb, r1, a1, a2, 0.0, 0.0) == 0.0


def test_dead_zone_shape_and_asymmetric_gap():
    """Remark 3.3.1: gaps c1 = 2Δa (P side, d < 0) and c2 = 2Δ(1 - a) (Q side)."""
    gn, gp = bl.asymmetric_gaps(1.0, 0.25)
    assert (gn, gp) == (0.5, 1.5)
    assert bl.asymmetric_gaps(0.3, 0.5) == (0.3, 0.3)
    assert bl.dead_zone(1.4, gn, gp) == 0.0 and bl.dead_zone(-0.4, gn, gp) == 0.0
    assert bl.dead_zone(2.0, gn, gp) == pytest.approx(0.5)
    assert bl.dead_zone(-1.0, gn, gp) == pytest.approx(-0.5)
    # continuity at the corners
    for corner in (gp, -gn):
        assert abs(bl.dead_zone(corner + 1e-12, gn, gp) - bl.dead_zone(corner - 1e-12, gn, gp)) \
            < 1e-11
    a1, a2 = bl.gear_lever_arms(0.05, 0.1, 0.2)
    assert (a1, a2) == (pytest.approx(0.1), pytest.approx(0.5))


SCALAR_FUNCTIONS = [
    (belt.stretch, 4), (belt.tight_side_force, 5), (belt.damped_tight_side_force, 4),
    (belt.strain_energy, 5), (belt.belt_torques, 5), (bl.dead_zone, 3),
    (bl.shaft_backlash_force, 5), (bl.shaft_backlash_deviation, 5),
    (bl.belt_gear_backlash_force, 8), (bl.belt_gear_backlash_deviation, 8),
    (bl.gear_lever_arms, 3), (bl.asymmetric_gaps, 2),
]


@pytest.mark.parametrize(("func", "nargs"), SCALAR_FUNCTIONS,
                         ids=[f.__name__ for f, _ in SCALAR_FUNCTIONS])
def test_numba_compiles_each_scalar_function_alone(func, nargs):
    """The physics functions are plain scalar maths: numba compiles each one by itself and gets
    the same numbers as Python (arguments on both sides of the gaps)."""
    compiled = numba.njit(cache=False)(func)
    rng = np.random.default_rng(7)
    for _ in range(20):
        args = [float(v) for v in rng.uniform(-2.0, 2.0, nargs)]
        args[2:] = [abs(v) for v in args[2:]]  # stiffness, radii, gaps are >= 0
        expected, got = func(*args), compiled(*args)
        assert np.allclose(got, expected, rtol=1e-14, atol=0.0)
        assert all(math.isfinite(v) for v in np.atleast_1d(got))
