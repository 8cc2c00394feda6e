"""Wound-roll stresses (physics.roll_stress) against closed forms, balances and an independent
solution (docs/wound-roll.md).

Sources: Altmann 1968 (Tappi J. 51(4):176-179), the constant-modulus model this closed form
generalises; Hakiel 1987 (Tappi J. 70(5):113-117), the accretive nonlinear model and its core
condition; Pfeiffer 1979 (Tappi J. 62(10):91-95), ``P = K1 (exp(K2 ε) − 1)``. The parameter
values are assumed (a polyester film on a steel or fibre core), chosen for a physically
plausible roll, not read from those papers.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_bvp

from webline.physics.roll_stress import (
    core_modulus,
    linear_roll_stress,
    pfeiffer_modulus,
    roll_stress,
)

E_T = 4.0e9  # [Pa] in-plane modulus of PET film (assumed, typical 3.5-5 GPa)
NU = 0.01  # [-] Hakiel's ν_rt (assumed: stacks are far softer radially than in-plane)
CORE_R = 0.0762  # [m] 6-inch core
H = 25e-6  # [m] 25 µm film


def _wound_on(n: int) -> np.ndarray:
    """A wound-on stress with a 30 % ripple [Pa], so that no check rests on uniform tension."""
    return 8e6 * (1.0 + 0.3 * np.sin(np.arange(n) / 37.0))


@pytest.mark.parametrize("core", [math.inf, core_modulus(2.0e9, 0.3, 0.066, CORE_R)])
def test_constant_modulus_equals_closed_form(core: float) -> None:
    """Constant E_r, rigid and fibre core: the sweep equals the closed-form superposition of
    every layer's analytic Euler-equation response to 1e-6 at every radius (measured ~1e-13:
    both are exact for the layered roll, so only round-off separates them)."""
    n = 1500
    t = _wound_on(n)
    kw = dict(tangential_modulus=E_T, poisson=NU, core_stiffness=core)
    swept = roll_stress(t, CORE_R, H, k1=60e6, k2=0.0, **kw)
    closed = linear_roll_stress(t, CORE_R, H, radial_modulus=60e6, **kw)
    # pressure > 0 everywhere: pointwise relative; hoop crosses zero: relative to its range
    assert np.all(closed.pressure > 0)
    np.testing.assert_allclose(swept.pressure, closed.pressure, rtol=1e-6, atol=0)
    np.testing.assert_allclose(
        swept.hoop, closed.hoop, rtol=0, atol=1e-6 * np.abs(closed.hoop).max()
    )


def test_outer_layer_pressure_is_ring_load() -> None:
    """The last layer presses on the roll with its wound-on stress × thickness / radius (a thin
    ring's equilibrium), exactly, in the nonlinear model too."""
    t = _wound_on(3000)
    r = roll_stress(t, CORE_R, H, tangential_modulus=E_T, k1=5e3, k2=100.0, poisson=NU)
    assert r.pressure[-1] == pytest.approx(t[-1] * H / r.radius[-1], rel=1e-12)
    assert r.hoop[-1] == t[-1]  # nothing lies on the last layer


def test_half_roll_force_balance_at_every_cut() -> None:
    """Cut the roll along a diameter outside radius r_k: the hoop forces on the two cut faces
    (2 Σ h σ̄_t per unit width) balance the pressure on the inner face (2 r_k P_k), to
    round-off, at every k (equilibrium d(rσ_r)/dr = σ_t integrated over the outer part)."""
    t = _wound_on(4000)
    r = roll_stress(
        t,
        CORE_R,
        H,
        tangential_modulus=E_T,
        k1=5e3,
        k2=100.0,
        poisson=NU,
        core_stiffness=core_modulus(2.0e9, 0.3, 0.066, CORE_R),
    )
    hoop_force = np.cumsum((H * r.hoop)[::-1])[::-1]  # Σ_{j>=k} h σ̄_t,j [N/m]
    scale = np.abs(H * r.hoop).sum()
    np.testing.assert_allclose(hoop_force, r.radius * r.pressure, rtol=0, atol=1e-12 * scale)
    assert r.hoop.min() < 0  # the balance holds through a compressive band too


def test_stiffer_core_raises_core_pressure() -> None:
    """Core pressure rises monotonically with the core's stiffness, up to the rigid core
    (a softer core gives way and sheds the inner layers' load into hoop compression)."""
    t = _wound_on(2000)
    stiff = [1e7, 1e8, 1e9, 1e10, 1e11, math.inf]
    p = [
        roll_stress(
            t, CORE_R, H, tangential_modulus=E_T, k1=5e3, k2=100.0, poisson=NU, core_stiffness=ec
        ).core_pressure
        for ec in stiff
    ]
    assert np.all(np.diff(p) > 0), p
    assert p[-1] > 1.5 * p[0]  # and by a margin that matters, not round-off


def test_core_modulus_limits() -> None:
    """Lamé cylinder: a solid core gives E/(1 − ν); a thin tube is far softer (∝ wall/radius)."""
    assert core_modulus(200e9, 0.3, 0.0, 0.05) == pytest.approx(200e9 / 0.7)
    thin = core_modulus(200e9, 0.3, 0.049, 0.05)
    assert thin == pytest.approx(200e9 / ((0.05**2 + 0.049**2) / (0.05**2 - 0.049**2) - 0.3))
    assert thin < 0.03 * 200e9
    with pytest.raises(ValueError):
        core_modulus(1e9, 0.3, 0.06, 0.05)


def _profile(n: int, radius: float) -> tuple[np.ndarray, np.ndarray]:
    h = (radius - CORE_R) / n
    r = roll_stress(
        np.full(n, 8e6),
        CORE_R,
        h,
        tangential_modulus=E_T,
        k1=5e3,
        k2=100.0,
        poisson=NU,
        core_stiffness=core_modulus(2.0e9, 0.3, 0.066, CORE_R),
    )
    return r.radius, r.pressure


def test_layer_count_convergence() -> None:
    """N → 2N → 4N layers of the same roll (thickness halved): the pressure profile changes
    less each time, by about half (Hakiel's lagged E_r is first order in the layer
    thickness), and by under 1 % of the peak at 4000 layers."""
    grid = np.linspace(CORE_R, CORE_R + 0.02, 200, endpoint=False)
    prof = [np.interp(grid, *_profile(n, CORE_R + 0.02)) for n in (1000, 2000, 4000)]
    d1 = np.abs(prof[1] - prof[0]).max()
    d2 = np.abs(prof[2] - prof[1]).max()
    assert 1.6 < d1 / d2 < 2.4, (d1, d2)
    assert d2 < 0.01 * prof[2].max()


def test_nonlinear_against_solve_bvp() -> None:
    """The nonlinear accretion against an independent solution of the same problem by a
    different method: at each outer radius s the continuous boundary-value problem
    ``w'' = g²(x) w`` (x = ln r, g² = E_t / (K2 (P(r) + K1)) with P interpolated linearly
    between the layer radii, ``w' = (ν + E_t/E_c) w`` at the core, ``w(s) = 1``) is solved by
    collocation (scipy solve_bvp, tol 1e-8), and the load ``T h / s`` added with E_r lagged
    by one layer as in Hakiel's scheme. The two share only that accretion step (whose own
    error test_layer_count_convergence measures); they differ in how E_r varies within a
    layer (linear P against the layer's mean P, a second-order difference) and agree to 1e-4
    of the peak pressure (measured 3e-5)."""
    n, rc, h = 150, 0.05, 1e-4
    et, k1, k2, ec, t = 1.0e9, 0.2e6, 20.0, 3.0e9, 5.0e6
    kappa = NU + et / ec
    model = roll_stress(
        np.full(n, t), rc, h, tangential_modulus=et, k1=k1, k2=k2, poisson=NU, core_stiffness=ec
    )
    grid = rc + h * np.arange(n + 1)
    p = np.zeros_like(grid)
    for m in range(n):
        s = rc + m * h
        if m == 0:
            p[0] += t * h / rc
            continue
        xs = math.log(s / rc)
        live = grid <= s + 1e-15
        xg, pg = np.log(grid[live] / rc), p[live].copy()

        def fun(x: np.ndarray, y: np.ndarray, xg=xg, pg=pg) -> np.ndarray:
            g2 = et / pfeiffer_modulus(np.interp(x, xg, pg), k1, k2)
            return np.vstack([y[1], g2 * y[0]])

        def bc(ya: np.ndarray, yb: np.ndarray) -> np.ndarray:
            return np.array([ya[1] - kappa * ya[0], yb[0] - 1.0])

        x = xg if xg.size > 2 else np.linspace(0.0, xs, 3)  # P's kinks on mesh nodes
        g0 = math.sqrt(et / pfeiffer_modulus(0.0, k1, k2))
        y0 = np.vstack([np.exp(g0 * (x - xs)), g0 * np.exp(g0 * (x - xs))])
        sol = solve_bvp(fun, bc, x, y0, tol=1e-8, max_nodes=100000)
        assert sol.success, sol.message
        p[live] += t * h * sol.sol(xg)[0] / grid[live]
    ref = np.interp(model.radius, grid, p)
    np.testing.assert_allclose(model.pressure, ref, rtol=0, atol=1e-4 * ref.max())


def test_plain_python_equals_compiled() -> None:
    """The same loop uncompiled gives the same roll (the benchmark's peer)."""
    t = _wound_on(120)
    kw = dict(tangential_modulus=E_T, k1=5e3, k2=100.0, poisson=NU, core_stiffness=3e9)
    a = roll_stress(t, CORE_R, H, **kw)
    b = roll_stress(t, CORE_R, H, compiled=False, **kw)
    np.testing.assert_allclose(a.pressure, b.pressure, rtol=1e-12)
    np.testing.assert_allclose(a.hoop, b.hoop, rtol=1e-12, atol=1e-6)


def test_roll_during_winding_is_the_roll_of_its_first_layers() -> None:
    """The roll kept at layer m during winding is exactly the roll of the first m + 1 layers
    wound alone (the accretion never looks ahead), to round-off."""
    t = _wound_on(1200)
    kw = dict(tangential_modulus=E_T, k1=5e3, k2=100.0, poisson=NU, core_stiffness=3e9)
    full = roll_stress(t, CORE_R, H, during=[899, 299], **kw)
    assert [len(s.radius) for s in full.during] == [900, 300]
    for snap in full.during:
        alone = roll_stress(t[: len(snap.radius)], CORE_R, H, **kw)
        np.testing.assert_allclose(snap.pressure, alone.pressure, rtol=1e-12)
        np.testing.assert_allclose(snap.hoop, alone.hoop, rtol=1e-12, atol=1e-6)
    # and the finished roll presses harder on its core than it did two thirds of the way
    assert full.core_pressure > full.during[0].core_pressure
    with pytest.raises(ValueError, match="during"):
        roll_stress(t, CORE_R, H, during=[1200], **kw)
