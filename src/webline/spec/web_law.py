"""``web.stress_strain``: the web's stress-strain law (docs/nonlinear-web.md) and the kinds of
the law array the simulation evaluates (``webline.physics.web_law``); its checks and the
array are built in ``spec.web_law_checks``."""

from __future__ import annotations

from typing import Annotated, Literal

import numpy as np

from webline.spec.quantities import Strict, si

Strain = Annotated[float, si("dimensionless", ">=0")]
PositiveStrain = Annotated[float, si("dimensionless", ">0")]
Stress = Annotated[float, si("pressure", ">=0")]
PerWidth = Annotated[float, si("force_per_width", ">=0")]

#: law kinds of the law array (``webline.physics.web_law``)
LINEAR, TABLE, POWER = 0, 1, 2

#: a table whose every point lies on T = EA ε to this relative error is the linear law (its
#: points are decimal numbers; their binary rounding is ~1e-16)
LINEAR_TABLE_RTOL = 1e-12


class StressStrainSpec(Strict):
    """A web's stress-strain law: ``law`` = ``"linear"`` (T = EA ε), ``"power"``
    (σ = E ε_r (ε/ε_r)^n), ``"bilinear"`` (E up to ``yield_strain``, ``hardening`` x E
    beyond) or ``"table"`` (piecewise linear through (``strain``, ``stress`` or
    ``tension_per_width``) points). Kelvin-Voigt spans add their damper on top."""

    law: Literal["linear", "power", "bilinear", "table"]
    exponent: PositiveStrain | None = None
    reference_strain: PositiveStrain | None = None
    yield_strain: PositiveStrain | None = None
    hardening: Annotated[float, si("dimensionless", ">=0")] | None = None
    strain: list[Strain] | None = None
    stress: list[Stress] | None = None
    tension_per_width: list[PerWidth] | None = None


def stretch_at(law: np.ndarray, tension: float) -> float:
    """Stretch [N] at which the law array ``law`` carries ``tension`` [N] (numpy, for the
    file's checks; the kernel's is ``physics.web_law.law_stretch``)."""
    if tension <= 0.0 or int(law[0]) == LINEAR:
        return tension
    if int(law[0]) == POWER:
        return float(law[1] * (tension / law[1]) ** (1.0 / law[2]))
    m = int(law[1])
    stretch, tensions = law[2:2 + m], law[2 + m:2 + 2 * m]
    if tension <= tensions[-1]:
        return float(np.interp(tension, tensions, stretch))
    slope = (tensions[-1] - tensions[-2]) / (stretch[-1] - stretch[-2])
    return float(stretch[-1] + (tension - tensions[-1]) / slope)
