"""Checks of a branched line's centre-winder keys (docs/branching.md, "Centre winders and
flying splices"): a roll's ``winder`` table, its ``inertia`` as totals and the flying
splices of its rolls, each
problem one ``LineFileError`` line naming the key."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from types import SimpleNamespace
from typing import Any, NoReturn

from webline.spec.branched.schema import BranchedLineSpec
from webline.spec.friction import check_friction_table
from webline.spec.roll_inertia import check_roll_inertia
from webline.spec.schema import RewindSpec, UnwindSpec
from webline.spec.splice import FlyingSplice

Fail = Callable[[str, str], NoReturn]


def check_winders(spec: BranchedLineSpec, fail: Fail) -> None:
    """A roll's ``winder``: not on a differential shaft (its drive runs in speed control,
    without a tension loop or a torque to compensate); its friction table well formed."""
    for i, roller in enumerate(spec.rollers):
        winder = getattr(roller, "winder", None)
        if winder is None:
            continue
        key = f"rollers[{i}].winder"
        if getattr(roller, "shaft", None) is not None:
            fail(key, "a differential shaft runs in speed control (its lanes' tension is "
                 "slip_torque / radius): no centre-winder torque functions on it")
        check_friction_table(winder.friction_table, f"{key}.friction_table", fail)


def check_splices(spec: BranchedLineSpec, fail: Fail) -> None:
    """The flying splices of the line's disturbances, of every scenario's and every
    scenario's ``splice``: of an unwind or a rewind (not a differential shaft), onto a roll
    larger than its core, one per roll and time."""
    lists: list[tuple[str, Sequence[Any], bool]] = [
        ("disturbances", spec.disturbances, True)]
    for name, scenario in spec.scenarios.items():
        if scenario.disturbances is not None:
            lists.append((f"scenarios.{name}.disturbances", scenario.disturbances, True))
        if scenario.splice is not None:
            lists.append((f"scenarios.{name}.splice", [scenario.splice], False))
    rollers = {r.name: r for r in spec.rollers}
    for key, items, indexed in lists:
        seen: set[tuple[str, float]] = set()
        for j, item in enumerate(items):
            if not isinstance(item, FlyingSplice):
                continue
            here = f"{key}[{j}]" if indexed else key
            roll = rollers.get(item.roll)
            if not isinstance(roll, UnwindSpec | RewindSpec):
                rolls = ", ".join(repr(r.name) for r in spec.rollers
                                  if isinstance(r, UnwindSpec | RewindSpec))
                fail(f"{here}.roll", f"must name an unwind or a rewind of this line ({rolls})"
                     f", got {item.roll!r}")
            if getattr(roll, "shaft", None) is not None:
                fail(f"{here}.roll", f"{item.roll!r} is a differential shaft: each lane winds "
                     "on its own slipping clutch core, whose speed and slip at the transfer "
                     "the splice's keys do not give (not modelled)")
            if (item.roll, item.at) in seen:
                fail(f"{here}.at", f"{item.roll!r} is already spliced at {item.at:g} s")
            seen.add((item.roll, item.at))
            if item.new_diameter <= 2.0 * roll.core_radius:
                fail(f"{here}.new_diameter", f"must exceed the core's diameter "
                     f"{2.0 * roll.core_radius:g} m, got {item.new_diameter:g} m")


def wound_web(widths_densities: Sequence[tuple[float, float]]) -> SimpleNamespace:
    """The web a roll's inertia totals describe (J1), as ``spec.roll_inertia`` takes it: the
    webs wound on the roll side by side (a shaft's lanes; (width [m], density [kg/m³]) of
    each), ``width`` their widths' sum, ``density`` their densities weighted by width."""
    width = sum(w for w, _ in widths_densities)
    return SimpleNamespace(width=width, density=sum(w * rho for w, rho in widths_densities)
                           / width)


def check_roll_inertias(spec: BranchedLineSpec, wound: dict[int, SimpleNamespace],
                        fail: Fail) -> None:
    """A roll's ``inertia`` given as totals (J1, ``spec.roll_inertia``): checked against the
    web wound on it (``wound``: node -> ``wound_web``); not on a differential shaft (each
    lane turns on its own core there)."""
    for i, roller in enumerate(spec.rollers):
        if not isinstance(roller, UnwindSpec | RewindSpec) or isinstance(roller.inertia, float):
            continue
        key = f"rollers[{i}].inertia"
        if getattr(roller, "shaft", None) is not None:
            fail(key, "totals describe a roll turning with its shaft; a differential shaft's "
                 "lanes turn on their own cores (give the shaft's inertia as a number)")
        check_roll_inertia(roller, wound[i], key, fail)
