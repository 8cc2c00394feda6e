"""The disturbances of a branched line in the plan: the compiled loop's table (``layout``
DS_*) of wound-in ripple per unwind, speed ripple per drive, drag torque per roller and
measurement noise (docs/branching.md, "Disturbances"); and a web break (docs/branching.md,
"Web breaks"): which spans it cuts loose, when, and the monitor's and the stop's settings as
the loop's columns (SF_BREAK, D_B*; the loop's side in ``sim.branches.loop.breaks``, the
verdict's in ``sim.branches.findings.break_verdict``)."""

from __future__ import annotations

import math

import numpy as np

from webline.model.web_graph import BranchedLine
from webline.profiles import breakpoints
from webline.sim.branches.loop import layout as B
from webline.spec.disturbances import (
    EccentricRoller,
    MeasurementNoise,
    RollerDrag,
    SpeedRipple,
    WoundInRipple,
)
from webline.spec.schema import IdleSpec, UnwindSpec
from webline.spec.winder import WebBreak


def eccentricities(line: BranchedLine) -> dict[int, float]:
    """Node -> eccentricity [m] of every out-of-round roller or roll (``eccentric_roller``):
    its lever arm and surface speed are r + e cos(angle), the angle a state (dθ/dt = ω)."""
    return {line.node_index[item.roller]: item.eccentricity for item in line.spec.disturbances
            if isinstance(item, EccentricRoller)}


def disturbance_table(line: BranchedLine,
                      profiles: list[tuple[np.ndarray, np.ndarray]]) -> np.ndarray:
    """Rows (kind, index, a, b, c) of ``line``'s disturbances; a drag's torque profile is
    appended to ``profiles`` and its row names it."""
    rows = []
    unwinds = [i for i, r in enumerate(line.spec.rollers) if isinstance(r, UnwindSpec)]
    for item in line.spec.disturbances:
        if isinstance(item, WoundInRipple):
            node = unwinds[0] if item.roller is None else line.node_index[item.roller]
            web = next(w for w, v in enumerate(line.spec.webs)
                       if line.node_index[v.path[0]] == node)
            rows.append((B.DIST_WOUND_RIPPLE, web, item.amplitude, item.frequency, item.phase))
        elif isinstance(item, SpeedRipple):
            drive = line.drives.index(line.node_index[item.roller])
            rows.append((B.DIST_SPEED_RIPPLE, drive, item.amplitude, item.frequency,
                         item.phase))
        elif isinstance(item, RollerDrag):
            rows.append((B.DIST_DRAG, line.node_index[item.roller], len(profiles), 0.0, 0.0))
            profiles.append(breakpoints(item.torque))
        elif isinstance(item, MeasurementNoise):
            rows.append((B.DIST_NOISE, item.seed, item.tension, item.speed,
                         item.speed_resolution))
    return np.array(rows, dtype=float).reshape(-1, B.DS_COLS)


HOLDS = {"zero_speed": B.HOLD_ZERO_SPEED, "off": B.HOLD_OFF, "brakes": B.HOLD_BRAKES,
         "stall_tension": B.HOLD_STALL}


def web_break(line: BranchedLine) -> WebBreak | None:
    """The line's web break (a ``web_break`` disturbance or a scenario's ``break``), if any
    (the check allows one per run)."""
    return next((d for d in line.spec.disturbances if isinstance(d, WebBreak)), None)


def broken_segment(line: BranchedLine, k: int) -> list[int]:
    """The spans [indices] that carry no tension once span ``k`` breaks: from the break both
    ways along the web tree up to the rollers that grip the web, a driven roller or a roll
    (through idle rollers the free end runs on). At a junction: a layer's free end stops at
    the lamination nip (the other layers carry the laminate on, B2 one term less); a
    laminate's runs back through an idle nip into every layer; a base web's runs through an
    idle slitter into every lane (each loses its feed); a lane's stops at the slitter (the
    base web carries the other lanes), but for a base web's only lane."""
    spec = line.spec
    grips = [not isinstance(r, IdleSpec) for r in spec.rollers]
    layers_of = {w: [line.web_index[n] for n in (web.layers or [])]
                 for w, web in enumerate(spec.webs)}
    lanes_of = {w: [v for v, lane in enumerate(spec.webs) if lane.slit_from == web.name]
                for w, web in enumerate(spec.webs)}
    laminate_of = {layer: w for w, layers in layers_of.items() for layer in layers}

    def neighbours(m: int) -> list[int]:
        span = line.spans[m]
        path = line.web_spans(span.web)
        out = []
        if m != path[-1]:
            out += [] if grips[span.b] else [m + 1]
        elif span.web not in laminate_of and not grips[span.b]:  # a base web's end
            out += [line.web_spans(v)[0] for v in lanes_of[span.web]]
        if m != path[0]:
            out += [] if grips[span.a] else [m - 1]
        elif not grips[span.a]:
            web = spec.webs[span.web]
            if web.layers is not None:  # a laminate's start: every layer
                out += [line.web_spans(v)[-1] for v in layers_of[span.web]]
            elif web.slit_from is not None:  # a lane's start: its base only if it is alone
                base = line.web_index[web.slit_from]
                if len(lanes_of[base]) == 1:
                    out.append(line.web_spans(base)[-1])
        return out

    seen, todo = {k}, [k]
    while todo:
        for m in neighbours(todo.pop()):
            if m not in seen:
                seen.add(m)
                todo.append(m)
    return sorted(seen)


def break_columns(line: BranchedLine, sf: np.ndarray, df: np.ndarray) -> bool:
    """Fill the break columns of the span table ``sf`` (each span's break time, inf: never)
    and of the drive table ``df`` (the monitor's and the stop's settings); True where the
    line breaks in this run."""
    sf[:, B.SF_BREAK] = math.inf
    item = web_break(line)
    if item is None:
        return False
    k = next(s.index for s in line.spans if s.name == item.span)
    sf[broken_segment(line, k), B.SF_BREAK] = item.at
    df[:, B.D_BTHRESH], df[:, B.D_BSTOP] = item.threshold, item.stop_time
    df[:, B.D_BHOLD], df[:, B.D_BDIAM] = HOLDS[item.hold], item.diameter_threshold
    df[:, B.D_BBRAKE] = item.brake_torque_fraction
    df[:, B.D_BOVER], df[:, B.D_BSTALL] = float(item.overspeed), item.standstill_tension
    return True
