"""Checks of a branched line's drive trains (compliant transmissions, brakes): the chain's
rules (``spec.check``, ``spec.splice``) with a branched line's keys."""

from __future__ import annotations

from collections.abc import Callable
from typing import NoReturn

from webline.spec.branched.schema import BranchedLineSpec
from webline.spec.schema import DriveSpec
from webline.spec.splice import FlyingSplice

Fail = Callable[[str, str], NoReturn]


def check_drive_train(spec: BranchedLineSpec, key: str, name: str, drive: DriveSpec,
                      fail: Fail) -> None:
    """A compliant transmission needs the motor's inertia (its speed is a state) and cannot
    take a roll change or a flying splice (its motor speed and twist would have to jump with
    the roll). Every controller family runs on it (measuring the side ``feedback`` names)."""
    kind = drive.transmission.type
    if kind == "direct":
        return
    if drive.motor_inertia <= 0.0:
        fail(f"{key}.drive.motor_inertia", f"a {kind} transmission needs the motor's inertia "
             "(> 0)")
    splices: list[tuple[str, object]] = [(f"disturbances[{j}]", item)
                                         for j, item in enumerate(spec.disturbances)]
    for scenario_name, scenario in spec.scenarios.items():
        here = f"scenarios.{scenario_name}"
        change = scenario.roll_change
        if change is not None and change.roller == name:
            fail(f"{here}.roll_change.roller", f"{name!r} has a {kind} transmission; a roll "
                 "change needs a direct drive on the roll")
        splices += [(f"{here}.disturbances[{j}]", item)
                    for j, item in enumerate(scenario.disturbances or [])]
        splices += [(f"{here}.splice", scenario.splice)] if scenario.splice is not None else []
    for where, item in splices:
        if isinstance(item, FlyingSplice) and item.roll == name:
            fail(f"{where}.roll", f"{name!r} has a {kind} transmission; a flying splice needs "
                 "a direct drive on the roll")
