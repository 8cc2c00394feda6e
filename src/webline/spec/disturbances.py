"""Disturbances a line file can put on a line: wound-in ripple, eccentric and dragging
rollers, speed ripple, measurement noise, a web break and a flying splice (SI floats, as in
the schema)."""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import Field

from webline.spec.quantities import (
    Angle,
    Force,
    Frequency,
    Length,
    Speed,
    Strict,
    TorqueProfile,
    si,
)
from webline.spec.splice import FlyingSplice
from webline.spec.winder import WebBreak

#: names (of lines, rollers, spans), bounded: a name becomes a folder name
Name = Annotated[str, Field(min_length=1, max_length=100)]

class WoundInRipple(Strict):
    """Sinusoidal component of the unwind's wound-in tension (thesis Ch. 4); ``roller``: the
    unwind (default: the line's only one)."""

    type: Literal["wound_in_ripple"]
    amplitude: Force
    frequency: Frequency
    phase: Angle = 0.0
    roller: Name | None = None


class EccentricRoller(Strict):
    """Out-of-round roller or roll: its effective radius is ``radius + eccentricity·cos(angle)``
    (on an unwind or rewind the radius is the roll's, changing as it winds; docs/winder.md
    E1)."""

    type: Literal["eccentric_roller"]
    roller: Name
    eccentricity: Length


class SpeedRipple(Strict):
    """Sinusoidal ripple added to a driven roller's speed reference."""

    type: Literal["speed_ripple"]
    roller: Name
    amplitude: Speed
    frequency: Frequency
    phase: Angle = 0.0


class RollerDrag(Strict):
    """A torque opposing a roller's rotation [N·m], constant or a profile: a failing bearing, a
    rubbing guard, a spreader. It adds to the roller's bearing friction."""

    type: Literal["roller_drag"]
    roller: Name
    torque: TorqueProfile


class MeasurementNoise(Strict):
    """White Gaussian noise on every controller's tension and speed measurements (standard
    deviations ``tension`` [N], ``speed`` [m/s]), reproducible from ``seed``; measured
    surface speeds are rounded to ``speed_resolution`` [m/s] (0: exact), as an encoder's
    counts per sample are. The diameter calculators measure as the controllers do."""

    type: Literal["measurement_noise"]
    tension: Annotated[float, si("force", ">=0")] = 0.0
    speed: Speed = 0.0
    speed_resolution: Speed = 0.0
    seed: int = 0


DisturbanceSpec = Annotated[
    WoundInRipple | EccentricRoller | SpeedRipple | RollerDrag | MeasurementNoise | WebBreak
    | FlyingSplice,
    Field(discriminator="type"),
]


