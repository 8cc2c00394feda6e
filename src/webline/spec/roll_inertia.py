"""A roll's inertia as drives are set up with it (docs/winder.md, "Roll inertia from totals"):
totals of everything that turns with the roll, at stated diameters, instead of the inertia
of the rotating parts plus the web from its density.

Everything turning with a roll, seen at its shaft (thesis 6.1, 6.2):

    J(D) = J_c + n² J_m + (π/32) ρ w (D⁴ - D_c⁴)                                  (J1)

J_c the core, shaft and chuck (the roll's ``inertia`` without its web), n² J_m the motor
reflected through the drive ratio, ρ the density of the wound roll, w the web width, D_c
the core diameter. Two totals J_a at D_a and J_b at D_b (D_a < D_b) give both unknowns:

    (π/32) ρ w = (J_b - J_a) / (D_b⁴ - D_a⁴),   J_c = J_a - n² J_m - (π/32) ρ w (D_a⁴ - D_c⁴)

and one total J_t at D_t gives J_c with ρ the web's ``density``. The density of a wound
roll is below the web's where air is wound in, which is why drives take totals.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Annotated, Any, Literal

from pydantic import Field

from webline.spec.quantities import Inertia, Length, Strict


class RollTotals(Strict):
    """``inertia = { type = "totals", empty = ..., full = ..., full_diameter = ... }``: the
    totals [kg·m²] of the empty roll (at ``empty_diameter`` [m], default the core's) and of
    the full roll (at ``full_diameter`` [m]); the core inertia and the wound density are
    derived (J1)."""

    type: Literal["totals"]
    empty: Inertia
    full: Inertia
    full_diameter: Length
    empty_diameter: Length | None = None


class RollTotal(Strict):
    """``inertia = { type = "total", total = ..., diameter = ... }``: the total [kg·m²] at
    one stated ``diameter`` [m]; the core inertia is derived with the web's density (J1)."""

    type: Literal["total"]
    total: Inertia
    diameter: Length


RollInertiaSpec = Annotated[RollTotals | RollTotal, Field(discriminator="type")]


def _factor_and_core(roll: Any, web: Any) -> tuple[float, float]:
    """((π/32) ρ w [kg/m²], J_c [kg·m²]) of a roll whose ``inertia`` is a table (J1)."""
    spec = roll.inertia
    motor = roll.drive.ratio**2 * roll.drive.motor_inertia
    d_core = 2.0 * roll.core_radius
    if isinstance(spec, RollTotals):
        d_a = d_core if spec.empty_diameter is None else spec.empty_diameter
        factor = (spec.full - spec.empty) / (spec.full_diameter**4 - d_a**4)
        return factor, spec.empty - motor - factor * (d_a**4 - d_core**4)
    factor = math.pi / 32.0 * web.density * web.width
    return factor, spec.total - motor - factor * (spec.diameter**4 - d_core**4)


def roll_constants(roll: Any, web: Any) -> tuple[float, float]:
    """(J_c [kg·m²], ρ [kg/m³]) of an unwind or rewind ``roll`` spec on ``web``: the inertia
    of its rotating parts without web and motor, and the density of its wound web; (its
    ``inertia``, the web's ``density``) where the inertia is given so."""
    if not isinstance(roll.inertia, RollTotals | RollTotal):
        return roll.inertia, web.density
    factor, core = _factor_and_core(roll, web)
    return core, factor * 32.0 / (math.pi * web.width)


def check_roll_inertia(roll: Any, web: Any, key: str, fail: Callable[[str, str], Any]) -> None:
    """Fail on totals that describe no roll: diameters below the core or not increasing, a
    full roll lighter than the empty one, a derived core inertia that is not positive."""
    spec = roll.inertia
    if not isinstance(spec, RollTotals | RollTotal):
        return
    d_core = 2.0 * roll.core_radius
    if isinstance(spec, RollTotals):
        d_a = d_core if spec.empty_diameter is None else spec.empty_diameter
        if d_a < d_core:
            fail(f"{key}.empty_diameter", f"must not be below the core diameter {d_core:g} m")
        if spec.full_diameter <= d_a:
            fail(f"{key}.full_diameter", f"must exceed the empty roll's diameter {d_a:g} m")
        if spec.full <= spec.empty:
            fail(f"{key}.full", f"the full roll must be heavier than the empty one "
                 f"({spec.empty:g} kg*m**2)")
    elif spec.diameter < d_core:
        fail(f"{key}.diameter", f"must not be below the core diameter {d_core:g} m")
    core = _factor_and_core(roll, web)[1]
    if core <= 0.0:
        what = ("with the web's density the web alone" if isinstance(spec, RollTotal)
                else "the web between the two totals, extrapolated to the core,")
        fail(f"{key}", f"{what} outweighs the total: the core inertia would be {core:.4g} "
             f"kg*m**2 (<= 0); give the empty and full totals (type = \"totals\")")


def derivation(roll: Any, web: Any) -> str | None:
    """One line saying what webline derived from a roll's totals (None where it took the
    roll's ``inertia`` and the web's density as they are)."""
    spec = roll.inertia
    if not isinstance(spec, RollTotals | RollTotal):
        return None
    core, density = roll_constants(roll, web)
    source = "its empty and full totals" if isinstance(spec, RollTotals) else (
        "its total and the web's density")
    return (f"{roll.name}: inertia from {source}: core (without web and motor) "
            f"{core:.6g} kg*m**2, wound density {density:.6g} kg/m**3, "
            f"J(D) = {core + roll.drive.ratio**2 * roll.drive.motor_inertia:.6g} kg*m**2 + "
            f"{math.pi / 32.0 * density * web.width:.6g} kg/m**2 * (D**4 - "
            f"{2.0 * roll.core_radius:.4g}**4 m**4)")
