"""The contenders of a benchmark: the built-in controller families, each on every drive, and
the user's controllers (docs/controllers.md), given as objects, classes or factories, or as
``"my_ctrl.py:MyController"`` / ``"module:Name"``.

A built-in family that a line does not allow is "n/a" on that line with the line's own reason;
a user's controller commands every drive.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

from webline.control.select import Family, with_controller
from webline.errors import ArgumentError, LineFileError
from webline.line import Line
from webline.sim.user_control import Controller


class NotApplicable(Exception):
    """A contender cannot run on a line; the message says why."""


@dataclass(frozen=True)
class Contender:
    """A ``name`` in the tables; a built-in ``family`` with ``options`` (the family's
    line-file keys) and ``observer`` (tension from a section observer where a zone allows),
    or a user's controller ``make`` (a fresh or reset object for each run)."""

    name: str
    family: Family | None = None
    options: Mapping[str, object] = field(default_factory=dict)
    observer: bool = False
    make: Callable[[], Controller] | None = None

    @property
    def user(self) -> bool:
        return self.make is not None

    def setup(self, line: Line) -> tuple[Line, Controller | None]:
        """The line this contender runs and the controller object to pass to ``simulate``
        (None for a built-in family). Raises ``NotApplicable`` with the line's reason."""
        if self.make is not None:
            return line, self.make()
        assert self.family is not None
        if self.family == "cascaded_pi" and all(
                getattr(getattr(line.spec.rollers[i], "controller", None), "type",
                        "") == "cascaded_pi"
                for i in line.drives):
            return line, None  # the line file's own PI, with its bandwidths
        overrides = {}
        if self.observer:
            overrides = {line.node_name(i): {"tension_feedback": "observer"}
                         for i in line.drives if _observable(line, i)}
            if not overrides:
                raise NotApplicable("no drive controls a zone of one span, which the "
                                    "section observer needs")
        try:
            return with_controller(line, self.family, overrides=overrides,
                                   **self.options), None
        except LineFileError as exc:
            raise NotApplicable(" ".join(str(exc).split())) from None


def _observable(line: Line, node: int) -> bool:
    """Whether the section observer serves ``node``'s drive: one whose zone is one span."""
    zone = line.controlled_zone(node)
    return zone is not None and len(line.zones[zone].spans) == 1


#: the built-in families, each with its default design on every drive
BUILTIN: tuple[Contender, ...] = (
    Contender("cascaded PI", "cascaded_pi"),
    Contender("state feedback", "state_feedback"),
    Contender("observer", "state_feedback", observer=True),
    Contender("adaptive", "adaptive"),
    Contender("MRAC", "mrac"),
)

#: what each built-in contender is, for the report
BUILTIN_NOTES = {
    "cascaded PI": "the line file's cascaded PI (thesis Fig. 4.3) on every drive",
    "state feedback": "decentralized state feedback (6.39-6.42), webline's LQ design",
    "observer": "the state feedback with the tension of a section observer on every drive "
                "(roll or roller) whose zone is one span, the loadcell elsewhere",
    "adaptive": "decentralized adaptive control (6.62-6.77), default design",
    "MRAC": "decentralized MRAC (Sec. 6.3), default design",
}


def user_contenders(controllers: object) -> list[Contender]:
    """Contenders of ``controllers``: one controller (an object, a class or factory called
    with no arguments for each run, or a ``"file.py:Name"`` / ``"module:Name"`` text), a
    sequence of them, or a dict name -> one of them. ``ArgumentError`` (one line) for a name
    that cannot be imported or found, or an object without the protocol."""
    if controllers is None:
        return []
    if isinstance(controllers, Mapping):
        items = [(str(k), v) for k, v in controllers.items()]
    elif isinstance(controllers, str) or not isinstance(controllers, Sequence):
        items = [("", controllers)]
    else:
        items = [("", c) for c in controllers]
    out: list[Contender] = []
    names: set[str] = set()
    for given, target in items:
        default, make = _factory(target)
        name = given or default
        while name in names or name in BUILTIN_NOTES:
            name += "'"
        names.add(name)
        out.append(Contender(name, make=make))
    return out


def _factory(target: object) -> tuple[str, Callable[[], Controller]]:
    """(default name, a function that gives the controller for a run) of one ``target``."""
    text = target if isinstance(target, str) else None
    if text is not None:
        target = load_object(text)
    label: str = text if text is not None else str(
        getattr(target, "__name__", type(target).__name__))
    if isinstance(target, Controller) and not isinstance(target, type):
        obj = target
        return label if text else type(obj).__name__, lambda: obj  # reset() each run
    if not callable(target):
        raise ArgumentError(f"controller {label!r}: neither a controller (reset(context), "
                            f"__call__(t, measurements, references)) nor a class or factory")
    factory = target
    try:
        made = factory()
    except Exception as exc:  # the user's constructor
        raise ArgumentError(f"controller {label!r}: calling it with no arguments raised "
                            f"{type(exc).__name__}: {exc}") from None
    if not isinstance(made, Controller):
        raise ArgumentError(f"controller {label!r} gave a {type(made).__name__}, which lacks "
                            f"reset(context) and __call__(t, measurements, references)")
    name = text.rpartition(":")[2] if text else getattr(factory, "__name__", "controller")
    return name, lambda: factory()


def load_object(text: str) -> object:
    """The object ``"file.py:Name"`` (a path, relative to the working folder) or
    ``"module:Name"`` names. ``ArgumentError`` naming ``text`` and the problem."""
    module_name, sep, attribute = text.partition(":")
    if not sep or not module_name or not attribute:
        raise ArgumentError(f"--controller {text!r}: expected FILE.py:NAME or MODULE:NAME")
    try:
        module = _module(module_name)
    except Exception as exc:  # importing runs the user's module: any error is theirs
        raise ArgumentError(f"--controller {text!r}: cannot import {module_name!r}: "
                            f"{type(exc).__name__}: {exc}") from None
    target: object = module
    for part in attribute.split("."):
        if not hasattr(target, part):
            raise ArgumentError(f"--controller {text!r}: {module_name!r} has no "
                                f"{attribute!r}")
        target = getattr(target, part)
    return target


def _module(name: str) -> object:
    """The module ``name``, or the ``.py`` file it names (typed by the user on the command
    line: their own code, no consent needed; docs/security.md)."""
    if not name.endswith(".py"):
        return importlib.import_module(name)
    from webline.spec.code_consent import import_file

    if not Path(name).is_file():
        raise FileNotFoundError(f"no file {name}")
    return import_file(Path(name).resolve())
