"""The line-file schema: strict pydantic models whose numeric fields are SI floats.

Quantities accept a plain SI number or a string with units (``"500 ft/min"``). Unknown keys
are errors; each component is chosen by its ``type``, never guessed from the keys present.
"""

from __future__ import annotations

from typing import Annotated, Any, Literal

from pydantic import ConfigDict, Field

from webline.spec.control_schema import (  # noqa: F401 - re-exported for users of the schema
    AdaptiveSpec,
    CascadedPISpec,
    ControllerSpec,
    MRACSpec,
    PythonControllerSpec,
    StateFeedbackSpec,
)
from webline.spec.dancer import DancerCarriage
from webline.spec.disturbances import (  # noqa: F401 - re-exported for users of the schema
    DisturbanceSpec,
    EccentricRoller,
    MeasurementNoise,
    Name,
    RollerDrag,
    SpeedRipple,
    WoundInRipple,
)
from webline.spec.friction import MeasuredFriction
from webline.spec.nip import NipSpec
from webline.spec.quantities import (  # noqa: F401 - re-exported for users of the schema
    Angle,
    AngularFrequency,
    Damping,
    Density,
    Force,
    Frequency,
    Gain,
    Inertia,
    InertiaNonNeg,
    Length,
    Modulus,
    Profile,
    Ramp,
    Ratio,
    Speed,
    SpeedProfile,
    Step,
    Steps,
    Strict,
    Table,
    TensionProfile,
    Time,
    TimeNonNeg,
    Torque,
    TorqueNonNeg,
    TorqueProfile,
    si,
)
from webline.spec.roll_inertia import RollInertiaSpec
from webline.spec.roll_stress import RollStressSpec
from webline.spec.sensors import SensorSpec
from webline.spec.splice import FlyingSplice, SpliceEvent  # noqa: F401
from webline.spec.web_law import StressStrainSpec
from webline.spec.winder import (  # noqa: F401
    BreakEvent,
    DiameterSpec,
    DifferentialShaftSpec,
    StartStopTension,
    StateChecksSpec,
    TaperSpec,
    WebBreak,
    WinderSpec,
)

#: free text, bounded
Text = Annotated[str, Field(max_length=10_000)]

# --- web ------------------------------------------------------------------------------------


class WebSpec(Strict):
    """The web material. Give ``modulus`` (with thickness and width) or ``ea`` directly.

    ``strength`` [N]: the tension at which the web breaks (a run stops there, failed);
    ``tension_limit`` [N]: a tension the line should stay below (a warning where exceeded).
    ``stress_strain``: the stress-strain law (``spec.web_law``; none: linear, T = EA ε).
    ``transport``: how a span's tension follows the speeds (docs/line-file.md): ``"exact"``
    conservation of web mass, d/dt[L/(1 + ε)] = v_in/(1 + ε_in) - v_out/(1 + ε), or the
    thesis's ``"first-order"`` form (6.8, errata E-6.6), right to within ε² of a draw.
    """

    thickness: Length
    width: Length
    density: Density
    modulus: Modulus | None = None
    ea: Force | None = None
    strength: Force | None = None
    tension_limit: Force | None = None
    stress_strain: StressStrainSpec | None = None
    transport: Literal["exact", "first-order"] = "exact"


# --- drives and controllers ---------------------------------------------------------------


class BacklashSpec(Strict):
    """Gear backlash in series with the transmission's compliance (thesis 3.22-3.23, 3.31-3.32).

    The load may move ``gap`` Δ [rad at the load shaft] either way before the teeth touch; with
    ``asymmetry`` a the free travel is 2Δa backwards and 2Δ(1 - a) forwards (Remark 3.3.1;
    a = 0.5 is the symmetric gap).
    """

    gap: Annotated[float, si("angle", ">=0")]
    asymmetry: Annotated[float, Field(ge=0.0, le=1.0)] = 0.5


class DirectSpec(Strict):
    """Rigid transmission: the motor inertia reflects to the roller as ratio² x motor_inertia."""

    type: Literal["direct"] = "direct"


class BeltSpec(Strict):
    """Belt-pulley transmission whose tight side is a spring (thesis 2.10): ``stiffness`` Kb
    [N/m], ``damping`` [N·s/m], the load pulley of ``load_pulley_radius`` r2 [m] (the motor
    pulley is r2/ratio). Seen from the load shaft: Kb r2² [N·m/rad]."""

    type: Literal["belt"]
    stiffness: Annotated[float, si("stiffness", ">0")]
    load_pulley_radius: Length
    damping: Annotated[float, si("linear_damping", ">=0")] = 0.0
    backlash: BacklashSpec | None = None


class ShaftSpec(Strict):
    """Compliant shaft (or coupling) seen from the load shaft: ``stiffness`` [N·m/rad],
    ``damping`` [N·m·s/rad] (thesis 3.22 in rotary form)."""

    type: Literal["shaft"]
    stiffness: Torque
    damping: Damping = 0.0
    backlash: BacklashSpec | None = None


TransmissionSpec = Annotated[DirectSpec | BeltSpec | ShaftSpec, Field(discriminator="type")]


class DriveSpec(Strict):
    """A motor, its torque loop and its transmission to the roller shaft.

    ``ratio`` is motor speed / roller speed, so the roller sees ``ratio * motor torque``.
    ``feedback`` chooses where the speed loop measures: the roller ("load") or the motor's
    encoder ("motor"), which differ across a compliant transmission (thesis 2.16-2.19).
    ``motor_friction`` [N·m·s] acts on the motor shaft; ``brake`` [N·m] is a torque on the
    roller shaft opposing its rotation (thesis 4.12), constant or a profile.
    """

    ratio: Ratio = 1.0
    torque_limit: Torque
    torque_lag: Time = 0.002
    motor_inertia: InertiaNonNeg = 0.0
    motor_friction: Damping = 0.0
    transmission: TransmissionSpec = DirectSpec()
    feedback: Literal["load", "motor"] = "load"
    brake: TorqueProfile | None = None


# --- rollers ----------------------------------------------------------------------------------


class AdheredSpec(Strict):
    """The web moves with the roller's surface: v = r ω."""

    type: Literal["adhered"] = "adhered"


class TractionSpec(Strict):
    """Web-roller traction with stiction, Coulomb and viscous terms (thesis 5.37-5.44, E-5.3):
    static ``friction`` μ0 [-], ``kinetic_friction`` μ' <= μ0 [-] (default μ0), ``viscous`` b
    [N·s/m]. The web slips when the tension difference leaves the capstan band of the wrap."""

    type: Literal["traction"]
    friction: Annotated[float, si("dimensionless", ">0")]
    kinetic_friction: Annotated[float, si("dimensionless", ">=0")] | None = None
    viscous: Annotated[float, si("linear_damping", ">0")]


ContactSpec = Annotated[AdheredSpec | TractionSpec, Field(discriminator="type")]


class _RollerBase(Strict):
    name: Name
    radius: Length
    inertia: Inertia
    friction: Damping = 0.0
    coulomb_friction: TorqueNonNeg = 0.0
    #: friction torque measured against shaft speed, added to the two above (spec.friction)
    friction_table: MeasuredFriction | None = None
    #: static friction [N·m] a roller at rest must overcome; 0: none (docs/winder.md, F2)
    breakaway_torque: TorqueNonNeg = 0.0


class UnwindSpec(_RollerBase):
    """Unwind roll. ``radius`` is the initial outer radius; ``inertia`` excludes the web, or
    is given as totals at stated diameters (``webline.spec.roll_inertia``)."""

    type: Literal["unwind"]
    #: rotating parts without the web [kg·m²], or totals at stated diameters (spec.roll_inertia)
    inertia: Inertia | RollInertiaSpec  # type: ignore[assignment]
    core_radius: Length
    wound_in_tension: Force
    drive: DriveSpec
    controller: ControllerSpec = CascadedPISpec()
    diameter: DiameterSpec | None = None
    winder: WinderSpec | None = None


class RewindSpec(_RollerBase):
    """Rewind roll. ``radius`` is the initial outer radius; ``inertia`` excludes the web (or
    totals, ``webline.spec.roll_inertia``);
    ``taper`` makes its zone's tension reference a function of its diameter; ``shaft`` a
    differential (slip) shaft for lanes on one shaft (branched lines only); ``roll_stress``
    the wound roll's stress model and limits (``webline.spec.roll_stress``)."""

    type: Literal["rewind"]
    inertia: Inertia | RollInertiaSpec  # type: ignore[assignment]
    core_radius: Length
    drive: DriveSpec
    controller: ControllerSpec = CascadedPISpec()
    taper: TaperSpec | None = None
    diameter: DiameterSpec | None = None
    winder: WinderSpec | None = None
    shaft: DifferentialShaftSpec | None = None
    roll_stress: RollStressSpec | None = None


class DrivenSpec(_RollerBase):
    """Driven roller: the master-speed roller or a tension-controlled one. ``wrap`` [rad] is
    the web's wrap angle; ``contact`` chooses adhesion or slip (Ch. 5); ``nip`` a pressure
    roller (``webline.spec.nip``)."""

    type: Literal["driven"]
    role: Literal["master", "tension"]
    wrap: Annotated[float, si("angle", ">0")] | None = None
    contact: ContactSpec = AdheredSpec()
    nip: NipSpec | None = None
    drive: DriveSpec
    controller: ControllerSpec = CascadedPISpec()


class IdleSpec(_RollerBase):
    """Idle roller: turned by the web, with bearing friction. ``wrap`` [rad], ``contact`` and
    ``nip`` as for a driven roller."""

    type: Literal["idle"]
    wrap: Annotated[float, si("angle", ">0")] | None = None
    contact: ContactSpec = AdheredSpec()
    nip: NipSpec | None = None


class DancerSpec(IdleSpec):
    """Idle roller on a moving carriage or arm: a dancer (``webline.spec.dancer``)."""

    type: Literal["dancer"]  # type: ignore[assignment]
    dancer: DancerCarriage


RollerSpec = Annotated[
    UnwindSpec | RewindSpec | DrivenSpec | IdleSpec | DancerSpec,
    Field(discriminator="type"),
]


class SpanSpec(Strict):
    """Free web span between two consecutive rollers. ``tension`` marks its zone's loadcell.
    ``model``: ``"elastic"`` (T = EA ε) or ``"kelvin-voigt"`` (T = EA (ε + τ dε/dt), τ the
    ``retardation`` time η/E [s]; docs/winder.md, Viscoelastic span)."""

    name: Name | None = None
    length: Length
    tension: TensionProfile | None = None
    model: Literal["elastic", "kelvin-voigt"] = "elastic"
    retardation: TimeNonNeg | None = None


class ControlSpec(Strict):
    """Sampling of the built-in controllers, and the tension ramp at start and stop of
    every zone's set tension (``spec.winder.StartStopTension``)."""

    sample_rate: Frequency = 1000.0
    tension_ramp: StartStopTension | None = None


class ScenarioSpec(Strict):
    """A named run of the line: it may replace the speed reference, the disturbances and the
    initial roll radii, add a web ``break`` or a flying ``splice``, and sets a default
    duration. ``set`` changes any other value by its nested path (``"spans.span2.tension"``
    = a steps profile, a controller's bandwidth...; see ``webline.spec.paths``), applied
    after the keys above."""

    description: Text = ""
    duration: Time
    set: dict[str, Any] = Field(default_factory=dict)
    speed: SpeedProfile | None = None
    disturbances: list[DisturbanceSpec] | None = None
    unwind_radius: Length | None = None
    rewind_radius: Length | None = None
    # ``break`` in the file (a Python keyword); a dump writes break_, which reads back too
    break_: BreakEvent | None = Field(None, alias="break")
    splice: SpliceEvent | None = None  # docs/winder.md, Flying splice
    model_config = ConfigDict(extra="forbid", frozen=True, populate_by_name=True)


class LineSpec(Strict):
    """A whole web line, rollers in web order (unwind first, rewind last)."""

    name: Name
    description: Text = ""
    source: Text = ""
    web: WebSpec
    rollers: list[RollerSpec] = Field(min_length=2)
    spans: list[SpanSpec] = Field(min_length=1)
    speed: SpeedProfile
    control: ControlSpec = ControlSpec()
    checks: StateChecksSpec = StateChecksSpec()
    disturbances: list[DisturbanceSpec] = Field(default_factory=list)
    #: the loadcells and encoders the controllers read, with their calibration (spec.sensors)
    sensors: list[SensorSpec] = Field(default_factory=list)
    scenarios: dict[str, ScenarioSpec] = Field(default_factory=dict)
