"""The user-controller protocol shared by the chain's runs (``sim.user_control``) and a
branched line's (``sim.branches.user``): what a controller is, what it is told about each
drive it commands, and the one-line error of one that fails (docs/controllers.md)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any, Protocol, runtime_checkable

import numpy as np

from webline.control.pi import PIGains
from webline.errors import ArgumentError, WeblineError

#: what a user's code may raise that ends the run as its failure (``ControllerError``): every
#: exception, and ``SystemExit`` (``sys.exit`` in a controller) and ``GeneratorExit``; a
#: debugger's ``BdbQuit`` is an ``Exception``. Only ``KeyboardInterrupt`` stops a run as Ctrl-C.
ENDINGS: tuple[type[BaseException], ...] = (Exception, SystemExit, GeneratorExit)

MEASURED = ("speed", "tension", "radius", "inertia")  # in ``user_loop.U_*`` order
REFERENCES = ("speed_reference", "tension_reference")


@runtime_checkable
class Controller(Protocol):
    """What ``simulate(..., controller=...)`` accepts (docs/controllers.md): ``reset(context)``
    once (a ``sim.user_control.ControllerContext``, or its branched line's), then
    ``__call__(t, measurements, references)`` every tick."""

    def reset(self, context: Any) -> None: ...

    def __call__(self, t: float, measurements: np.ndarray,
                 references: np.ndarray) -> Any: ...


class NamedReadings:
    """``index`` by name over a context's ``measurement_names`` and ``reference_names``
    (the chain's and a branched line's controller contexts)."""

    measurement_names: tuple[str, ...]
    reference_names: tuple[str, ...]

    def index(self, name: str) -> int:
        """Position of measurement or reference ``name`` (e.g. ``"rewind.tension"``)."""
        for names in (self.measurement_names, self.reference_names):
            if name in names:
                return names.index(name)
        raise KeyError(f"no measurement or reference {name!r}; there are "
                       f"{', '.join(self.measurement_names + self.reference_names)}")


@dataclass(frozen=True)
class DriveInfo:
    """One drive a user controller commands.

    ``node``: its roller's index in the line; ``roll``: True for the unwind or rewind, whose
    radius and inertia change as the roll runs; ``role``: "master" (speed) or "tension";
    ``tension_sign`` σ: +1 if speeding the drive up raises its zone's tension, -1 if it
    lowers it (the drive upstream of its zone), 0 for the master; ``torque_limit`` [N·m]
    (the command is clipped there); ``ratio`` motor / roller speed; ``radius`` [m] and
    ``inertia`` [kg·m²] at the roller at t = 0; ``builtin_pi``: the cascaded-PI gains
    webline would run this drive with (SI, ``control.pi``; a dancer zone's tension gains act
    on the dancer's position error, (m/s)/m), a place to start; ``gain_norm`` [kg·m]: the
    inertia / (ratio x radius) those gains were tuned at (the built-in PI scales its speed
    gains by the current value over this one); ``equilibrium_command`` [N·m]: the command
    that holds the drive at the operating point, where the run starts (the motor torque
    there, less what the drive's own compensation adds); ``equilibrium_trim`` [m/s]: how
    much faster than its speed reference the drive runs there (the draw its idle rollers'
    friction takes; the built-in PI's tension integrator starts at it times σ).
    """

    name: str
    node: int
    roll: bool
    role: str
    tension_sign: float
    torque_limit: float
    ratio: float
    radius: float
    inertia: float
    builtin_pi: PIGains
    gain_norm: float
    equilibrium_command: float
    equilibrium_trim: float


@dataclass(frozen=True)
class Group:
    """One controller object and the drives (indices into ``line.drives``) it commands."""

    name: str
    controller: Controller
    drives: tuple[int, ...]


def argument_groups(controller: object | Mapping[str, object] | None, names: Sequence[str]
                    ) -> list[Group]:
    """The groups of a run's ``controller`` argument over drives ``names`` (drive order):
    none, one object for every drive (group "line"), or a dict drive name -> object (a group
    each); ``ArgumentError`` for an unknown drive name or an object without the protocol."""
    if controller is None:
        return []
    if not isinstance(controller, Mapping):
        return [Group("line", checked_controller(controller, "controller"),
                      tuple(range(len(names))))]
    groups = []
    for name, obj in controller.items():
        if name not in names:
            raise ArgumentError(f"controller: no drive {name!r}; the drives are "
                                f"{', '.join(names)}")
        groups.append(Group(name, checked_controller(obj, f"controller[{name!r}]"),
                            (list(names).index(name),)))
    return groups


def checked_controller(obj: object, what: str) -> Controller:
    """``obj`` if it has the protocol, else ``ArgumentError`` naming ``what``."""
    if not isinstance(obj, Controller):
        raise ArgumentError(f"{what}: {type(obj).__name__} is not a controller: it needs "
                            f"reset(context) and __call__(t, measurements, references)")
    return obj


def shape_of(value: object) -> str:
    """What a controller returned, for an error: "shape (2,)", "a str"."""
    shape = np.shape(value) if isinstance(value, np.ndarray | list | tuple) else None
    return f"shape {shape}" if shape is not None else f"a {type(value).__name__}"


def controller_error(group: Group, tick: int, t: float, exc: BaseException | None,
                     what: str = "", where: str = "") -> str:
    """One sentence: which controller failed, how (in ``where``, e.g. "reset(context)"), at
    which tick and time [s]; its drives named."""
    if exc is not None:
        what = f"raised {type(exc).__name__}: {exc}".rstrip(": ")
        if where:
            what += f" in {where}"
    kind = getattr(group.controller, "kind", type(group.controller).__name__)
    return f"controller {group.name!r} ({kind}) {what} at tick {tick} (t = {t:.6g} s)"


def reset_all(groups: Sequence[Group], context: Any) -> tuple[Group, str] | None:
    """Call each group's ``reset(context(group))``; the first that fails ends it: (its
    group, the one-line error naming it, tick 0) — webline's own errors (a compiled law's
    bad parameters: bad input) pass through as they are."""
    for g in groups:
        try:
            g.controller.reset(context(g))
        except WeblineError:
            raise
        except ENDINGS as exc:  # the user's code: it ends the run, named
            return g, controller_error(g, 0, 0.0, exc, where="reset(context)")
    return None
