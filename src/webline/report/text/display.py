"""Showing SI numbers in the unit system a user chose ('si' or 'imperial'), forces optionally
per width of web ('si-per-width': N/m, 'imperial-per-width': pli), as converting engineers
quote tension."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

import numpy as np

from webline.units import display_factor

System = Literal["si", "imperial", "si-per-width", "imperial-per-width"]
SYSTEMS: tuple[System, ...] = ("si", "imperial", "si-per-width", "imperial-per-width")

#: How units are written for people (pint's '**' and '*' made readable).
PRETTY = {"kg*m**2": "kg·m²", "N*m": "N·m", "N*m*s": "N·m·s", "lb*ft**2": "lb·ft²",
          "lbf*ft": "lbf·ft", "lbf*ft*s": "lbf·ft·s", "kg/m**3": "kg/m³", "lb/ft**3": "lb/ft³",
          "N*s/m": "N·s/m", "lbf*s/in": "lbf·s/in"}


@dataclass(frozen=True)
class Display:
    """Converts SI values of a kind ('force', 'speed', 'length', 'torque', 'inertia', ...) to
    ``system`` and formats them with their unit. The per-width systems show every force
    (tensions, EA, loads) divided by the web's ``width`` [m], which they need."""

    system: System = "si"
    width: float | None = None

    def __post_init__(self) -> None:
        if self.system not in SYSTEMS:
            raise ValueError(f"unit system must be one of {', '.join(SYSTEMS)}, "
                             f"got {self.system!r}")
        if self.per_width and not (self.width is not None and self.width > 0):
            raise ValueError(f"units {self.system!r} need the web's width, got {self.width!r}")

    @property
    def per_width(self) -> bool:
        """True if forces are shown per width of web."""
        return self.system.endswith("-per-width")

    def at_width(self, width: float) -> Display:
        """This system for forces on a web ``width`` [m] wide: a per-width system divides by
        that width (a branched line's webs and lanes each have their own); the others are
        themselves."""
        return Display(self.system, width) if self.per_width else self

    def base(self) -> Display:
        """This system without the per-width ('si' or 'imperial'): forces not on one web."""
        return Display("imperial" if self.system.startswith("imperial") else "si")

    def _factor_unit(self, kind: str) -> tuple[float, str]:
        base = "imperial" if self.system.startswith("imperial") else "si"
        if self.per_width and kind == "force":
            factor, unit = display_factor("force_per_width", base)
            return factor / self.width, unit  # type: ignore[operator]
        return display_factor(kind, base)

    def factor(self, kind: str) -> float:
        """Multiply an SI value of ``kind`` by this to express it in the chosen system."""
        return self._factor_unit(kind)[0]

    def unit(self, kind: str) -> str:
        """The chosen system's unit of ``kind``, as people write it (``lbf``, ``lb·ft²``)."""
        unit = self._factor_unit(kind)[1]
        return PRETTY.get(unit, unit)

    def plain_unit(self, kind: str) -> str:
        """The chosen system's unit of ``kind`` in ASCII pint notation (``lb*ft**2``), for
        machine-readable output."""
        return self._factor_unit(kind)[1]

    def value(self, si: float, kind: str) -> float:
        """``si`` expressed in the chosen system."""
        return float(si) * self.factor(kind)

    def array(self, si: np.ndarray, kind: str) -> np.ndarray:
        """An SI array expressed in the chosen system."""
        return np.asarray(si, dtype=float) * self.factor(kind)

    def label(self, name: str, kind: str) -> str:
        """A column or axis label such as ``'tension [lbf]'``."""
        unit = self.unit(kind)
        return f"{name} [{unit}]" if unit else name

    def text(self, si: float | None, kind: str, digits: int = 4) -> str:
        """``si`` in the chosen system with its unit, e.g. ``'14.35 lbf'``; '–' for None/NaN."""
        number = number_text(None if si is None else self.value(si, kind), digits)
        unit = self.unit(kind)
        return f"{number} {unit}" if unit and number != "–" else number


def number_text(value: float | None, digits: int = 4) -> str:
    """A number with ``digits`` significant digits; '–' for None or NaN."""
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return "–"
    text = f"{value:.{digits}g}"
    return "0" if text in ("-0", "0") else text


def profile_text(profile: object, kind: str, display: Display) -> str:
    """A reference profile in words: ``'14.35 lbf'``, ``'ramp 200 → 1000 ft/min, 2 s to 7 s'``."""
    if profile is None:
        return ""
    if isinstance(profile, float | int):
        return display.text(profile, kind)
    unit = display.unit(kind)
    kind_name = getattr(profile, "type", "")
    if kind_name == "ramp":
        start, end = profile.start, profile.start + profile.duration  # type: ignore[attr-defined]
        return (f"ramp {number_text(display.value(profile.initial, kind))} → "  # type: ignore[attr-defined]
                f"{display.text(profile.final, kind)}, {start:g} s to {end:g} s")  # type: ignore[attr-defined]
    if kind_name == "steps":
        steps = ", ".join(f"{number_text(display.value(s.value, kind))} at {s.time:g} s"
                          for s in profile.steps)  # type: ignore[attr-defined]
        return f"steps from {display.text(profile.initial, kind)}: {steps} [{unit}]"  # type: ignore[attr-defined]
    values = [display.value(v, kind) for v in profile.value]  # type: ignore[attr-defined]
    return (f"table of {len(values)} points, {number_text(min(values))} to "
            f"{number_text(max(values))} {unit}")
