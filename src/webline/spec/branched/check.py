"""Checks of a branched line's topology and of what stage 1 of branched lines supports.

Each problem is one ``LineFileError`` line naming the file, the key and the problem
(docs/branching.md, docs/line-file.md "webs").
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import NoReturn

from webline.errors import LineFileError
from webline.spec.branched.controllers import check_controller
from webline.spec.branched.disturbances import check_disturbances
from webline.spec.branched.drive_train import check_drive_train
from webline.spec.branched.schema import BranchedLineSpec, WebPathSpec
from webline.spec.branched.traction import check_traction
from webline.spec.branched.values import check_roll_radii
from webline.spec.branched.web_law import check_web_laws
from webline.spec.branched.winder import check_splices, check_winders
from webline.spec.dancer import DancerCarriage
from webline.spec.roll_stress import check_roll_stress
from webline.spec.schema import (
    DrivenSpec,
    IdleSpec,
    RewindSpec,
    RollerSpec,
    UnwindSpec,
)
from webline.spec.sensors import check_sensors
from webline.spec.winder import check_taper

Fail = Callable[[str, str], NoReturn]

STAGE = "stage 1: {}"
_ROLLER_FEATURES = "unwind, rewind, driven and idle rollers with a direct drive and cascaded PI"


def unsupported(key: str, fail: Fail, what: str = _ROLLER_FEATURES) -> NoReturn:
    fail(key, f"not yet supported on a branched line ({STAGE.format(what)})")


def kind_of(web: WebPathSpec) -> str:
    """'laminate', 'lane' or 'web' (a raw web from an unwind)."""
    return "laminate" if web.layers is not None else "lane" if web.slit_from else "web"


def check_branched(spec: BranchedLineSpec, file: str) -> None:
    """Raise ``LineFileError`` for the first problem of ``spec``'s topology or features."""

    def fail(key: str, problem: str) -> NoReturn:
        raise LineFileError(file, key, problem)

    _check_features(spec, fail)
    rollers = {r.name: (k, r) for k, r in enumerate(spec.rollers)}
    if len(rollers) != len(spec.rollers):
        fail("rollers", "roller names must be unique")
    webs = {w.name: w for w in spec.webs}
    if len(webs) != len(spec.webs):
        fail("webs", "web names must be unique")
    materials = [("web", spec.web)] + [(f"webs[{w}].web", web.web)
                                       for w, web in enumerate(spec.webs)]
    for key, material in materials:  # as a single-path line's [web]: E or EA, never both
        if material is not None and material.stress_strain is None and (
                material.modulus is None) == (material.ea is None):  # (a law: its checks)
            fail(key, "give exactly one of 'modulus' or 'ea'")
    masters = [r.name for r in spec.rollers if isinstance(r, DrivenSpec) and r.role == "master"]
    if len(masters) != 1:
        fail("rollers", f"a line needs exactly one master roller, found {len(masters)}")
    for w, web in enumerate(spec.webs):
        _check_web(spec, w, web, webs, rollers, fail)
    _check_rollers_once(spec, fail)
    _check_tree(spec, fail)
    check_disturbances(spec, fail)
    check_winders(spec, fail)
    check_splices(spec, fail)
    check_traction(spec, fail)  # traction rollers, nips, measured friction
    check_roll_radii(spec, fail)  # scenarios' unwind_radius / rewind_radius


def _check_features(spec: BranchedLineSpec, fail: Fail) -> None:
    _check_sensors(spec, fail)
    for i, roller in enumerate(spec.rollers):
        key = f"rollers[{i}]"
        dancer = getattr(roller, "dancer", None)
        if dancer is not None:
            _check_dancer(dancer, f"{key}.dancer", fail)
        _check_diameter(spec, i, roller, fail)
        if isinstance(roller, RewindSpec):
            check_taper(roller.taper, f"{key}.taper", fail)
            check_roll_stress(roller, f"{key}.roll_stress", fail)
            if roller.taper is not None and roller.shaft is not None:
                fail(f"{key}.taper", "a differential shaft has no tension loop to taper (its "
                     "lanes' tension is slip_torque / radius)")
        drive = getattr(roller, "drive", None)
        if drive is not None:
            check_drive_train(spec, key, roller.name, drive, fail)
        check_controller(key, roller, fail, unsupported)
    check_web_laws(spec, fail)
    for name, scenario in spec.scenarios.items():
        change = scenario.roll_change
        if change is not None and not isinstance(
                next((r for r in spec.rollers if r.name == change.roller), None), UnwindSpec):
            fail(f"scenarios.{name}.roll_change.roller",
                 f"{change.roller!r} is no unwind roller of this line")


def _check_sensors(spec: BranchedLineSpec, fail: Fail) -> None:
    """Sensors on a branched line (docs/branching.md, "Sensors"): the chain's checks, by the
    spans' names (``name`` or ``WEB[k]``). Their delays in controller samples are checked
    with the sample rate, in the plan (``sim.branches.sensors``), as the chain's."""
    spans = {(s.name or f"{web.name}[{k}]"): s.tension is not None
             for web in spec.webs for k, s in enumerate(web.spans)}
    driven = {r.name for r in spec.rollers if not isinstance(r, IdleSpec)}
    check_sensors(spec.sensors, list(spans), {n for n, ref in spans.items() if ref}, driven,
                  {r.name for r in spec.rollers}, fail)


def _check_dancer(carriage: DancerCarriage, key: str, fail: Fail) -> None:
    """A dancer on a branched line (docs/branching.md, "Dancers"), the chain's checks: a
    tension sensor on a spring, a straight angle below 90 deg, a pivoting arm with both its
    keys."""
    if carriage.use == "tension" and carriage.stiffness == 0.0:
        fail(f"{key}.stiffness", "a dancer as tension sensor needs a spring (stiffness > 0): "
             "without one it reads load / (g_in + g_out) whatever the tension")
    if carriage.position > carriage.travel:
        fail(f"{key}.position", f"must lie within the travel {carriage.travel:g} m")
    for name in ("angle_in", "angle_out"):
        if getattr(carriage, name) >= 0.5 * math.pi:
            fail(f"{key}.{name}", "a span at 90 deg or more to the travel does not pull the "
                 "carriage back (must be below 90 deg)")
    if (carriage.arm_length is None) != (carriage.arm_inertia is None):
        fail(f"{key}.arm_inertia", "a pivoting arm needs both arm_length and arm_inertia")


def _check_diameter(spec: BranchedLineSpec, i: int, roller: RollerSpec, fail: Fail) -> None:
    """A roll's diameter calculator: its line-speed source is the master, the reference or
    another roller that is no roll; not on a differential shaft."""
    diameter = getattr(roller, "diameter", None)
    if diameter is None:
        return
    key = f"rollers[{i}].diameter"
    if getattr(roller, "shaft", None) is not None:
        fail(key, "a differential shaft has no speed-to-radius loop to calculate for")
    source = next((r for r in spec.rollers if r.name == diameter.line_speed), None)
    if diameter.line_speed not in ("master", "reference") and (
            source is None or source is roller or isinstance(source, UnwindSpec | RewindSpec)):
        fail(f"{key}.line_speed", "must be 'master', 'reference' or the name of another "
             f"roller that is no roll, got {diameter.line_speed!r}")


def _check_web(spec: BranchedLineSpec, w: int, web: WebPathSpec, webs: dict[str, WebPathSpec],
               rollers: dict[str, tuple[int, RollerSpec]], fail: Fail) -> None:
    key = f"webs[{w}]"
    kind = kind_of(web)
    if web.layers is not None and web.slit_from is not None:
        fail(f"{key}.slit_from", "a web is a laminate (layers) or a lane (slit_from), not both")
    if kind != "web" and web.web is not None:
        fail(f"{key}.web", f"a {kind} takes its material from its "
             f"{'layers' if kind == 'laminate' else 'base web'}; give no 'web'")
    if kind == "web" and web.web is None and spec.web is None:
        fail(f"{key}.web", "required key is missing (the line gives no default [web])")
    if kind != "lane":
        for name in ("width", "thickness"):
            if getattr(web, name) is not None:
                fail(f"{key}.{name}", "only a lane (slit_from) gives its own width or thickness")
    if len(web.spans) != len(web.path) - 1:
        fail(f"{key}.spans", f"a path of {len(web.path)} rollers has {len(web.path) - 1} spans, "
             f"got {len(web.spans)}")
    for p, name in enumerate(web.path):
        if name not in rollers:
            fail(f"{key}.path[{p}]", f"no roller named {name!r}")
    if len(set(web.path)) != len(web.path):
        fail(f"{key}.path", "a roller appears twice in one path")
    first = rollers[web.path[0]][1]
    if kind == "laminate":
        assert web.layers is not None
        if len(set(web.layers)) < 2 or len(set(web.layers)) < len(web.layers):
            fail(f"{key}.layers", "a laminate has at least two layers, each named once")
        for layer in web.layers:
            if layer not in webs or layer == web.name:
                fail(f"{key}.layers", f"no other web named {layer!r}")
            if webs[layer].path[-1] != web.path[0]:
                fail(f"{key}.path[0]", f"a laminate starts at the roller where its layers end: "
                     f"layer {layer!r} ends at {webs[layer].path[-1]!r}")
    elif kind == "lane":
        base = web.slit_from
        if base not in webs or base == web.name:
            fail(f"{key}.slit_from", f"no other web named {base!r}")
        if webs[base].path[-1] != web.path[0]:
            fail(f"{key}.path[0]", f"a lane starts at the slitter, where web {base!r} ends "
                 f"({webs[base].path[-1]!r})")
        if web.width is None:
            fail(f"{key}.width", "required key is missing (a lane's share of its base web)")
    elif not isinstance(first, UnwindSpec):
        fail(f"{key}.path[0]", f"a web starts at an unwind roller; {first.name!r} is "
             f"{first.type}")
    if kind != "web" and not isinstance(first, DrivenSpec | IdleSpec):
        fail(f"{key}.path[0]", f"a junction is a driven or idle roller; {first.name!r} is "
             f"{first.type}")
    for p, name in enumerate(web.path[1:-1], start=1):
        if isinstance(rollers[name][1], UnwindSpec | RewindSpec):
            fail(f"{key}.path[{p}]", f"a roll ({name!r}) can only start or end a path")
    last = rollers[web.path[-1]][1]
    consumers = [v for v in spec.webs if v.path[0] == web.path[-1]  # (or its laminate or
                 or web.name in (v.layers or []) or v.slit_from == web.name]  # lanes: say so)
    if isinstance(last, UnwindSpec):
        fail(f"{key}.path[-1]", "a path ends at a rewind or a junction, not at an unwind")
    if not isinstance(last, RewindSpec) and not consumers:
        fail(f"{key}.path[-1]", f"{last.name!r} is no rewind and no web starts there: the web "
             "would end in the air")
    if not isinstance(last, RewindSpec) and not any(
            web.name in (v.layers or []) or v.slit_from == web.name for v in consumers):
        fail(f"{key}.path[-1]", f"web {web.name!r} ends at junction {last.name!r} but is "
             "neither a layer of the laminate nor the base of the lanes that start there")
    starting = [v for v in spec.webs if v.path[0] == web.path[0]]
    if isinstance(first, UnwindSpec) and len(starting) > 1:
        fail(f"{key}.path[0]", f"several webs start at unwind {first.name!r}: an unwind "
             "unwinds one web")
    if kind != "web" and (len({kind_of(v) for v in starting}) > 1 or (
            kind == "laminate" and len(starting) > 1)):
        fail(f"{key}.path[0]", f"junction {first.name!r} starts several kinds of web: a "
             "junction is one lamination nip or one slitter")
    if isinstance(last, RewindSpec) and kind != "lane" and sum(
            v.path[-1] == last.name for v in spec.webs) > 1:
        fail(f"{key}.path[-1]", f"several webs end on rewind {last.name!r}: only lanes may "
             "share a shaft")
    lanes = [v for v in spec.webs if v.slit_from == web.name]
    if lanes:
        width = _width(spec, web, webs)
        total = sum(v.width or 0.0 for v in lanes)
        if total > width * (1 + 1e-12):
            fail(f"{key}", f"its lanes are {total * 1e3:.6g} mm wide together, wider than the "
                 f"web ({width * 1e3:.6g} mm)")


def _width(spec: BranchedLineSpec, web: WebPathSpec, webs: dict[str, WebPathSpec]) -> float:
    """Width [m] of a web (a laminate: its narrowest layer)."""
    if web.layers is not None:
        return min(_width(spec, webs[n], webs) for n in web.layers)
    if web.slit_from is not None:
        assert web.width is not None
        return web.width
    material = web.web or spec.web
    assert material is not None
    return material.width


def _check_rollers_once(spec: BranchedLineSpec, fail: Fail) -> None:
    """Every roller on a path; an inner roller on exactly one; a junction where paths meet."""
    seen: dict[str, int] = {}
    for web in spec.webs:
        for name in web.path:
            seen[name] = seen.get(name, 0) + 1
    ends = {w.path[-1] for w in spec.webs} | {w.path[0] for w in spec.webs}
    for i, roller in enumerate(spec.rollers):
        if roller.name not in seen:
            fail(f"rollers[{i}]", f"roller {roller.name!r} is on no web's path")
        if seen[roller.name] > 1 and roller.name not in ends:
            fail(f"rollers[{i}]", f"roller {roller.name!r} is inside several paths; only a "
                 "junction (a path's end and another's start) or a shared rewind may be")
    for w, web in enumerate(spec.webs):
        for p, name in enumerate(web.path[1:-1], start=1):
            if name in ends:
                fail(f"webs[{w}].path[{p}]", f"{name!r} starts or ends another path: a "
                     "junction must end this path too")


def _check_tree(spec: BranchedLineSpec, fail: Fail) -> None:
    """Webs joined by laminations and slits form one connected tree."""
    edges = [(w.name, layer) for w in spec.webs for layer in (w.layers or [])]
    edges += [(w.name, w.slit_from) for w in spec.webs if w.slit_from is not None]
    parents = [layer for w in spec.webs for layer in (w.layers or [])]
    for name in set(parents):
        if parents.count(name) > 1:
            fail("webs", f"web {name!r} is a layer of several laminates")
    bases = {w.slit_from for w in spec.webs if w.slit_from}
    for name in bases & set(parents):
        fail("webs", f"web {name!r} is both slit and laminated at its end")
    group = {w.name: w.name for w in spec.webs}

    def root(n: str) -> str:
        while group[n] != n:
            n = group[n]
        return n

    for a, b in edges:
        ra, rb = root(a), root(b)
        if ra == rb:
            fail("webs", f"webs {a!r} and {b!r} close a loop: the webs must form a tree")
        group[ra] = rb
    if len({root(w.name) for w in spec.webs}) > 1:
        fail("webs", "the webs are not all joined: a line is one connected tree of webs")
