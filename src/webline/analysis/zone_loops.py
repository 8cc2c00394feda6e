"""Each tension zone's loop against what was asked of it (docs/winder.md, Z1-Z3): the
stiffness its tension PI works against, the asked bandwidth and damping, and the closed-loop
mode the loop actually has (the one its tension integrator takes the largest part in), and the
speed loops that let tension leak through their rollers.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from webline.control.zone_tuning import SpeedLoopLeak, loop_plant_gain, speed_loop_leaks
from webline.limits import MAX_EIGEN_STATES
from webline.line import Line, load_line
from webline.sim import layout as L
from webline.sim.linearize import plan_linear_model
from webline.sim.plan import compile_plan
from webline.spec.schema import CascadedPISpec

#: a loop's mode counts as meeting its asked bandwidth within this share, with this damping
BANDWIDTH_TOLERANCE = 0.3
MIN_DAMPING = 0.5


@dataclass(frozen=True)
class ZoneLoop:
    """One zone's tension loop (cascaded PI): what it measures, the plant gain per metre of
    web stored (K [N/m] for a tension, G [m/m] for a dancer position), the asked bandwidth
    [rad/s] and damping, and its closed-loop mode: eigenvalue [1/s], natural frequency
    [rad/s], damping."""

    zone: int
    drive: str
    measures: str
    plant_gain: float
    asked_bandwidth: float
    asked_damping: float
    eigenvalue: complex

    @property
    def bandwidth(self) -> float:
        return abs(self.eigenvalue)

    @property
    def damping(self) -> float:
        return -self.eigenvalue.real / abs(self.eigenvalue) if self.eigenvalue else float("nan")

    @property
    def meets(self) -> bool:
        """Within ``BANDWIDTH_TOLERANCE`` of the asked bandwidth with damping >=
        min(``MIN_DAMPING``, the asked one)."""
        close = abs(self.bandwidth / self.asked_bandwidth - 1.0) <= BANDWIDTH_TOLERANCE
        return close and self.damping >= min(MIN_DAMPING, self.asked_damping)

    def as_dict(self) -> dict[str, object]:
        return {"zone": self.zone + 1, "drive": self.drive, "measures": self.measures,
                "plant_gain": self.plant_gain, "asked_bandwidth_rad_s": self.asked_bandwidth,
                "asked_damping": self.asked_damping, "bandwidth_rad_s": self.bandwidth,
                "damping_ratio": self.damping, "meets": self.meets}


def zone_loops(line: Line | str, t: float = 0.0) -> list[ZoneLoop]:
    """The tension loop of every zone whose drive runs a cascaded PI, linearized at time ``t``
    [s] (the plan's cached closed-loop model); none for a model beyond
    ``limits.MAX_EIGEN_STATES`` states (its dense eigen-decomposition is not computed)."""
    line = load_line(line)
    plan = compile_plan(line)
    model = plan_linear_model(plan, loop="closed", t=t)
    if len(model.states) > MAX_EIGEN_STATES:
        return []
    values, right = np.linalg.eig(np.asarray(model.a, dtype=float))
    left = np.linalg.inv(right)
    participation = np.abs(right * left.T)
    share = participation / participation.sum(axis=0, keepdims=True)
    out = []
    for z, zone in enumerate(line.zones):
        roller = line.spec.rollers[zone.controller]
        c = getattr(roller, "controller", None)
        if not isinstance(c, CascadedPISpec):
            continue
        name = f"{roller.name}_tension_integral"
        if name not in model.states or plan.drives[line.drives.index(zone.controller),
                                                    L.D_FAMILY] != L.FAMILY_PI:
            continue
        row = share[model.states.index(name)]
        j = int(np.argmax(np.where(values.imag >= 0.0, row, -1.0)))
        measures, gain = loop_plant_gain(line, z)
        out.append(ZoneLoop(z, roller.name, measures, gain, c.tension_bandwidth, c.damping,
                            complex(values[j])))
    return out


def speed_leaks(line: Line | str) -> list[SpeedLoopLeak]:
    """Driven rollers whose speed loop (as the plan tuned it) lets tension leak (Z3)."""
    line = load_line(line)
    plan = compile_plan(line)
    return speed_loop_leaks(line, {i: float(plan.drives[d, L.D_KIS])
                                   for d, i in enumerate(line.drives)})
