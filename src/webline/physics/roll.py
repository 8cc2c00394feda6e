"""Unwind and rewind rolls whose radius and inertia change as web leaves or arrives (6.1-6.6)."""

from __future__ import annotations

import math

from webline.physics import Real


def web_inertia(radius: float, core_radius: float, width: float, density: float) -> float:
    """Inertia [kg·m²] of the web wound between ``core_radius`` and ``radius`` [m] (6.2).

    ``width`` [m], ``density`` [kg/m³]: J = (π/2) w ρ (R⁴ - Rc⁴).
    """
    return 0.5 * math.pi * width * density * (radius**4 - core_radius**4)


def radius_rate(web_speed: Real, radius: Real, thickness: float, direction: float) -> Real:
    """dR/dt [m/s] of a roll of outer ``radius`` [m] (6.6).

    Each turn adds or removes one layer of ``thickness`` [m]: 2πR dR/dt = ±δ v, with
    ``direction`` = -1 for an unwind and +1 for a rewind; ``web_speed`` [m/s] is the surface
    speed of the roll.
    """
    return direction * thickness * web_speed / (2.0 * math.pi * radius)


def roll_inertia(constant: float, radius: Real, core_radius: float, width: float,
                 density: float) -> Real:
    """Total inertia [kg·m²] about the roll shaft: rotating parts ``constant`` plus web (6.1).

    (Self-contained rather than calling ``web_inertia`` so that numba can compile it alone.)
    """
    r2, c2 = radius * radius, core_radius * core_radius
    return constant + 0.5 * math.pi * width * density * (r2 * r2 - c2 * c2)
