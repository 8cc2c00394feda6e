"""One pint registry with the units web-handling engineers use (fpm, pli, lbf, lb·ft²).

Everything inside webline is SI; quantities are parsed here at the boundary. A quantity
string is a number times a unit, so its SI value is the number times the unit's factor: the
factors of the unit strings met before are kept on disk (``_conversions``), and a command
whose line file uses only those never imports pint (0.4-0.6 s of its start-up, more where
dask is installed, which pint imports when it finds it).
"""

from __future__ import annotations

import functools
import hashlib
import json
import math
import numbers
import os
import re
import sys
from pathlib import Path
from typing import TYPE_CHECKING

from webline import unit_registry
from webline.files import atomic_write_text
from webline.unit_registry import NO_CACHE_VARIABLE

if TYPE_CHECKING:
    import pint

    ureg: pint.UnitRegistry  # built on first use (``__getattr__``)

def __getattr__(name: str) -> object:
    if name == "ureg":  # ``from webline.units import ureg`` builds the registry
        return unit_registry.ureg()
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def _conversions_path() -> Path:
    """The file of known factors, beside pint's cache: named by pint's and Python's versions
    and by this module's source (its tables and rules decide every factor)."""
    folder = unit_registry.cache_folder()
    digest = hashlib.sha256(Path(__file__).read_bytes()).hexdigest()[:16]
    return folder.with_name(f"{folder.name}-conversions-{digest}.json")


@functools.cache
def _conversions() -> dict[str, float | None]:
    """Known factors: "kind|unit" -> SI value of one unit, "per_width|unit" -> N/m per unit
    (None: not a force per width), "display|kind|system" -> display factor. Read once; a
    missing or unreadable file is an empty memo."""
    if os.environ.get(NO_CACHE_VARIABLE):
        return {}
    try:
        data = json.loads(_conversions_path().read_text())
    except Exception:  # the memo only saves time
        return {}
    if not isinstance(data, dict):
        return {}
    return {k: v for k, v in data.items() if isinstance(k, str)
            and (v is None or (isinstance(v, float) and math.isfinite(v)))}


def _remember(key: str, factor: float | None) -> None:
    """Add a factor to the memo and rewrite its file whole (a reader never sees half)."""
    memo = _conversions()
    memo[key] = factor
    if os.environ.get(NO_CACHE_VARIABLE):
        return
    try:
        path = _conversions_path()
        path.parent.mkdir(parents=True, exist_ok=True)
        atomic_write_text(path, json.dumps(memo))
    except Exception:  # the memo only saves time: never fail a command for it
        pass


def _is_pint_quantity(value: object) -> bool:
    """Whether ``value`` is a pint Quantity (none can exist before pint is imported)."""
    pint = sys.modules.get("pint")
    return pint is not None and isinstance(value, pint.Quantity)


#: The dimension each kind of parameter must have, as pint dimensionality strings.
DIMENSIONS: dict[str, str] = {
    "length": "[length]",
    "speed": "[length] / [time]",
    "force": "[mass] * [length] / [time] ** 2",
    "torque": "[mass] * [length] ** 2 / [time] ** 2",
    "inertia": "[mass] * [length] ** 2",
    "mass": "[mass]",
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
    "force_per_width": "[mass] / [time] ** 2",
}

#: SI unit shown to users for each kind.
SI_UNITS: dict[str, str] = {
    "length": "m",
    "speed": "m/s",
    "force": "N",
    "torque": "N*m",
    "inertia": "kg*m**2",
    "mass": "kg",
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
    "force_per_width": "N/m",
}

#: Imperial display unit for each kind (where engineers use one).
IMPERIAL_UNITS: dict[str, str] = {
    "length": "ft",
    "speed": "ft/min",
    "force": "lbf",
    "torque": "lbf*ft",
    "inertia": "lb*ft**2",
    "mass": "lb",
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
    "force_per_width": "pli",
}


#: A quantity string: a number, then optionally a unit expression, nothing else. Checked
#: before pint, which would evaluate "1,5 m" as 15 m and "{{7*7}} m" as 49 m. A unit is
#: words joined by '*', '/', '·' or spaces, each with an optional 1- or 2-digit power.
_NUMBER = r"[+-]?(?:(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?:[eE][+-]?[0-9]+)?|inf|nan)"
_WORD = r"(?:[A-Za-z_µμΩ°]+|%)(?:(?:\*\*|\^)-?[0-9]{1,2})?"
_UNIT = rf"(?:1 ?/ ?)?{_WORD}(?: ?[*/·] ?{_WORD}| {_WORD})*"
_QUANTITY = re.compile(rf" *({_NUMBER}) *({_UNIT})? *")
#: Longest quantity string read [characters].
MAX_QUANTITY_TEXT = 100
#: units a plain ratio may carry (an angle such as "3 deg" is not a ratio)
_RATIO_UNITS = {"dimensionless", "percent", "ppm", "permille"}
#: unit names that count angle (rad, deg, turns): a frequency in rad/s is 1/(2π) Hz
_ANGLE_UNITS = {"radian", "degree", "revolution", "turn", "arcminute", "arcsecond", "gradian",
                "rpm_", "revolutions_per_minute", "revolutions_per_second"}
#: unit names that count cycles: "6 Hz" is 2π·6 rad/s for an angular frequency
_CYCLE_UNITS = {"hertz", "cycle"}


def clip(text: str, limit: int) -> str:
    """``text`` cut to at most ``limit`` characters (with '...') for error messages."""
    return text if len(text) <= limit else text[:limit - 3] + "..."


def short(value: object, limit: int = 40) -> str:
    """``repr(value)``, cut to at most ``limit`` characters for error messages."""
    return clip(repr(value), limit)


@functools.lru_cache(maxsize=64)
def _dimensionality(kind: str) -> pint.util.UnitsContainer:
    return unit_registry.ureg().parse_expression(SI_UNITS[kind] or "1").dimensionality


def _split(text: str, kind: str) -> tuple[float, str]:
    """(number, unit) of a strictly formed quantity string."""
    if len(text) > MAX_QUANTITY_TEXT:
        raise ValueError(f"cannot read {short(text)} as {_a(kind)}: longer than "
                         f"{MAX_QUANTITY_TEXT} characters")
    if any(ord(c) < 32 or ord(c) == 127 for c in text):
        raise ValueError(f"cannot read {short(text)} as {_a(kind)}: it contains control "
                         "characters")
    match = _QUANTITY.fullmatch(text)
    if match is None:
        if text.count(":") == 1:  # a sweep's range without its count
            raise ValueError(f"cannot read {short(text)} as {_a(kind)}: a range of values is "
                             f"written start:stop:n (n values, both ends included), e.g. "
                             f"{clip(text.strip(), 60) + ':5'!r}")
        unit = SI_UNITS.get(kind, "m")
        hint = f"a number and a unit, e.g. '1.5 {unit}'" if unit else "a number, e.g. '0.5'"
        raise ValueError(f"cannot read {short(text)} as {_a(kind)}: write {hint} (a decimal "
                         "point, no commas or expressions)")
    number, unit = match.groups()
    return float(number), unit.strip() if unit else ""


def quantity_parts(text: str) -> tuple[float, str]:
    """(number, unit as written, "" for none) of a quantity string, read as strictly as a line
    file's values (at most ``MAX_QUANTITY_TEXT`` characters, a number and a unit, no
    expressions such as ``9**9**9``, which pint would evaluate); ``ValueError`` otherwise."""
    return _split(text, "quantity")


def unit_reading(unit: str, text: str) -> tuple[float, str, bool]:
    """(SI value of one ``unit``, its dimensionality as pint writes it ("" for none), whether
    it is a plain ratio such as ppm or percent) through pint; ``text``: the string it came
    from, for errors (``ValueError`` naming it for a unit pint does not know)."""
    quantity = _quantity(unit, text, "quantity").to_base_units()
    names = {str(name) for name, _ in unit_registry.ureg().Quantity(1.0, unit).unit_items()}
    dims = str(quantity.dimensionality) if quantity.dimensionality else ""
    return float(quantity.magnitude), dims, bool(names) and names <= _RATIO_UNITS


def _quantity(unit: str, text: str, kind: str) -> pint.Quantity:
    """One ``unit`` as a pint quantity (``text``: the string it came from, for errors)."""
    try:
        return unit_registry.ureg().Quantity(1.0, unit)
    except Exception as exc:  # pint raises many types for unknown units
        raise ValueError(f"cannot read {short(text)} as {_a(kind)}: {exc}") from None


def _factor(unit: str, kind: str, text: str) -> float:
    """SI value [SI unit of ``kind``] of one ``unit``, from the memo or through pint."""
    key = f"{kind}|{unit}"
    factor = _conversions().get(key)
    if factor is None:
        factor = _si_number(_quantity(unit, text, kind), kind, text)
        _remember(key, factor)
    return factor


def _a(kind: str) -> str:
    """``kind`` in words with its article: "a force", "an angular frequency"."""
    words = kind.replace("_", " ")
    return ("an " if words[0] in "aeiou" else "a ") + words


def to_si(value: object, kind: str) -> float:
    """Convert ``value`` to an SI float of dimension ``kind``.

    ``value`` is a plain number (taken as SI), a string holding a number and a unit
    (``"500 ft/min"``; nothing else) or a pint ``Quantity``. A ratio (``kind`` =
    "dimensionless") accepts a plain number or a percentage, not an angle. Frequencies count
    cycles: for an ``angular_frequency`` [rad/s] "6 Hz" is 2π·6 rad/s; for a ``frequency``
    [Hz] "40 rad/s" is 40/(2π) Hz. Raises ``ValueError`` with a user-readable message.
    """
    if isinstance(value, bool):
        raise ValueError(f"expected {_a(kind)} (a number or a string with units), got {value!r}")
    if isinstance(value, numbers.Real):
        try:
            number = float(value)
        except OverflowError:  # an int beyond float range
            raise ValueError(f"must be finite, got {short(value)}") from None
    elif isinstance(value, str):
        magnitude, unit = _split(value, kind)
        number = magnitude * _factor(unit, kind, value)
    elif _is_pint_quantity(value):
        try:
            quantity = unit_registry.ureg().Quantity(float(value.magnitude), str(value.units))  # type: ignore[attr-defined]
        except Exception:  # an array, or a unit this registry does not know
            raise ValueError(f"expected {_a(kind)} as one number with a unit, "
                             f"got {short(value)}") from None
        number = _si_number(quantity, kind, value)
    else:
        raise ValueError(f"expected {_a(kind)} (a number or a string with units), "
                         f"got {short(value)}")
    if not math.isfinite(number):
        raise ValueError(f"must be finite, got {short(value)}")
    return number


def per_width_to_si(value: object) -> float | None:
    """A force per width of web (``"175 N/m"``, ``"2 N/cm"``, ``"1 pli"``, a pint Quantity)
    as an SI float [N/m], or None when ``value`` is not one (a plain number is a force, not a
    force per width). Raises ``ValueError`` for a malformed quantity string."""
    if isinstance(value, str):
        magnitude, unit = _split(value, "force")
        key = f"per_width|{unit}"
        memo = _conversions()
        if key not in memo:
            _remember(key, _per_width_factor(_quantity(unit, value, "force")))
        factor = memo[key]
        return None if factor is None else magnitude * factor
    if _is_pint_quantity(value):
        try:
            quantity = unit_registry.ureg().Quantity(float(value.magnitude), str(value.units))  # type: ignore[attr-defined]
        except Exception:  # an array, or a unit this registry does not know
            return None
        factor = _per_width_factor(quantity)
        return None if factor is None else float(quantity.magnitude) * factor
    return None


def _per_width_factor(quantity: pint.Quantity) -> float | None:
    """N/m per unit of ``quantity``, or None if it is not a force per width."""
    if quantity.dimensionless or quantity.dimensionality != _dimensionality("force_per_width"):
        return None
    return float(unit_registry.ureg().Quantity(1.0, quantity.units).to("N/m").magnitude)


def _si_number(quantity: pint.Quantity, kind: str, value: object) -> float:
    units = {str(name) for name, _ in quantity.unit_items()}
    wrong = quantity.dimensionality != _dimensionality(kind)
    if kind == "frequency" and quantity.dimensionless and not units:
        wrong = False  # a plain number is Hz
    if kind == "dimensionless" and not units <= _RATIO_UNITS:
        wrong = True  # "3 deg" is an angle, not a ratio
    if kind == "angle" and units & (_RATIO_UNITS - {"dimensionless"}):
        wrong = True
    if wrong:
        raise ValueError(f"expected {_a(kind)} (e.g. {SI_UNITS[kind] or 'a plain number'}), "
                         f"got {short(value)}{_force_unit_hint(quantity, kind, value)}")
    if not units:
        return float(quantity.magnitude)  # a plain number is SI
    if kind == "angular_frequency" and units & _CYCLE_UNITS:
        return 2.0 * math.pi * float(quantity.to("Hz").magnitude)  # cycles/s -> rad/s
    if kind == "frequency" and units & _ANGLE_UNITS:
        return float(quantity.to("rad/s").magnitude) / (2.0 * math.pi)  # rad/s -> cycles/s
    return float(quantity.to(SI_UNITS[kind]).magnitude)


#: mass units written where their force unit was meant, and that force unit
_MASS_AS_FORCE = re.compile(r"\b(?:(lbs?|pounds?|lbm)|(kg))\b")


def _force_unit_hint(quantity: pint.Quantity, kind: str, value: object) -> str:
    """": did you mean '9 lbf'? ..." where ``value`` wrote a mass unit (lb, lbs, kg) and its
    force unit (lbf, kgf) gives ``kind`` (a force, a force per width...); "" otherwise."""
    if not isinstance(value, str):
        return ""
    gravity = unit_registry.ureg().Quantity(1.0, "standard_gravity")
    if (quantity * gravity).dimensionality != _dimensionality(kind):
        return ""
    fixed = _MASS_AS_FORCE.sub(lambda m: "lbf" if m.group(1) else "kgf", value)
    if fixed == value:
        return ""
    return f": did you mean {short(fixed)}? (lb and kg are masses; lbf and kgf are forces)"


def display_factor(kind: str, system: str) -> tuple[float, str]:
    """Factor and unit that express an SI value of ``kind`` in ``system`` ('si' or 'imperial').

    Multiply an SI value (or array) by the factor to get the display value.
    """
    unit = (IMPERIAL_UNITS if system == "imperial" else SI_UNITS)[kind]
    if not unit or unit == SI_UNITS[kind]:
        return 1.0, unit
    key = f"display|{kind}|{system}"
    factor = _conversions().get(key)
    if factor is None:
        factor = float(unit_registry.ureg().Quantity(1.0, SI_UNITS[kind]).to(unit).magnitude)
        _remember(key, factor)
    return factor, unit
