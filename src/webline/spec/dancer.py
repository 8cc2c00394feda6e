"""Line-file keys of a dancer's carriage (docs/winder.md): the moving part of a ``dancer``
roller, its load, spring, damper, travel and what the zone's drive does with it."""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import Annotated, Any, Literal

from pydantic import Field

from webline.spec.quantities import Length, Strict, TensionProfile, si

Mass = Annotated[float, si("mass", ">0")]
Stiffness = Annotated[float, si("stiffness", ">=0")]
LinearDamping = Annotated[float, si("linear_damping", ">=0")]
PositionGain = Annotated[float, si("frequency", ">=0")]
PositionIntegral = Annotated[float, Field(ge=0.0)]  # [1/s²]: plain SI


class DancerCarriage(Strict):
    """A dancer roller's carriage (linear slide) or pivoting arm.

    The carriage moves by y [m] along its ``travel`` (0 .. travel, end stops of
    ``stop_stiffness`` [N/m] beyond); moving by dy lengthens its upstream span by g_in dy and
    its downstream span by g_out dy, g = (``strands``/2) cos(angle), ``angle_in`` and
    ``angle_out`` [rad] the spans' angles to the travel (default 0: the web wrapped 180°,
    spans parallel to the travel, g = 1); a festoon of n strands stores n dy of web, its
    spans' tensions pulling the carriage back with g_in T_in + g_out T_out (D0-D2). A span's
    ``length`` in the file is its length with the carriage at ``position`` (the set
    position). ``mass`` [kg] is everything that moves with the roller; a pivoting arm of
    ``arm_inertia`` J [kg·m²] about its pivot with the roller at ``arm_length`` a [m] moves
    like a mass J/a² at the roller (small swings, y = a·angle), added to ``mass``. ``load``
    [N] pushes the carriage towards longer spans (weight or air cylinder, constant or a
    profile; default: (g_in + g_out) x the zone's tension reference, so the set position is
    an equilibrium); ``stiffness`` [N/m] pulls it back to
    ``position``; ``damping`` [N·s/m].

    ``use``: ``"position"`` - the zone's drive trims its speed by a PI on the position error
    (dancer position control; gains ``position_kp`` [(m/s)/m], ``position_ki`` [(m/s)/(m·s)],
    tuned like the zone's tension loop where missing); ``"tension"`` - the dancer is the zone's
    tension sensor, T = (load - stiffness·(y - position))/(g_in + g_out); ``"none"`` - the
    loadcell.
    """

    mass: Mass
    travel: Length
    position: Length
    load: TensionProfile | None = None
    stiffness: Stiffness = 0.0
    damping: LinearDamping = 0.0
    stop_stiffness: Annotated[float, si("stiffness", ">0")] = 1e6
    arm_length: Length | None = None
    arm_inertia: Annotated[float, si("inertia", ">0")] | None = None
    strands: Annotated[int, Field(ge=2, le=200)] = 2
    angle_in: Annotated[float, si("angle", ">=0")] = 0.0
    angle_out: Annotated[float, si("angle", ">=0")] = 0.0
    use: Literal["position", "tension", "none"] = "position"
    position_kp: PositionGain | None = None
    position_ki: PositionIntegral | None = None

    @property
    def gains(self) -> tuple[float, float]:
        """(g_in, g_out) [m/m]: how much the upstream and downstream span lengthen per metre
        of travel, (strands / 2) cos(angle) (docs/winder.md, D0)."""
        half = self.strands / 2
        return half * math.cos(self.angle_in), half * math.cos(self.angle_out)

    @property
    def moving_mass(self) -> float:
        """Mass [kg] the carriage equation sees: carriage plus arm inertia / arm length²."""
        if self.arm_inertia is not None and self.arm_length is not None:
            return self.mass + self.arm_inertia / self.arm_length**2
        return self.mass


def check_dancers(rollers: Sequence[Any], spans: Sequence[Any],
                  zone_nodes: Sequence[tuple[int, int]], fail: Callable[[str, str], Any]) -> None:
    """Fail on a dancer whose set position lies outside its travel or would shorten a span
    to nothing, or whose position loop is asked of a drive that is not a cascaded PI."""
    for i, roller in enumerate(rollers):
        c = getattr(roller, "dancer", None)
        if c is None:
            continue
        key = f"rollers[{i}].dancer"
        if c.position > c.travel:
            fail(f"{key}.position", f"must lie within the travel {c.travel:g} m")
        for k, gain in zip((i - 1, i), c.gains, strict=True):
            if spans[k].length <= gain * c.position:
                fail(f"spans[{k}].length", f"must exceed {gain * c.position:g} m, what the "
                     f"dancer {roller.name!r} takes from it between its set position "
                     f"{c.position:g} m and y = 0 (D0)")
        for name, angle in (("angle_in", c.angle_in), ("angle_out", c.angle_out)):
            if angle >= 0.5 * math.pi:
                fail(f"{key}.{name}", "a span at 90 deg or more to the travel does not "
                     "pull the carriage back (must be below 90 deg)")
        if (c.arm_length is None) != (c.arm_inertia is None):
            fail(f"{key}.arm_inertia", "a pivoting arm needs both arm_length and arm_inertia")
        if c.use == "tension" and c.stiffness == 0.0:
            fail(f"{key}.stiffness", "a dancer as tension sensor needs a spring (stiffness > "
                 "0): without one it reads load / 2 whatever the tension")
        if c.use == "position":
            first, last = next(z for z in zone_nodes if z[0] < i < z[1])
            master = next(j for j, r in enumerate(rollers) if getattr(r, "role", "") == "master")
            drive = rollers[first if last <= master else last]
            if getattr(drive.controller, "type", "") != "cascaded_pi":
                fail(f"{key}.use", f"position control trims the speed of a cascaded PI; "
                     f"{drive.name!r} runs {drive.controller.type!r}")
