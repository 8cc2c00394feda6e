"""Line-file keys of friction as drives measure it (docs/winder.md, F1-F2): a table of
friction torque against shaft speed, and a break-away torque at standstill."""

from __future__ import annotations

from collections.abc import Callable
from typing import Annotated, Any

import numpy as np
from pydantic import Field

from webline.spec.quantities import Strict, si

#: points of a friction table: drives measure at 0, 25, 50, 75 and 100 % of their top speed
MAX_POINTS = 5


class MeasuredFriction(Strict):
    """Friction torque ``torque`` [N·m] measured at shaft speeds ``speed`` [rad/s; "rpm"
    works], e.g. at 0/25/50/75/100 % of the top speed; linear between the points, constant
    beyond them, with the sign of the rotation (smoothed at rest as Coulomb friction)."""

    speed: list[Annotated[float, si("angular_frequency", ">=0")]] = Field(min_length=1)
    torque: list[Annotated[float, si("torque", ">=0")]] = Field(min_length=1)

    def arrays(self) -> tuple[np.ndarray, np.ndarray]:
        """(speeds [rad/s], torques [N·m]) as float arrays."""
        return np.array(self.speed, dtype=float), np.array(self.torque, dtype=float)


def check_friction_table(table: MeasuredFriction | None, key: str,
                         fail: Callable[[str, str], Any]) -> None:
    """Fail on a table whose columns differ in length, that has too many points or whose
    speeds do not increase."""
    if table is None:
        return
    if len(table.speed) != len(table.torque):
        fail(f"{key}.torque", f"needs as many torques as speeds ({len(table.speed)}), "
             f"got {len(table.torque)}")
    if len(table.speed) > MAX_POINTS:
        fail(f"{key}.speed", f"at most {MAX_POINTS} points (0/25/50/75/100 % of the top "
             f"speed), got {len(table.speed)}")
    if any(b <= a for a, b in zip(table.speed, table.speed[1:], strict=False)):
        fail(f"{key}.speed", "speeds must increase")


def check_friction(roller: Any, key: str, fail: Callable[[str, str], Any]) -> None:
    """Fail on a roller's (and its winder's) friction tables, and on a break-away torque
    that does not exceed the friction it runs with at rest (Coulomb plus the table's first
    point): static friction is the larger."""
    check_friction_table(roller.friction_table, f"{key}.friction_table", fail)
    winder = getattr(roller, "winder", None)
    if winder is not None:
        check_friction_table(winder.friction_table, f"{key}.winder.friction_table", fail)
    if roller.breakaway_torque > 0.0:
        table = roller.friction_table
        running = roller.coulomb_friction + (table.torque[0] if table is not None else 0.0)
        if roller.breakaway_torque <= running:
            fail(f"{key}.breakaway_torque", f"must exceed the running friction at rest "
                 f"({running:g} N*m: coulomb_friction plus the table's first torque)")
