"""Checks that need more than one key: topology, zones, physical consistency."""

from __future__ import annotations

import itertools
from collections.abc import Callable, Iterable
from typing import NoReturn

from webline.errors import LineFileError
from webline.spec.control_schema import AdaptiveSpec, MRACSpec, StateFeedbackSpec
from webline.spec.dancer import check_dancers
from webline.spec.friction import check_friction
from webline.spec.nip import check_nips
from webline.spec.roll_inertia import check_roll_inertia
from webline.spec.roll_stress import check_roll_stress
from webline.spec.schema import (
    DisturbanceSpec,
    DrivenSpec,
    EccentricRoller,
    IdleSpec,
    LineSpec,
    Profile,
    Ramp,
    RewindSpec,
    RollerDrag,
    SpeedRipple,
    Steps,
    Table,
    UnwindSpec,
    WebSpec,
    WoundInRipple,
)
from webline.spec.sensors import check_sensors
from webline.spec.splice import check_splices
from webline.spec.web_law import stretch_at
from webline.spec.web_law_checks import check_web_law, law_array, table_modulus
from webline.spec.winder import WebBreak, check_diameters, check_taper

Fail = Callable[[str, str], NoReturn]


def web_ea(web: WebSpec) -> float:
    """Axial stiffness E·A of the web [N]."""
    if web.ea is not None:
        return web.ea
    if web.modulus is None and web.stress_strain is not None:
        return table_modulus(web)  # a table law: its first segment
    assert web.modulus is not None
    return web.modulus * web.thickness * web.width


def profile_values(profile: Profile) -> list[float]:
    """Every value a reference profile takes at its breakpoints [SI]."""
    if isinstance(profile, float | int):
        return [float(profile)]
    if isinstance(profile, Ramp):
        return [profile.initial, profile.final]
    if isinstance(profile, Steps):
        return [profile.initial, *(s.value for s in profile.steps)]
    return list(profile.value)


def zones(spec: LineSpec) -> list[tuple[int, int]]:
    """Tension zones as (first node, last node) between consecutive driven nodes."""
    driven = [i for i, r in enumerate(spec.rollers) if not isinstance(r, IdleSpec)]
    return list(itertools.pairwise(driven))


def check_spec(spec: LineSpec, file: str) -> None:
    """Raise ``LineFileError`` for the first inconsistency in ``spec``."""

    def fail(key: str, problem: str) -> NoReturn:
        raise LineFileError(file, key, problem)

    web = spec.web
    if web.stress_strain is not None:
        check_web_law(web, fail)
    elif (web.modulus is None) == (web.ea is None):
        fail("web", "give exactly one of 'modulus' or 'ea'")
    ea = web_ea(web)
    law = law_array(web, ea)

    def strain_of(tension: float) -> float:  # the law's strain at a tension [-]
        return stretch_at(law, tension) / ea

    rollers = spec.rollers
    if not isinstance(rollers[0], UnwindSpec):
        fail("rollers[0].type", "the first roller must be the unwind roll")
    if not isinstance(rollers[-1], RewindSpec):
        fail(f"rollers[{len(rollers) - 1}].type", "the last roller must be the rewind roll")
    for i, roller in enumerate(rollers[1:-1], start=1):
        if isinstance(roller, UnwindSpec | RewindSpec):
            fail(f"rollers[{i}].type", f"'{roller.type}' may only be the first/last roller")
    _unique((r.name for r in rollers), "rollers", "name", fail)
    if len(spec.spans) != len(rollers) - 1:
        fail("spans",
             f"{len(rollers)} rollers need {len(rollers) - 1} spans, got {len(spec.spans)}")
    _unique((s.name for s in spec.spans if s.name), "spans", "name", fail)

    masters = [i for i, r in enumerate(rollers) if isinstance(r, DrivenSpec) and r.role == "master"]
    if len(masters) != 1:
        fail("rollers", f"exactly one driven roller must have role = 'master', got {len(masters)}")

    for i, roller in enumerate(rollers):
        if isinstance(roller, UnwindSpec | RewindSpec) and roller.core_radius >= roller.radius:
            fail(f"rollers[{i}].core_radius",
                 f"must be below the roll radius {roller.radius:g} m, got {roller.core_radius:g} m")
        if isinstance(roller, UnwindSpec | RewindSpec):
            check_roll_inertia(roller, web, f"rollers[{i}].inertia", fail)
        check_friction(roller, f"rollers[{i}]", fail)
        if isinstance(roller, RewindSpec) and roller.shaft is not None:
            fail(f"rollers[{i}].shaft", "a differential shaft holds lanes on one shaft: only "
                 "on a branched line ([[webs]], docs/branching.md)")
        contact = getattr(roller, "contact", None)
        if contact is not None and contact.type == "traction":
            if roller.wrap is None:  # type: ignore[union-attr]
                fail(f"rollers[{i}].wrap", "a traction contact needs the wrap angle")
            kinetic = contact.kinetic_friction
            if kinetic is not None and kinetic > contact.friction:
                fail(f"rollers[{i}].contact.kinetic_friction",
                     f"must not exceed the static friction {contact.friction:g}")
        check_open_loop(roller, f"rollers[{i}]", fail)
        drive = getattr(roller, "drive", None)
        if drive is not None and drive.transmission.type != "direct" and drive.motor_inertia <= 0:
            fail(f"rollers[{i}].drive.motor_inertia",
                 f"a {drive.transmission.type} transmission needs the motor's inertia (> 0)")
        if isinstance(roller, UnwindSpec) and strain_of(roller.wound_in_tension) >= 1.0:
            fail(f"rollers[{i}].wound_in_tension", f"must be below EA = {ea:g} N"
                 if law.size == 1 else "must be below the law's tension at strain 1")

    for z, (first, last) in enumerate(zones(spec)):
        loadcells = [k for k in range(first, last) if spec.spans[k].tension is not None]
        if len(loadcells) != 1:
            names = f"spans[{first}]" + (f"..spans[{last - 1}]" if last - 1 > first else "")
            fail(names, f"tension zone {z + 1} ({rollers[first].name} to {rollers[last].name}) "
                 f"needs exactly one span with a 'tension' reference, got {len(loadcells)}")
    check_dancers(rollers, spec.spans, zones(spec), fail)
    check_nips(rollers, fail)
    check_diameters(list(rollers), fail)
    check_taper(getattr(rollers[-1], "taper", None), f"rollers[{len(rollers) - 1}].taper", fail)
    check_roll_stress(rollers[-1], f"rollers[{len(rollers) - 1}].roll_stress", fail)
    for k, span in enumerate(spec.spans):
        _check_span_model(spec, k, fail)
        if span.tension is not None:
            for value in profile_values(span.tension):
                if strain_of(value) >= 1.0:
                    below = f"EA = {ea:g} N" if law.size == 1 else "the law's tension at strain 1"
                    fail(f"spans[{k}].tension", f"reference {value:g} N must be below "
                         f"{below} (the web would break, strain >= 100 %)")

    _check_disturbances(spec.disturbances, spec, "disturbances", fail)
    check_sensors(spec.sensors, [s.name or f"span{k + 1}" for k, s in enumerate(spec.spans)],
                  {s.name or f"span{k + 1}" for k, s in enumerate(spec.spans)
                   if s.tension is not None},
                  {r.name for r in rollers if not isinstance(r, IdleSpec)},
                  {r.name for r in rollers}, fail)
    for name, scenario in spec.scenarios.items():
        key = f"scenarios.{name}"
        if not 0 < len(name) <= 100:
            fail(f"scenarios.{name[:40]}", "a scenario's name has 1 to 100 characters")
        if scenario.disturbances is not None:
            _check_disturbances(scenario.disturbances, spec, f"{key}.disturbances", fail)
        span_names = {s.name or f"span{k + 1}" for k, s in enumerate(spec.spans)}
        if scenario.break_ is not None and scenario.break_.span not in span_names:
            fail(f"{key}.break.span", f"no span named {scenario.break_.span!r}")
        if scenario.splice is not None:  # the splice key, with any splice in its disturbances
            before = (scenario.disturbances if scenario.disturbances is not None
                      else spec.disturbances)
            check_splices([scenario.splice], spec.rollers, f"{key}.splice", fail,
                          indexed=False)
            if any(getattr(d, "type", "") == "flying_splice"
                   and (d.roll, d.at) == (scenario.splice.roll, scenario.splice.at)  # type: ignore[union-attr]
                   for d in before):
                fail(f"{key}.splice.at", f"{scenario.splice.roll!r} is already spliced at "
                     f"{scenario.splice.at:g} s in the disturbances")
        for attr, index in (("unwind_radius", 0), ("rewind_radius", len(rollers) - 1)):
            radius = getattr(scenario, attr)
            roll = rollers[index]
            assert isinstance(roll, UnwindSpec | RewindSpec)
            if radius is not None and radius <= roll.core_radius:
                fail(f"{key}.{attr}", f"must be above the core radius {roll.core_radius:g} m")
    _check_profiles(spec, fail)


def _check_span_model(spec: LineSpec, k: int, fail: Fail) -> None:
    """A Kelvin-Voigt span needs its retardation time; an elastic one has none; a roller
    the web may slip over reads the tensions on both sides, which webline takes as elastic
    (the slip model would otherwise need the tension rate it sets itself)."""
    span = spec.spans[k]
    if span.model == "kelvin-voigt" and span.retardation is None:
        fail(f"spans[{k}].retardation", "a kelvin-voigt span needs its retardation time "
             "(tau = viscosity / modulus, e.g. '5 ms')")
    if span.model == "elastic" and span.retardation is not None:
        fail(f"spans[{k}].retardation", "only a span with model = 'kelvin-voigt' has one")
    for i in (k, k + 1):
        contact = getattr(spec.rollers[i], "contact", None)
        if span.model != "elastic" and contact is not None and contact.type == "traction":
            fail(f"spans[{k}].model", f"a kelvin-voigt span next to a traction contact "
                 f"(rollers[{i}]) is not modelled; use an elastic span there")


def _check_profiles(spec: LineSpec, fail: Fail) -> None:
    profiles: list[tuple[str, Profile | None]] = [("speed", spec.speed)]
    profiles += [(f"spans[{k}].tension", s.tension) for k, s in enumerate(spec.spans)]
    profiles += [(f"scenarios.{n}.speed", s.speed) for n, s in spec.scenarios.items()]
    for key, profile in profiles:
        if isinstance(profile, Table):
            times = profile.time
            if len(times) != len(profile.value):
                fail(key, "'time' and 'value' must have the same length")
            if any(b < a for a, b in itertools.pairwise(times)):
                fail(f"{key}.time", "times must not decrease")
        if isinstance(profile, Steps):
            times = [s.time for s in profile.steps]
            if any(b < a for a, b in itertools.pairwise(times)):
                fail(f"{key}.steps", "step times must not decrease")


def _check_disturbances(items: list[DisturbanceSpec], spec: LineSpec, key: str,
                        fail: Fail) -> None:
    by_name = {r.name: r for r in spec.rollers}
    check_splices(items, spec.rollers, key, fail)
    for j, item in enumerate(items):
        here = f"{key}[{j}]"
        if isinstance(item, WebBreak) and item.span not in {
                spec.spans[k].name or f"span{k + 1}" for k in range(len(spec.spans))}:
            fail(f"{here}.span", f"no span named {item.span!r}")
        if isinstance(item, RollerDrag):
            roller = by_name.get(item.roller)
            if roller is None:
                fail(f"{here}.roller", f"no roller named {item.roller!r}")
            dragged = [d.roller for d in items[:j] if isinstance(d, RollerDrag)]
            braked = getattr(getattr(roller, "drive", None), "brake", None) is not None
            if item.roller in dragged or braked:
                fail(f"{here}.roller", f"{item.roller!r} already has a drag or brake torque")
        if isinstance(item, EccentricRoller | SpeedRipple):
            roller = by_name.get(item.roller)
            if roller is None:
                fail(f"{here}.roller", f"no roller named {item.roller!r}")
            elif isinstance(item, EccentricRoller):
                if isinstance(roller, UnwindSpec | RewindSpec):  # an out-of-round roll
                    if item.eccentricity >= roller.core_radius:
                        fail(f"{here}.eccentricity", f"must be below the roll's core radius "
                             f"{roller.core_radius:g} m (the roll is never smaller)")
                elif item.eccentricity >= roller.radius:
                    fail(f"{here}.eccentricity", "must be below the roller radius")
            elif isinstance(roller, IdleSpec):
                fail(f"{here}.roller", "a speed ripple needs a driven roller")
        elif isinstance(item, WoundInRipple) and item.roller not in (None, spec.rollers[0].name):
            fail(f"{here}.roller", f"the unwind of this line is {spec.rollers[0].name!r}")
        elif isinstance(item, WoundInRipple) and item.amplitude >= _wound_in(spec):
            fail(f"{here}.amplitude", "must be below the unwind's wound-in tension (a wound "
                 "web cannot be in compression)")


def _wound_in(spec: LineSpec) -> float:
    unwind = spec.rollers[0]
    return unwind.wound_in_tension if isinstance(unwind, UnwindSpec) else float("inf")


def _unique(names: Iterable[str], key: str, attr: str, fail: Fail) -> None:
    seen: set[str] = set()
    for i, name in enumerate(names):
        if name in seen:
            fail(f"{key}[{i}].{attr}", f"duplicate name {name!r}")
        seen.add(name)


def check_open_loop(roller: object, key: str, fail: Fail) -> None:
    """Open-loop tension control replaces the roll's controller, and its speed limiter (W7)
    runs on the cascaded PI's speed gains: under a decentralized controller those are 0 and
    the limiter would never hold a freed roll (as a branched line refuses it)."""
    winder, controller = getattr(roller, "winder", None), getattr(roller, "controller", None)
    if winder is not None and winder.mode == "open_loop" and isinstance(
            controller, StateFeedbackSpec | AdaptiveSpec | MRACSpec):
        fail(f"{key}.winder.mode", f"open_loop replaces the drive's {controller.type!r} "
             "controller (torque T_ref R / n, its speed limiter on the cascaded PI's speed "
             "gains): give controller cascaded_pi, or mode closed_loop to add the "
             "compensations to the state feedback")
