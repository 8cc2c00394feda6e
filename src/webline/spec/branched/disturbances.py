"""Checks of a branched line's disturbances (docs/branching.md, "Disturbances"): each
problem one ``LineFileError`` line naming the file, the key and the problem."""

from __future__ import annotations

from collections.abc import Callable, Mapping
from typing import NoReturn

from webline.spec.branched.breaks import check_break, check_breaks
from webline.spec.branched.schema import BranchedLineSpec
from webline.spec.disturbances import (
    DisturbanceSpec,
    EccentricRoller,
    MeasurementNoise,
    RollerDrag,
    SpeedRipple,
    WoundInRipple,
)
from webline.spec.schema import IdleSpec, RewindSpec, UnwindSpec
from webline.spec.splice import FlyingSplice
from webline.spec.winder import WebBreak

Fail = Callable[[str, str], NoReturn]

#: what a branched line runs (the rest is refused naming its key)
SUPPORTED = ("roller_drag, eccentric_roller, speed_ripple, wound_in_ripple, "
             "measurement_noise, flying_splice and web_break disturbances")


def check_disturbances(spec: BranchedLineSpec, fail: Fail) -> None:
    """The line's disturbances and every scenario's (which replace the line's)."""
    lists = [("disturbances", spec.disturbances)] + [
        (f"scenarios.{name}.disturbances", s.disturbances)
        for name, s in spec.scenarios.items() if s.disturbances is not None]
    for key, items in lists:
        _check_list(spec, key, items, fail)
    check_breaks(spec, fail)


def _check_list(spec: BranchedLineSpec, key: str, items: list[DisturbanceSpec],
                fail: Fail) -> None:
    by_name = {r.name: r for r in spec.rollers}
    unwinds = [r.name for r in spec.rollers if isinstance(r, UnwindSpec)]
    dragged: set[str] = set()
    eccentric: set[str] = set()
    noises = breaks = 0
    for j, item in enumerate(items):
        here = f"{key}[{j}]"
        if not isinstance(item, RollerDrag | SpeedRipple | WoundInRipple | MeasurementNoise
                          | EccentricRoller | FlyingSplice  # (splices: spec.branched.winder)
                          | WebBreak):
            fail(f"{here}.type", f"not yet supported on a branched line ({SUPPORTED})")
        if isinstance(item, WebBreak):
            breaks += 1
            if breaks > 1:
                fail(here, "one web_break per run")
            check_break(spec, item, here, fail)
        elif isinstance(item, EccentricRoller):
            _check_eccentric(item, here, by_name, eccentric, fail)
        elif isinstance(item, RollerDrag | SpeedRipple):
            roller = by_name.get(item.roller)
            if roller is None:
                fail(f"{here}.roller", f"no roller named {item.roller!r}")
            if isinstance(item, RollerDrag):
                braked = getattr(getattr(roller, "drive", None), "brake", None) is not None
                if item.roller in dragged or braked:  # (a drive's brake is a drag: as chains)
                    fail(f"{here}.roller", f"{item.roller!r} already has a drag or brake torque")
                dragged.add(item.roller)
            elif isinstance(roller, IdleSpec):
                fail(f"{here}.roller", "a speed ripple needs a driven roller")
        elif isinstance(item, WoundInRipple):
            name = item.roller
            if name is None and len(unwinds) > 1:
                fail(f"{here}.roller", f"the line has several unwinds ({', '.join(unwinds)}): "
                     "name the one whose wound-in tension ripples")
            name = unwinds[0] if name is None else name
            unwind = by_name.get(name)
            if not isinstance(unwind, UnwindSpec):
                fail(f"{here}.roller", f"{name!r} is no unwind of this line")
            if item.amplitude >= unwind.wound_in_tension:
                fail(f"{here}.amplitude", f"must be below {name!r}'s wound-in tension (a wound "
                     "web cannot be in compression)")
        elif isinstance(item, MeasurementNoise):
            noises += 1
            if noises > 1:
                fail(here, "one measurement_noise per line")


def _check_eccentric(item: EccentricRoller, here: str, by_name: Mapping[str, object],
                     eccentric: set[str], fail: Fail) -> None:
    roller = by_name.get(item.roller)
    if roller is None:
        fail(f"{here}.roller", f"no roller named {item.roller!r}")
    if item.roller in eccentric:
        fail(f"{here}.roller", f"{item.roller!r} is already eccentric")
    eccentric.add(item.roller)
    if isinstance(roller, RewindSpec) and roller.shaft is not None:
        fail(f"{here}.roller", "not yet supported on a differential shaft (its lanes turn on "
             "their own cores)")
    if isinstance(roller, UnwindSpec | RewindSpec):  # an out-of-round roll
        if item.eccentricity >= roller.core_radius:
            fail(f"{here}.eccentricity", f"must be below the roll's core radius "
                 f"{roller.core_radius:g} m (the roll is never smaller)")
    elif item.eccentricity >= getattr(roller, "radius", 0.0):
        fail(f"{here}.eccentricity", "must be below the roller radius")
