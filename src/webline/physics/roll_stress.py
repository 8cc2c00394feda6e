"""Stresses in a wound roll: the accretive nonlinear model (docs/wound-roll.md).

A roll is built layer by layer. Each new layer of thickness ``h`` [m] carries its wound-on
(hoop) stress ``T`` [Pa]; on the stack below it acts as a pressure ``T h / s`` on the surface of
radius ``s`` [m] (a thin ring's equilibrium). The stack answers that load as a plane-stress,
orthotropic, axisymmetric body (Hakiel 1987, Tappi J. 70(5):113-117):

* equilibrium ``d(r σ_r)/dr = σ_t``;
* compliance ``ε_r = σ_r/E_r − ν σ_t/E_t``, ``ε_t = σ_t/E_t − ν σ_r/E_t``;
* compatibility ``ε_r = d(r ε_t)/dr``;

which give, for the increments of a layer's load, ``r² σ_r'' + 3 r σ_r' + (1 − g²) σ_r = 0``
with ``g² = E_t / E_r``. The radial (stack) modulus follows Pfeiffer's pressure–strain law
(Pfeiffer 1979, Tappi J. 62(10):91-95) ``P = K1 (exp(K2 ε) − 1)``, so
``E_r = dP/dε = K2 (P + K1)``, evaluated at each layer's pressure before the new load (Hakiel's
explicit update); ``K2 = 0`` with ``K1`` taken as the modulus gives the constant-modulus
(Altmann 1968, Tappi J. 51(4):176-179) linear model. The core is a spring on the innermost
layer: ``ε_t = σ_r / E_c`` at ``r = r_c`` (Hakiel's core condition, ``core_modulus`` below).

Solution method (derived in docs/wound-roll.md, not Hakiel's finite differences): in
``x = ln r`` and ``w = r σ_r`` the equation is ``w'' = g² w`` with ``w' = r σ_t``, so within a
layer of constant ``g²`` the transfer ``(w, w')`` across ``Δx = ln(r₂/r₁)`` is exact
(``cosh``/``sinh``). Both ``w`` and ``w'`` are continuous across layers (``σ_r`` and the radial
displacement are). One sweep from the core gives the stack's response to a unit load at its
surface; every layer's pressure and mean hoop stress take the scaled response. With constant
``E_r`` the result is exact for the layered roll (the test checks it against the closed form);
with Pfeiffer's law the only approximation is the one-layer lag of ``E_r``, first order in
``h`` (the test shows N → 2N convergence and checks against a continuous solution).

The layer-mean hoop stress is ``(1/h)∫σ_t dr`` over the layer, the exact integral of the
layer's field (``Δw / h``), so the half-roll force balance ``Σ h σ̄_t = r_k P_k`` holds to
round-off at every cut. The compiled kernel loads numba only when first called.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

#: |w| above which the sweep rescales (and counts a level): the response ratio of two nodes a
#: level or more apart is below 1e-200 and taken as zero.
_BIG = 1e200


def core_modulus(modulus: float, poisson: float, inner_radius: float, outer_radius: float) -> float:
    """Effective radial stiffness ``E_c`` [Pa] of a hollow isotropic core (Hakiel's ``E_c``).

    ``modulus`` [Pa] and ``poisson`` [-] of the core material, ``inner_radius`` and
    ``outer_radius`` [m]. A plane-stress Lamé cylinder under external pressure ``p`` has hoop
    strain ``−(p/E)((b² + a²)/(b² − a²) − ν)`` at its surface, so ``ε_t = σ_r / E_c`` with
    ``E_c = E / ((b² + a²)/(b² − a²) − ν)``; a solid core (``a = 0``) gives ``E/(1 − ν)``.
    ``math.inf`` modulus gives a rigid core.
    """
    if not 0.0 <= inner_radius < outer_radius:
        raise ValueError(
            f"core radii must satisfy 0 <= inner < outer, got {inner_radius}, {outer_radius} m"
        )
    a2, b2 = inner_radius**2, outer_radius**2
    return modulus / ((b2 + a2) / (b2 - a2) - poisson)


def pfeiffer_modulus(pressure: Any, k1: float, k2: float) -> Any:
    """Radial modulus ``E_r = K2 (P + K1)`` [Pa] of a stack at interlayer ``pressure`` [Pa] from
    Pfeiffer's law ``P = K1 (exp(K2 ε) − 1)`` (``k1`` [Pa], ``k2`` [-])."""
    return k2 * (pressure + k1)


@dataclass(frozen=True)
class RollStress:
    """Stresses of a finished roll of ``n`` layers (layer 0 on the core).

    ``radius`` [m] (n,): inner radius of each layer; ``pressure`` [Pa] (n,): interlayer
    pressure ``−σ_r`` on that radius (``pressure[0]`` is on the core); ``hoop`` [Pa] (n,): each
    layer's mean tangential stress, wound-on stress included; ``wound_on`` [Pa] (n,): the
    wound-on stress of each layer; ``thickness`` [m]; ``during``: the roll at the layers
    ``roll_stress`` was asked to keep.
    """

    radius: np.ndarray
    pressure: np.ndarray
    hoop: np.ndarray
    wound_on: np.ndarray
    thickness: float
    during: tuple[RollStress, ...] = ()

    @property
    def core_pressure(self) -> float:
        """Pressure [Pa] the roll puts on its core."""
        return float(self.pressure[0])

    @property
    def outer_radius(self) -> float:
        """Radius [m] of the finished roll's surface."""
        return float(self.radius[-1] + self.thickness)


def _accrete(
    wound_on: np.ndarray,
    radius: np.ndarray,
    k1: float,
    k2: float,
    tangential: float,
    core_ratio: float,
    pressure: np.ndarray,
    hoop: np.ndarray,
    during: np.ndarray,
    during_pressure: np.ndarray,
    during_hoop: np.ndarray,
) -> None:
    """Add the layers one by one (plain Python; numba compiles it unchanged).

    ``radius`` (n+1,) node radii; ``core_ratio`` = ``w'/w`` at the core = ``ν + E_t/E_c``;
    ``pressure`` (n+1,) and ``hoop`` (n,) accumulate (start at zero, hoop at the wound-on
    stress); ``during`` (j,) layer indices whose roll is copied into row j of
    ``during_pressure`` and ``during_hoop`` (j, n+1) as it is once that layer is on.
    """
    n = wound_on.shape[0]
    h = radius[1] - radius[0]
    nonlinear = k2 != 0.0
    w, wx, dx, dx2 = np.empty(n + 1), np.empty(n + 1), np.empty(n), np.empty(n)
    inv_r = 1.0 / radius
    for k in range(n):
        dx[k] = math.log(radius[k + 1] / radius[k])
        dx2[k] = dx[k] * dx[k]
    swept = 0  # nodes whose (w, w') are current (all of them when E_r is constant)
    start_prev = 0  # first node of the level below the surface's
    start_top = 0  # first node of the surface's level
    for m in range(n):
        if nonlinear or m == 0:
            swept = 0
            w[0] = 1.0
            wx[0] = core_ratio
            start_prev = 0
            start_top = 0
        # Sweep from the core (or the last valid node) to the surface node m: in each layer
        # w'' = g² w, so (w, w') crosses it by cosh y, sinh(y)/g with y = g Δx.
        for k in range(swept, m):
            if nonlinear:
                g2 = tangential / (k2 * (0.5 * (pressure[k] + pressure[k + 1]) + k1))
            else:
                g2 = tangential / k1
            z = g2 * dx2[k]
            if z < 1e-2:  # Taylor series of cosh y and sinh(y)/y, error < 1e-16
                ck = 1.0 + z * (0.5 + z * (1.0 / 24.0 + z * (1.0 / 720.0 + z / 40320.0)))
                sk = dx[k] * (
                    1.0 + z * (1.0 / 6.0 + z * (1.0 / 120.0 + z * (1.0 / 5040.0 + z / 362880.0)))
                )
            else:
                y = math.sqrt(z)
                ck = math.cosh(y)
                sk = math.sinh(y) * dx[k] / y
            w1 = ck * w[k] + sk * wx[k]
            wx1 = g2 * sk * w[k] + ck * wx[k]
            if abs(w1) > _BIG or abs(wx1) > _BIG:  # rescale: a new level starts at k + 1
                w1 /= _BIG
                wx1 /= _BIG
                start_prev = start_top
                start_top = k + 1
            w[k + 1] = w1
            wx[k + 1] = wx1
        swept = m
        # The unit response scaled so that w(surface) = r σ_r = −T h: pressure −w/r, the
        # mean hoop of layer k −(w(r_{k+1}) − w(r_k))/h. Nodes two levels below the surface's
        # see less than 1e-200 of the load and are left alone.
        a = wound_on[m] * h / w[m]
        for k in range(start_top, m + 1):
            pressure[k] += a * w[k] * inv_r[k]
        for k in range(start_top, m):
            hoop[k] -= a * (w[k + 1] - w[k]) / h
        if start_top > 0:
            b = a / _BIG  # nodes one level down are stored _BIG times too large
            for k in range(start_prev, start_top):
                pressure[k] += b * w[k] * inv_r[k]
            for k in range(start_prev, start_top - 1):
                hoop[k] -= b * (w[k + 1] - w[k]) / h
            k = start_top - 1
            hoop[k] -= a * (w[k + 1] - w[k] / _BIG) / h
        # the roll as it is after layer m, for each snapshot asked at m (sorted ``during``)
        for j in range(during.shape[0]):
            if during[j] == m:
                for k in range(m + 1):
                    during_pressure[j, k] = pressure[k]
                    during_hoop[j, k] = hoop[k]


_compiled: Callable[..., None] | None = None


def _kernel() -> Callable[..., None]:
    global _compiled
    if _compiled is None:
        import numba

        # fastmath lets LLVM fuse multiply-adds; no NaN/inf reaches the loop (checked inputs)
        _compiled = numba.njit(cache=True, fastmath=True, error_model="numpy")(_accrete)
    return _compiled


def roll_stress(
    wound_on: Any,
    core_radius: float,
    thickness: float,
    *,
    tangential_modulus: float,
    k1: float,
    k2: float,
    poisson: float = 0.0,
    core_stiffness: float = math.inf,
    during: Sequence[int] = (),
    compiled: bool = True,
) -> RollStress:
    """Interlayer pressure and hoop stress [Pa] of a roll wound with stresses ``wound_on``.

    ``wound_on`` [Pa] (n,): wound-on hoop stress of each layer, core outwards (tension per
    width over thickness, plus the nip's share: ``physics.wound_on``); ``core_radius`` [m];
    ``thickness`` [m] per layer; ``tangential_modulus`` ``E_t`` [Pa] (the web's in-plane
    modulus); ``k1`` [Pa], ``k2`` [-]: Pfeiffer's law, ``E_r = K2 (P + K1)``, or with
    ``k2 = 0`` a constant radial modulus ``E_r = k1``; ``poisson`` ``ν`` [-] (Hakiel's
    ``ν_rt``, enters through the core); ``core_stiffness`` ``E_c`` [Pa] (``core_modulus``;
    ``math.inf``: rigid). ``during``: layer indices at which the roll is kept as it is once
    that layer is on (``RollStress.during``, in the order given: the roll at chosen radii
    during winding). ``compiled=False`` runs the same loop in plain Python.
    """
    t = np.ascontiguousarray(wound_on, dtype=float)
    n = t.shape[0]
    if t.ndim != 1 or n < 1:
        raise ValueError("wound_on must be a 1-D array of at least one layer")
    if not (core_radius > 0.0 and thickness > 0.0 and tangential_modulus > 0.0):
        raise ValueError("core_radius, thickness and tangential_modulus must be > 0")
    if not (k1 > 0.0 and k2 >= 0.0):
        raise ValueError(f"need k1 > 0 and k2 >= 0, got k1={k1} Pa, k2={k2}")
    if not core_stiffness > 0.0:
        raise ValueError(f"core_stiffness must be > 0, got {core_stiffness} Pa")
    radius = core_radius + thickness * np.arange(n + 1, dtype=float)
    core_ratio = poisson + tangential_modulus / core_stiffness
    pressure = np.zeros(n + 1)
    hoop = t.copy()
    at = np.asarray(during, dtype=np.int64).reshape(-1)
    if at.size and (at.min() < 0 or at.max() >= n):
        raise ValueError(f"during: layer indices must be within 0..{n - 1}, got {list(at)}")
    at_pressure, at_hoop = np.zeros((at.size, n + 1)), np.zeros((at.size, n))
    run = _kernel() if compiled else _accrete
    run(
        t,
        radius,
        float(k1),
        float(k2),
        float(tangential_modulus),
        float(core_ratio),
        pressure,
        hoop,
        at,
        at_pressure,
        at_hoop,
    )
    snapshots = tuple(
        RollStress(
            radius[: m + 1],
            at_pressure[j, : m + 1],
            at_hoop[j, : m + 1],
            t[: m + 1],
            float(thickness),
        )
        for j, m in enumerate(at)
    )
    return RollStress(
        radius=radius[:-1],
        pressure=pressure[:-1],
        hoop=hoop,
        wound_on=t,
        thickness=float(thickness),
        during=snapshots,
    )


def linear_roll_stress(
    wound_on: Any,
    core_radius: float,
    thickness: float,
    *,
    tangential_modulus: float,
    radial_modulus: float,
    poisson: float = 0.0,
    core_stiffness: float = math.inf,
) -> RollStress:
    """Closed form of the constant-modulus (Altmann-type) layered roll [Pa], O(n²) numpy.

    The superposition of every layer's load ``T_j h`` on the analytic solution of the Euler
    equation ``w = A r^g + B r^−g`` (``w = r σ_r``, ``g² = E_t/E_r``) that meets the core
    condition ``w'/w = ν + E_t/E_c`` at ``x = ln r_c``: ``W(x) ∝ (1 + κ/g) e^{g(x−x_c)} +
    (1 − κ/g) e^{−g(x−x_c)}``. Independent of ``roll_stress``'s sweep (used to check it);
    arguments as there, ``radial_modulus`` ``E_r`` [Pa]. Memory grows as n²: for checks.
    """
    t = np.asarray(wound_on, dtype=float)
    n = t.shape[0]
    g = math.sqrt(tangential_modulus / radial_modulus)
    kappa = poisson + tangential_modulus / core_stiffness
    a, b = 1.0 + kappa / g, 1.0 - kappa / g
    r = core_radius + thickness * np.arange(n + 1, dtype=float)
    x = np.log(r / core_radius)
    # ratio[k, j] = W(x_k) / W(x_j) for k <= j (node k, load on node j), overflow-free form
    xk, xj = x[:, None], x[None, :]
    den = a + b * np.exp(-2.0 * g * xj)
    ratio = (a * np.exp(g * (xk - xj)) + b * np.exp(-g * (xk + xj))) / den
    below = np.triu(np.ones((n + 1, n), dtype=bool))  # node k <= layer j (load on node j)
    wj = -t * thickness  # w at node j from layer j's load
    w_total = (np.where(below, ratio[:, :n], 0.0) * wj).sum(axis=1)
    pressure = -w_total / r
    # Mean hoop of layer k: T_k + Σ_{j>k} (w_j(r_{k+1}) − w_j(r_k)) / h
    above = np.triu(np.ones((n, n), dtype=bool), 1)
    dw = (ratio[1:, :n] - ratio[:-1, :n]) * wj
    hoop = t + np.where(above, dw, 0.0).sum(axis=1) / thickness
    return RollStress(
        radius=r[:-1], pressure=pressure[:-1], hoop=hoop, wound_on=t, thickness=float(thickness)
    )
