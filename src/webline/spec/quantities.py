"""Building blocks of the line-file schema: SI quantity types and reference profiles.

A quantity is a plain SI number or a string with units (``"500 ft/min"``); a profile is a
quantity (constant) or a table with ``type`` = "ramp", "steps" or "table".
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Annotated, Any, Generic, Literal, TypeVar

from pydantic import (
    BaseModel,
    BeforeValidator,
    ConfigDict,
    Discriminator,
    Field,
    Tag,
    ValidationInfo,
    field_validator,
)

from webline.spec.ranges import numbers_of, range_for
from webline.units import per_width_to_si, to_si


class Strict(BaseModel):
    """Base: frozen, unknown keys rejected, every quantity inside its physical range
    (``webline.spec.ranges``, which maps each model to its sections)."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    if not TYPE_CHECKING:  # (for the type checker an unknown attribute stays an error)
        def __getattr__(self, name: str) -> Any:
            """A missing attribute, at once. pydantic's own fallback looks for private and
            extra attributes first, which these models have none of: ``getattr(roller,
            "nip", None)`` on a roller without that field (plans, checks and operating
            points ask ~30 such questions per line) then costs a fifth."""
            raise AttributeError(f"{type(self).__name__!r} object has no attribute {name!r}")

    @field_validator("*", mode="after")
    @classmethod
    def _in_physical_range(cls, value: object, info: ValidationInfo) -> object:
        found = range_for(cls, info.field_name or "")
        if found is not None:
            for suffix, number in numbers_of(value):
                problem = found.hard_problem(number)
                if problem:  # the loader moves a [[suffix]] into the key path
                    raise ValueError(f"[[{suffix}]] {problem}" if suffix else problem)
        return value


#: validation context key of the web's width [m] (``spec.load.spec_from_dict``), with which a
#: force given per width of web (N/m, N/cm, pli) becomes a force [N]
WEB_WIDTH = "web_width"


def si(kind: str, bound: str | None = None) -> BeforeValidator:
    """Validator turning a number or a unit string into an SI float of dimension ``kind``;
    ``bound`` is '>0' or '>=0'. A force may also be given per width of web (``"1 pli"``,
    ``"175 N/m"``): it is multiplied by the web's width from the validation context."""

    def check(number: float, value: object) -> float:
        if bound == ">0" and not number > 0:
            raise ValueError(f"must be > 0, got {value!r}")
        if bound == ">=0" and not number >= 0:
            raise ValueError(f"must be >= 0, got {value!r}")
        return number

    def parse(value: object) -> float:
        return check(to_si(value, kind), value)

    def parse_force(value: object, info: ValidationInfo) -> float:
        per_width = per_width_to_si(value)
        if per_width is None:
            return parse(value)
        width = (info.context or {}).get(WEB_WIDTH)
        if width is None:
            raise ValueError(f"{value!r} is a force per width of web, and no web width is "
                             "known here (give web.width, or the force in N)")
        return check(per_width * width, value)

    return BeforeValidator(parse_force if kind == "force" else parse)


Length = Annotated[float, si("length", ">0")]
Speed = Annotated[float, si("speed", ">=0")]
Force = Annotated[float, si("force", ">0")]
Torque = Annotated[float, si("torque", ">0")]
TorqueNonNeg = Annotated[float, si("torque", ">=0")]
Inertia = Annotated[float, si("inertia", ">0")]
InertiaNonNeg = Annotated[float, si("inertia", ">=0")]
Damping = Annotated[float, si("rot_damping", ">=0")]
Time = Annotated[float, si("time", ">0")]
TimeNonNeg = Annotated[float, si("time", ">=0")]
Frequency = Annotated[float, si("frequency", ">0")]
#: a rate in rad/s; "6 Hz" is read as 2π·6 rad/s
AngularFrequency = Annotated[float, si("angular_frequency", ">0")]
Density = Annotated[float, si("density", ">0")]
Modulus = Annotated[float, si("pressure", ">0")]
Angle = Annotated[float, si("angle")]
Ratio = Annotated[float, si("dimensionless", ">0")]
Gain = Annotated[float, si("dimensionless", ">=0")]


# --- reference profiles -------------------------------------------------------------------


Q = TypeVar("Q")


class Ramp(Strict, Generic[Q]):
    """Linear change from ``initial`` to ``final`` over ``duration`` starting at ``start``."""

    type: Literal["ramp"]
    initial: Q
    final: Q
    start: TimeNonNeg = 0.0
    duration: Time


class Step(Strict, Generic[Q]):
    time: TimeNonNeg
    value: Q


class Steps(Strict, Generic[Q]):
    """Piecewise-constant: ``initial`` until the first step time, then each step's value."""

    type: Literal["steps"]
    initial: Q
    steps: list[Step[Q]] = Field(min_length=1)


class Table(Strict, Generic[Q]):
    """Piecewise-linear through (time, value) points; constant outside them."""

    type: Literal["table"]
    time: list[TimeNonNeg] = Field(min_length=1)
    value: list[Q] = Field(min_length=1)


def _profile_tag(value: object) -> str:
    if isinstance(value, dict):
        return str(value.get("type", "missing"))
    if isinstance(value, BaseModel):
        return str(getattr(value, "type", "constant"))
    return "constant"


_PROFILE = Discriminator(
    _profile_tag,
    custom_error_type="profile_type",
    custom_error_message="a profile is a quantity or a table with type = 'ramp', 'steps' or "
    "'table'",
)

SpeedProfile = Annotated[
    Annotated[Speed, Tag("constant")] | Annotated[Ramp[Speed], Tag("ramp")]
    | Annotated[Steps[Speed], Tag("steps")] | Annotated[Table[Speed], Tag("table")],
    _PROFILE,
]
TensionProfile = Annotated[
    Annotated[Force, Tag("constant")] | Annotated[Ramp[Force], Tag("ramp")]
    | Annotated[Steps[Force], Tag("steps")] | Annotated[Table[Force], Tag("table")],
    _PROFILE,
]
TorqueProfile = Annotated[
    Annotated[TorqueNonNeg, Tag("constant")] | Annotated[Ramp[TorqueNonNeg], Tag("ramp")]
    | Annotated[Steps[TorqueNonNeg], Tag("steps")]
    | Annotated[Table[TorqueNonNeg], Tag("table")],
    _PROFILE,
]
Profile = SpeedProfile | TensionProfile | TorqueProfile
