"""Parameter sets of the drive-train analyses and the loaders of the data files.

Parameter sets are frozen dataclasses in SI units. The data files under
``webline/data/drivetrain/`` are named after their source in the thesis; each opens with a
comment citing it and listing every assumed value. Values in the files are numbers (SI) or
strings with units (``"2.13 kg*m**2"``, ``"4.51 in"``).
"""

from __future__ import annotations

import tomllib
from dataclasses import dataclass, replace
from importlib import resources
from typing import Any

from webline.units import ureg

DATA_PACKAGE = "webline.data.drivetrain"


@dataclass(frozen=True)
class BeltDrive:
    """Two inertias joined by the tight side of a belt (thesis Fig. 2.1, eq. 2.10).

    j_motor, j_load [kg·m²]; b_motor, b_load [N·m·s/rad] viscous friction; r_motor (R1),
    r_load (R2) [m] pulley pitch radii; stiffness (Kb) [N/m] of the tight side.
    """

    j_motor: float
    j_load: float
    b_motor: float
    b_load: float
    r_motor: float
    r_load: float
    stiffness: float

    @property
    def speed_ratio(self) -> float:
        """BR = R2/R1 [-] (thesis's BR): motor speed / load speed for a rigid belt."""
        return self.r_load / self.r_motor

    @property
    def j_sum(self) -> float:
        """Jeq of (2.15a): R2² Jm + R1² JL [kg·m⁴]."""
        return self.r_load**2 * self.j_motor + self.r_motor**2 * self.j_load

    @property
    def b_sum(self) -> float:
        """beq of (2.15b), corrected (E-2.1): R2² bm + R1² bL [N·m³·s]."""
        return self.r_load**2 * self.b_motor + self.r_motor**2 * self.b_load

    def with_stiffness(self, stiffness: float) -> BeltDrive:
        """The same drive with belt ``stiffness`` [N/m]."""
        return replace(self, stiffness=stiffness)


@dataclass(frozen=True)
class SpeedPI:
    """PI speed controller τ = kp e + ki ∫e, e = ω_ref - ω (2.3 or 2.7).

    kp [N·m·s/rad], ki [N·m/rad] (rectilinear analog: [N·s/m], [N/m]).
    """

    kp: float
    ki: float


@dataclass(frozen=True)
class BacklashDrive:
    """Compliance in series with backlash, general form of (3.22) and (3.31).

    Jm θ̈m + bm θ̇m + r1 ψ = τm,  JL θ̈L + bL θ̇L - α1 ψ = τL,
    ψ = K dz(r1 θm - α1 θL) with the gap [-α2 gap_neg, α2 gap_pos] (physics.backlash).

    j_motor, j_load [kg·m²] (or masses [kg]); b_motor, b_load [N·m·s] (or [N·s/m]); stiffness K
    [N/m]; r_motor = R1 [m]; lever_load = α1 [m]; gap_gain = α2 [-]; gap_neg, gap_pos [m].
    The compliant shaft of Fig. 3.10 (rectilinear analog) has R1 = α1 = α2 = 1.
    """

    j_motor: float
    j_load: float
    b_motor: float
    b_load: float
    stiffness: float
    gap_neg: float
    gap_pos: float
    r_motor: float = 1.0
    lever_load: float = 1.0
    gap_gain: float = 1.0

    @classmethod
    def rectilinear(cls, m_motor: float, m_load: float, b_motor: float, b_load: float,
                    stiffness: float, half_gap: float) -> BacklashDrive:
        """Fig. 3.10(b): masses [kg], damping [N·s/m], spring [N/m], symmetric gap ±Δ [m]."""
        return cls(m_motor, m_load, b_motor, b_load, stiffness, half_gap, half_gap)

    @classmethod
    def belt_and_gears(cls, belt: BeltDrive, rg1: float, rg2: float,
                       half_gap: float) -> BacklashDrive:
        """Fig. 3.12: ``belt`` then a gear pair of pitch radii ``rg1``, ``rg2`` [m] with a
        symmetric gap ±``half_gap`` [m] at the pitch circle: α1 = R2 Rg2/Rg1, α2 = R2/Rg1."""
        return cls(belt.j_motor, belt.j_load, belt.b_motor, belt.b_load, belt.stiffness,
                   half_gap, half_gap, r_motor=belt.r_motor,
                   lever_load=belt.r_load * rg2 / rg1, gap_gain=belt.r_load / rg1)

    @property
    def deviation_bound(self) -> float:
        """sup |φ| [N] of (3.48)/(3.65): K α2 max(gap_neg, gap_pos)."""
        return self.stiffness * self.gap_gain * max(self.gap_neg, self.gap_pos)

    def with_gap(self, gap_neg: float, gap_pos: float) -> BacklashDrive:
        """The same drive with another gap [m]."""
        return replace(self, gap_neg=gap_neg, gap_pos=gap_pos)


def _to_si(value: Any) -> Any:
    if isinstance(value, str):
        return float(ureg.Quantity(value).to_base_units().magnitude)
    if isinstance(value, dict):
        return {key: _to_si(item) for key, item in value.items()}
    return value


def load_parameter_set(name: str) -> dict[str, Any]:
    """The data file ``webline/data/drivetrain/<name>.toml`` with every table value in SI.

    Top-level strings (``name``, ``source``) are kept as text; strings inside tables are read as
    quantities and converted to SI base units (rad/s and Hz become 1/s: Hz is *not* turned
    into rad/s, so a ``frequency`` in Hz arrives in cycles per second).
    """
    text = resources.files(DATA_PACKAGE).joinpath(f"{name}.toml").read_text(encoding="utf-8")
    data = tomllib.loads(text)
    return {key: (_to_si(value) if isinstance(value, dict) else value)
            for key, value in data.items()}


def hswl_unwind_belt_drive(belt: str = "36mm") -> BeltDrive:
    """The HSWL unwind belt drive of thesis Sec. 2.5 with the ``belt`` '12mm', '24mm', '36mm'."""
    data = load_parameter_set("hswl_unwind_belt_sec2_5")
    plant = data["plant"]
    return BeltDrive(plant["motor_inertia"], plant["load_inertia"], plant["motor_damping"],
                     plant["load_damping"], plant["motor_pulley_radius"],
                     plant["load_pulley_radius"], data["belt_stiffness"][belt])


def ecp_rectilinear_plant(gap: str = "fig3_17") -> BacklashDrive:
    """The ECP rectilinear plant of thesis Sec. 3.5 with the backlash ``gap`` of the named
    figure ('fig3_17', 'fig3_18', 'fig3_19'; the gap is 2Δ, see the data file)."""
    data = load_parameter_set("ecp_rectilinear_sec3_5")
    plant = data["plant"]
    return BacklashDrive.rectilinear(plant["motor_mass"], plant["load_mass"],
                                     plant["motor_damping"], plant["load_damping"],
                                     plant["stiffness"], 0.5 * data["backlash_gap"][gap])
