"""Checks of a branched line's controller families (docs/branching.md, "State feedback"):
the cascaded PI, decentralized state feedback, adaptive control and MRAC run on any drive
but a differential shaft's (speed control only), with their loadcells or a section observer
(``sim.branches.drives.observer``, which checks its zone), a centre winder's compensations added to
their torque (closed loop); a user's Python controller on any (docs/controllers.md, "On a
branched line")."""

from __future__ import annotations

from collections.abc import Callable
from typing import NoReturn

from webline.spec.check import check_open_loop
from webline.spec.schema import (
    AdaptiveSpec,
    CascadedPISpec,
    MRACSpec,
    PythonControllerSpec,
    RewindSpec,
    StateFeedbackSpec,
)

Fail = Callable[[str, str], NoReturn]
Unsupported = Callable[[str, Fail, str], NoReturn]

#: the families a branched line runs
FAMILIES = "cascaded_pi, state_feedback, adaptive, mrac and python controllers"


def check_controller(key: str, roller: object, fail: Fail, unsupported: Unsupported) -> None:
    """One line naming ``key``'s controller key where roller's controller is not run on a
    branched line (``unsupported`` words it as the other stage-1 refusals)."""
    controller = getattr(roller, "controller", None)
    if controller is None or isinstance(controller, CascadedPISpec):
        return
    if isinstance(controller, PythonControllerSpec):  # (its object is made when it runs)
        winder = getattr(roller, "winder", None)
        if winder is not None and winder.mode == "open_loop":
            fail(f"{key}.winder.mode", "open-loop tension control takes no command from a "
                 "python controller: use mode = 'closed_loop' or another controller")
        return
    if not isinstance(controller, StateFeedbackSpec | AdaptiveSpec | MRACSpec):
        unsupported(f"{key}.controller.type", fail, FAMILIES)
    check_open_loop(roller, key, fail)  # (as on a chain)
    if isinstance(roller, RewindSpec) and roller.shaft is not None:
        fail(f"{key}.controller.type", f"{controller.type!r} needs a tension loop; a "
             "differential shaft runs in speed control (its lanes' tension is slip_torque / "
             "radius): use cascaded_pi")


def python_drives(spec: object) -> list[str]:
    """The rollers of a branched line's ``spec`` whose controller is a user's Python one:
    they have no linear model in webline (docs/controllers.md)."""
    return [r.name for r in getattr(spec, "rollers", ())
            if isinstance(getattr(r, "controller", None), PythonControllerSpec)]
