"""One pint registry with the units web-handling engineers use (fpm, pli, lbf, lb·ft²).

Everything inside webline is SI; quantities are parsed here at the boundary.
"""

from __future__ import annotations

import math
import re
from functools import lru_cache

import pint

ureg: pint.UnitRegistry = pint.UnitRegistry()
ureg.define("fpm = foot / minute")
ureg.define("pli = pound_force / inch")
ureg.define("rpm_ = revolution / minute")

#: The dimension each kind of parameter must have, as pint dimensionality strings.
DIMENSIONS: dict[str, str] = {
    "length": "[length]",
    "speed": "[length] / [time]",
    "force": "[mass] * [length] / [time] ** 2",
    "torque": "[mass] * [length] ** 2 / [time] ** 2",
    "inertia": "[mass] * [length] ** 2",
    "rot_damping": "[mass] * [length] ** 2 / [time]",
    "stiffness": "[mass] / [time] ** 2",
    "linear_damping": "[mass] / [time]",
    "time": "[time]",
    "frequency": "1 / [time]",
    "angular_frequency": "1 / [time]",
    "density": "[mass] / [length] ** 3",
    "pressure": "[mass] / [length] / [time] ** 2",
    "angle": "",
    "dimensionless": "",
}

#: SI unit shown to users for each kind.
SI_UNITS: dict[str, str] = {
    "length": "m",
    "speed": "m/s",
    "force": "N",
    "torque": "N*m",
    "inertia": "kg*m**2",
    "rot_damping": "N*m*s",
    "stiffness": "N/m",
    "linear_damping": "N*s/m",
    "time": "s",
    "frequency": "Hz",
    "angular_frequency": "rad/s",
    "density": "kg/m**3",
    "pressure": "Pa",
    "angle": "rad",
    "dimensionless": "",
}

#: Imperial display unit for each kind (where engineers use one).
IMPERIAL_UNITS: dict[str, str] = {
    "length": "ft",
    "speed": "ft/min",
    "force": "lbf",
    "torque": "lbf*ft",
    "inertia": "lb*ft**2",
    "rot_damping": "lbf*ft*s",
    "stiffness": "lbf/in",
    "linear_damping": "lbf*s/in",
    "time": "s",
    "frequency": "Hz",
    "angular_frequency": "rad/s",
    "density": "lb/ft**3",
    "pressure": "psi",
    "angle": "deg",
    "dimensionless": "",
}


#: a power with a 3-digit (or longer) or chained exponent: pint would compute it exactly,
#: which can take forever ("9**9**9 m")
_HUGE_POWER = re.compile(r"(\*\*|\^)\s*\(?\s*[-+]?\d{3,}|(\*\*|\^)[^*^]*(\*\*|\^)")


@lru_cache(maxsize=64)
def _dimensionality(kind: str) -> pint.util.UnitsContainer:
    return ureg.parse_expression(SI_UNITS[kind] or "1").dimensionality


def to_si(value: object, kind: str) -> float:
    """Convert ``value`` (a plain SI number or a string such as ``"500 ft/min"``) to SI.

    Plain numbers are taken as SI. Raises ``ValueError`` with a user-readable message.
    """
    if isinstance(value, bool):
        raise ValueError(f"expected a {kind} (a number or a string with units), got {value!r}")
    if isinstance(value, int | float):
        try:
            number = float(value)
        except OverflowError:  # an int beyond float range
            raise ValueError(f"must be finite, got {value!r}") from None
    elif isinstance(value, str):
        if _HUGE_POWER.search(value) or len(value) > 200:
            raise ValueError(f"cannot read {value!r} as a {kind}: exponent or text too large")
        try:
            quantity: pint.Quantity = ureg.Quantity(value.strip())
        except Exception as exc:  # pint raises many types for bad strings
            raise ValueError(f"cannot read {value!r} as a {kind}: {exc}") from None
        if not isinstance(quantity, pint.Quantity):
            quantity = ureg.Quantity(float(quantity), "")
        if quantity.dimensionality != _dimensionality(kind):
            if kind == "frequency" and quantity.dimensionless:
                pass
            else:
                raise ValueError(
                    f"expected a {kind} (e.g. {SI_UNITS[kind] or 'a plain number'}), "
                    f"got {value!r}"
                )
        si = SI_UNITS[kind]
        if kind == "angular_frequency" and "hertz" in str(quantity.units):
            number = 2.0 * math.pi * float(quantity.to("Hz").magnitude)  # cycles/s -> rad/s
        elif not si or quantity.dimensionless:  # a plain-number string is taken as SI
            number = float(quantity.to("").magnitude)
        else:
            number = float(quantity.to(si).magnitude)
    else:
        raise ValueError(f"expected a {kind} (a number or a string with units), got {value!r}")
    if not math.isfinite(number):
        raise ValueError(f"must be finite, got {value!r}")
    return number


def display_factor(kind: str, system: str) -> tuple[float, str]:
    """Factor and unit that express an SI value of ``kind`` in ``system`` ('si' or 'imperial').

    Multiply an SI value (or array) by the factor to get the display value.
    """
    unit = (IMPERIAL_UNITS if system == "imperial" else SI_UNITS)[kind]
    if not unit or unit == SI_UNITS[kind]:
        return 1.0, unit
    return float(ureg.Quantity(1.0, SI_UNITS[kind]).to(unit).magnitude), unit
