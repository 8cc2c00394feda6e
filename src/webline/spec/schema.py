"""The line-file schema: strict pydantic models whose numeric fields are SI floats.

Quantities accept a plain SI number or a string with units (``"500 ft/min"``). Unknown keys
are errors; each component is chosen by its ``type``, never guessed from the keys present.
"""

from __future__ import annotations

from typing import Annotated, Any, Literal

from pydantic import BaseModel, BeforeValidator, ConfigDict, Discriminator, Field, Tag

from webline.units import to_si


class Strict(BaseModel):
    """Base: frozen, unknown keys rejected."""

    model_config = ConfigDict(extra="forbid", frozen=True)


def _quantity(kind: str, bound: str | None = None) -> Any:
    """An SI float of dimension ``kind``; ``bound`` is '>0' or '>=0'."""

    def parse(value: object) -> float:
        number = to_si(value, kind)
        if bound == ">0" and not number > 0:
            raise ValueError(f"must be > 0, got {value!r}")
        if bound == ">=0" and not number >= 0:
            raise ValueError(f"must be >= 0, got {value!r}")
        return number

    return Annotated[float, BeforeValidator(parse)]


Length = _quantity("length", ">0")
Speed = _quantity("speed", ">=0")
SignedSpeed = _quantity("speed")
Force = _quantity("force", ">0")
SignedForce = _quantity("force")
Torque = _quantity("torque", ">0")
TorqueNonNeg = _quantity("torque", ">=0")
Inertia = _quantity("inertia", ">0")
InertiaNonNeg = _quantity("inertia", ">=0")
Damping = _quantity("rot_damping", ">=0")
Time = _quantity("time", ">0")
TimeNonNeg = _quantity("time", ">=0")
Frequency = _quantity("frequency", ">0")
Density = _quantity("density", ">0")
Modulus = _quantity("pressure", ">0")
Angle = _quantity("angle")
Ratio = _quantity("dimensionless", ">0")
Gain = _quantity("dimensionless", ">=0")


# --- reference profiles -------------------------------------------------------------------


def _profile_models(kind: str, value_type: Any) -> Any:
    """Constant, ramp, steps and table profiles for a reference of ``kind``."""

    class Ramp(Strict):
        """Linear change from ``initial`` to ``final`` over ``duration`` starting at ``start``."""

        type: Literal["ramp"]
        initial: value_type
        final: value_type
        start: TimeNonNeg = 0.0
        duration: Time

    class Step(Strict):
        time: TimeNonNeg
        value: value_type

    class Steps(Strict):
        """Piecewise-constant: ``initial`` until the first step time, then each step's value."""

        type: Literal["steps"]
        initial: value_type
        steps: list[Step] = Field(min_length=1)

    class Table(Strict):
        """Piecewise-linear through (time, value) points; constant outside them."""

        type: Literal["table"]
        time: list[TimeNonNeg] = Field(min_length=1)  # type: ignore[valid-type]
        value: list[value_type] = Field(min_length=1)  # type: ignore[valid-type]

    Ramp.__name__ = Ramp.__qualname__ = f"{kind.title()}Ramp"
    Steps.__name__ = Steps.__qualname__ = f"{kind.title()}Steps"
    Table.__name__ = Table.__qualname__ = f"{kind.title()}Table"

    def tag(value: object) -> str:
        if isinstance(value, dict):
            return str(value.get("type", "missing"))
        if isinstance(value, BaseModel):
            return str(getattr(value, "type", "constant"))
        return "constant"

    return Annotated[
        Annotated[value_type, Tag("constant")]
        | Annotated[Ramp, Tag("ramp")]
        | Annotated[Steps, Tag("steps")]
        | Annotated[Table, Tag("table")],
        Discriminator(
            tag,
            custom_error_type="profile_type",
            custom_error_message="a profile is a quantity or a table with type = "
            "'ramp', 'steps' or 'table'",
        ),
    ]


SpeedProfile = _profile_models("speed", Speed)
TensionProfile = _profile_models("tension", Force)


# --- web ------------------------------------------------------------------------------------


class WebSpec(Strict):
    """The web material. Give ``modulus`` (with thickness and width) or ``ea`` directly."""

    thickness: Length
    width: Length
    density: Density
    modulus: Modulus | None = None
    ea: Force | None = None


# --- drives and controllers ---------------------------------------------------------------


class DriveSpec(Strict):
    """A motor and its direct transmission to the roller shaft.

    ``ratio`` is motor speed / roller speed, so the roller sees ``ratio * motor torque`` and
    the motor inertia reflects as ``ratio**2 * motor_inertia``.
    """

    ratio: Ratio = 1.0
    torque_limit: Torque
    torque_lag: Time = 0.002
    motor_inertia: InertiaNonNeg = 0.0


class CascadedPISpec(Strict):
    """Industrial cascaded PI (thesis Fig. 4.3): tension PI trims the speed reference.

    Gains are SI: speed_kp [N·m·s/m], speed_ki [N·m/m], tension_kp [(m/s)/N],
    tension_ki [(m/s)/(N·s)]. A missing gain is tuned by pole placement from the bandwidths
    [rad/s] and damping ratio (see ``webline.control.pi.tune``).
    """

    type: Literal["cascaded_pi"] = "cascaded_pi"
    speed_kp: Gain | None = None
    speed_ki: Gain | None = None
    tension_kp: Gain | None = None
    tension_ki: Gain | None = None
    speed_bandwidth: Frequency = 40.0
    tension_bandwidth: Frequency = 8.0
    damping: Ratio = 1.0
    inertia_adaptive: bool = True


# --- rollers ----------------------------------------------------------------------------------


class _RollerBase(Strict):
    name: str = Field(min_length=1)
    radius: Length
    inertia: Inertia
    friction: Damping = 0.0
    coulomb_friction: TorqueNonNeg = 0.0


class UnwindSpec(_RollerBase):
    """Unwind roll. ``radius`` is the initial outer radius; ``inertia`` excludes the web."""

    type: Literal["unwind"]
    core_radius: Length
    wound_in_tension: Force
    drive: DriveSpec
    controller: CascadedPISpec = CascadedPISpec()


class RewindSpec(_RollerBase):
    """Rewind roll. ``radius`` is the initial outer radius; ``inertia`` excludes the web."""

    type: Literal["rewind"]
    core_radius: Length
    drive: DriveSpec
    controller: CascadedPISpec = CascadedPISpec()


class DrivenSpec(_RollerBase):
    """Driven roller: the master-speed roller or a tension-controlled one."""

    type: Literal["driven"]
    role: Literal["master", "tension"]
    drive: DriveSpec
    controller: CascadedPISpec = CascadedPISpec()


class IdleSpec(_RollerBase):
    """Idle roller: turned by the web, with bearing friction."""

    type: Literal["idle"]


RollerSpec = Annotated[
    UnwindSpec | RewindSpec | DrivenSpec | IdleSpec,
    Field(discriminator="type"),
]


class SpanSpec(Strict):
    """Free web span between two consecutive rollers. ``tension`` marks its zone's loadcell."""

    name: str | None = None
    length: Length
    tension: TensionProfile | None = None


# --- disturbances ---------------------------------------------------------------------------


class WoundInRipple(Strict):
    """Sinusoidal component of the unwind's wound-in tension (thesis Ch. 4)."""

    type: Literal["wound_in_ripple"]
    amplitude: Force
    frequency: Frequency
    phase: Angle = 0.0


class EccentricRoller(Strict):
    """Out-of-round roller: its effective radius is ``radius + eccentricity·cos(angle)``."""

    type: Literal["eccentric_roller"]
    roller: str
    eccentricity: Length


class SpeedRipple(Strict):
    """Sinusoidal ripple added to a driven roller's speed reference."""

    type: Literal["speed_ripple"]
    roller: str
    amplitude: Speed
    frequency: Frequency
    phase: Angle = 0.0


DisturbanceSpec = Annotated[
    WoundInRipple | EccentricRoller | SpeedRipple, Field(discriminator="type")
]


class ControlSpec(Strict):
    """Sampling of the built-in controllers."""

    sample_rate: Frequency = 1000.0


class ScenarioSpec(Strict):
    """A named run of the line: it may replace the speed reference, the disturbances and the
    initial roll radii, and sets a default duration."""

    description: str = ""
    duration: Time
    speed: SpeedProfile | None = None
    disturbances: list[DisturbanceSpec] | None = None
    unwind_radius: Length | None = None
    rewind_radius: Length | None = None


class LineSpec(Strict):
    """A whole web line, rollers in web order (unwind first, rewind last)."""

    name: str = Field(min_length=1)
    description: str = ""
    source: str = ""
    web: WebSpec
    rollers: list[RollerSpec] = Field(min_length=2)
    spans: list[SpanSpec] = Field(min_length=1)
    speed: SpeedProfile
    control: ControlSpec = ControlSpec()
    disturbances: list[DisturbanceSpec] = []
    scenarios: dict[str, ScenarioSpec] = {}
