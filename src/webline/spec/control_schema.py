"""The controller families of a driven roller in the line file (``[rollers.controller]``):
the industrial cascaded PI, the decentralized families of thesis Ch. 6 and a user's Python
controller; ``ControllerSpec`` chooses one by its ``type``."""

from __future__ import annotations

from typing import Annotated, Any, Literal

from pydantic import Discriminator, Field, Tag, model_validator

from webline.spec.quantities import (
    AngularFrequency,
    Damping,
    Force,
    Gain,
    Ratio,
    Strict,
    Torque,
    si,
)


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
    speed_bandwidth: AngularFrequency = 40.0
    tension_bandwidth: AngularFrequency = 8.0
    damping: Ratio = 1.0
    inertia_adaptive: bool = True


Signed = Annotated[float, si("dimensionless")]


class _DecentralizedSpec(Strict):
    """Common keys of the decentralized controllers of thesis Ch. 6.

    Each drive feeds back only its own section: the deviation of its zone's loadcell tension
    and of its web speed from their references, around the equilibrium input recomputed every
    tick from the current roll radii and inertias (6.20-6.37). Gains missing from the file are
    designed by LQ on the section model, with the deviations scaled by ``tension_scale`` [N],
    ``speed_scale`` [m/s] and ``torque_scale`` [N·m] (default: 1 % of the tension reference,
    1 % of the line speed (at least 0.01 m/s), 10 % of the torque limit).
    ``friction_estimate`` [N·m·s] is the controller's model of the bearing friction (default:
    the roller's true value). ``tension_feedback = "observer"``: ``webline.sim.drives.observer``.
    """

    tension_scale: Force | None = None
    speed_scale: Annotated[float, si("speed", ">0")] | None = None
    torque_scale: Torque | None = None
    friction_estimate: Damping | None = None
    tension_feedback: Literal["loadcell", "observer"] = "loadcell"
    observer_bandwidth: AngularFrequency = 30.0
    observer_ea: Force | None = None  #: the observer's EA [N] (default: the web's)


class StateFeedbackSpec(_DecentralizedSpec):
    """Decentralized state feedback (thesis 6.39-6.42): u = u_eq - K x - f(V).

    ``tension_gain`` [N·m/N] and ``speed_gain`` [N·m·s/m] act on the section deviations.
    """

    type: Literal["state_feedback"]
    tension_gain: Signed | None = None
    speed_gain: Signed | None = None


class AdaptiveSpec(_DecentralizedSpec):
    """Decentralized adaptive control (thesis 6.62-6.77, re-derived, docs/errata.md E-6.8).

    The state feedback of ``state_feedback`` with each section's unknown, its bearing
    friction, estimated on line from ``friction_estimate`` (the initial guess).
    ``adaptation_gain`` γ [rad/s] is the corner frequency of the integral-like action the
    estimate adds to the speed feedback; ``leakage`` σ [-] pulls the estimate towards the
    initial guess (σ-modification); projection keeps it in [0, ``parameter_bound`` x the
    friction whose torque at the initial speed is the torque scale].
    """

    type: Literal["adaptive"]
    tension_gain: Signed | None = None
    speed_gain: Signed | None = None
    adaptation_gain: AngularFrequency = 20.0
    leakage: Gain = 0.0
    parameter_bound: Annotated[float, si("dimensionless", ">0")] = 10.0


class MRACSpec(_DecentralizedSpec):
    """Decentralized MRAC of Sec. 6.3 (``webline.sim.drives.mrac``; docs/line-file.md, E-6.14)."""

    type: Literal["mrac"]
    tension_gain: Signed | None = None
    speed_gain: Signed | None = None
    adaptation_gain: AngularFrequency = 1.0
    leakage: Gain = 0.01
    parameter_bound: Annotated[float, si("dimensionless", ">0")] = 2.0


_TARGET = r"^[^:]+:[A-Za-z_][\w.]*$"  # "module:attribute"


class PythonControllerSpec(Strict):
    """A user's controller in Python (docs/controllers.md): ``object`` is
    ``"module:attribute"`` (an importable module, or a ``.py`` file relative to the line
    file) naming a class or factory, called with ``parameters`` as keyword arguments, or a
    controller object itself (then ``parameters`` must be empty). Or ``function``: a
    control law numba compiles into the loop (``sim.compiled_control``), given ``params``
    and ``states`` values of memory, ``checked`` for its checked mode. The code runs only
    with the user's consent (``spec.code_consent``, docs/security.md)."""

    type: Literal["python"]
    object: Annotated[str, Field(pattern=_TARGET)] | None = None
    parameters: dict[str, Any] = Field(default_factory=dict)
    function: Annotated[str, Field(pattern=_TARGET)] | None = None
    params: list[float] = Field(default_factory=list)
    states: Annotated[int, Field(ge=0, le=1_000_000)] = 0
    #: a ``function``'s checked mode: bounds and NaN checks, slower (docs/controllers.md)
    checked: bool = False

    @model_validator(mode="after")
    def _object_or_function(self) -> PythonControllerSpec:
        if (self.object is None) == (self.function is None):
            raise ValueError("give either object (a controller) or function (a compiled "
                             "law), not both or neither")
        if self.object is not None and (self.params or self.states):
            raise ValueError("params and states go with function; an object takes "
                             "parameters")
        if self.function is not None and self.parameters:
            raise ValueError("parameters go with object; a function takes params and states")
        if self.object is not None and self.checked:
            raise ValueError("checked goes with function (a compiled law's checked mode)")
        return self


def _controller_tag(value: object) -> str:
    """The controller family; a table without ``type`` is the industrial cascaded PI."""
    if isinstance(value, dict):
        return str(value.get("type", "cascaded_pi"))
    return str(getattr(value, "type", "cascaded_pi"))


ControllerSpec = Annotated[
    Annotated[CascadedPISpec, Tag("cascaded_pi")]
    | Annotated[StateFeedbackSpec, Tag("state_feedback")]
    | Annotated[AdaptiveSpec, Tag("adaptive")]
    | Annotated[MRACSpec, Tag("mrac")]
    | Annotated[PythonControllerSpec, Tag("python")],
    Discriminator(_controller_tag),
]
