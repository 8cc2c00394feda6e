"""Showing SI numbers in the unit system a user chose ('si' or 'imperial')."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

import numpy as np

from webline.units import display_factor

System = Literal["si", "imperial"]
SYSTEMS: tuple[System, ...] = ("si", "imperial")

#: How units are written for people (pint's '**' and '*' made readable).
PRETTY = {"kg*m**2": "kg·m²", "N*m": "N·m", "N*m*s": "N·m·s", "lb*ft**2": "lb·ft²",
          "lbf*ft": "lbf·ft", "lbf*ft*s": "lbf·ft·s", "kg/m**3": "kg/m³", "lb/ft**3": "lb/ft³"}


@dataclass(frozen=True)
class Display:
    """Converts SI values of a kind ('force', 'speed', 'length', 'torque', 'inertia', ...) to
    ``system`` and formats them with their unit."""

    system: System = "si"

    def __post_init__(self) -> None:
        if self.system not in SYSTEMS:
            raise ValueError(f"unit system must be 'si' or 'imperial', got {self.system!r}")

    def factor(self, kind: str) -> float:
        """Multiply an SI value of ``kind`` by this to express it in the chosen system."""
        return display_factor(kind, self.system)[0]

    def unit(self, kind: str) -> str:
        """The chosen system's unit of ``kind``, as people write it (``lbf``, ``lb·ft²``)."""
        unit = display_factor(kind, self.system)[1]
        return PRETTY.get(unit, unit)

    def plain_unit(self, kind: str) -> str:
        """The chosen system's unit of ``kind`` in ASCII pint notation (``lb*ft**2``), for
        machine-readable output."""
        return display_factor(kind, self.system)[1]

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
