"""Verdict findings of winder states (docs/winder.md, "Winder states in the verdict"): a
dancer on an end stop, a zone far from its set tension, a calculated diameter far from the
true one. Each is a ``warning`` naming where, when and how long.

The checks watch ``StateElement`` rows (``state_elements``: the element, its threshold and
minimum duration). Over the records before the first web break, each row gives a condition
per record and two extremes (``Extremes``); the intervals in which the condition holds for at
least the minimum duration reduce to ``IntervalStats``. A run computes both from its records
(``winder_state_findings``, numpy), a study case from its batch's accumulators
(``sim.sweeps.batch_states``, compiled, the same definitions); ``state_finding`` turns them into the
same finding for both.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Protocol

import numpy as np

from webline.line import Line
from webline.sim.core.plan import Plan
from webline.sim.elements import layout as L
from webline.sim.results.events import intervals
from webline.spec.winder import WebBreak
from webline.verdict import Finding

#: the kinds of check, in the order their findings are listed
DANCER, TENSION, DIAMETER = range(3)
KIND_NAMES = ("dancer_end_stop", "tension_off_set", "diameter_error")


class Result(Protocol):
    """What the checks read of a run (``webline.sim.results.result.Result``): [SI] arrays over
    its records."""

    @property
    def plan(self) -> Plan: ...
    @property
    def time(self) -> np.ndarray: ...
    @property
    def states(self) -> np.ndarray: ...
    @property
    def control_radius(self) -> np.ndarray: ...
    @property
    def line(self) -> Line: ...
    @property
    def tension(self) -> np.ndarray: ...
    @property
    def tension_ref(self) -> np.ndarray: ...
    @property
    def radius(self) -> np.ndarray: ...


@dataclass(frozen=True)
class StateElement:
    """One element a check watches: ``kind`` (``DANCER``, ``TENSION``, ``DIAMETER``),
    ``where`` (its name in the finding), ``node`` (the dancer's, the drive's), ``drive``
    (-1 for a dancer), ``span`` (a tension zone's loadcell span, else -1), ``limit`` (the
    dancer's travel [m], else the tolerance [-]), ``min_duration`` [s] an interval must last
    to count, ``read`` (a tension zone whose drive reads its loadcell)."""

    kind: int
    where: str
    node: int
    drive: int
    span: int
    limit: float
    min_duration: float
    read: bool = False


@dataclass(frozen=True)
class IntervalStats:
    """The intervals of a condition that lasted at least their minimum duration: how many,
    the first one's start and end, the total and the longest [s]."""

    count: int
    first: float
    first_end: float
    total: float
    longest: float


#: two numbers per element over the records looked at (the NaN-free start values in
#: ``EXTREMES_START``): a dancer's (1 if it touched its low stop, unused); a zone's (largest
#: error |T - T_set| [N] where it was off, T/T_set there (NaN: T_set = 0)); a calculator's
#: (largest |error| [m] of the diameter, that error with its sign [m])
Extremes = tuple[float, float]
EXTREMES_START: Extremes = (-1.0, math.nan)


def state_elements(plan: Plan) -> list[StateElement]:
    """Every element the checks watch on ``plan``'s line, in the order of their findings:
    the dancers, the tension zones' drives, the drives with a diameter calculator."""
    line, checks = plan.line, plan.line.spec.checks
    out = [StateElement(DANCER, line.node_name(i), i, -1, -1,
                        float(plan.nodes[i, L.N_DTRAVEL]), checks.end_stop_time)
           for i in map(int, np.flatnonzero(plan.nodes[:, L.N_DANCER] >= 0))]
    for d, i in enumerate(line.drives):
        row = plan.drives[d]
        if row[L.D_ROLE] == L.ROLE_TENSION:
            read = bool(row[L.D_FAMILY] != L.FAMILY_OPEN_LOOP and row[L.D_OBS] == 0.0)
            k = int(row[L.D_LOADCELL])
            out.append(StateElement(TENSION, line.span_name(k), i, d, k,
                                    checks.tension_tolerance, checks.min_duration, read))
    out += [StateElement(DIAMETER, line.node_name(i), i, d, -1, checks.diameter_tolerance,
                         checks.min_duration)
            for d, i in enumerate(line.drives) if plan.drives[d, L.D_DCALC] != L.DCALC_NONE]
    return out


def window_end(line: Line) -> float:
    """The time [s] the checks stop looking: the first web break (inf: none)."""
    return min((b.at for b in line.spec.disturbances if isinstance(b, WebBreak)),
               default=math.inf)


def state_finding(line: Line, element: StateElement, stats: IntervalStats,
                  extremes: Extremes, duration: float) -> Finding:
    """The ``warning`` of ``element`` whose condition held in ``stats``' intervals, with
    its ``extremes``, over a run of ``duration`` [s]."""
    what, details = _words(line, element, extremes)
    times = "once" if stats.count == 1 else f"{stats.count} times"
    message = (f"{what} {times}, first from t = {stats.first:.4g} s to "
               f"{stats.first_end:.4g} s, {stats.total:.3g} s in all "
               f"({stats.total / duration:.1%} of the run)")
    return Finding("warning", KIND_NAMES[element.kind], element.where, message, stats.first,
                   {"first_s": stats.first, "total_s": stats.total,
                    "longest_s": stats.longest, "count": stats.count,
                    "fraction": stats.total / duration, **details})


def _words(line: Line, element: StateElement, extremes: Extremes
           ) -> tuple[str, dict[str, object]]:
    """The sentence's subject and condition, and the finding's own numbers."""
    name, first, second = element.where, extremes[0], extremes[1]
    if element.kind == DANCER:
        return (f"{name} rested on its end stop",
                {"travel_m": element.limit, "low_stop": first > 0.0})
    if element.kind == TENSION:
        words = "measured" if element.read else "true (no loadcell read)"
        return (f"{name}'s {words} tension stayed more than {element.limit:.0%} off its set "
                f"tension (the zone of {line.node_name(element.node)})",
                {"source": "measured (loadcell)" if element.read else "true tension",
                 "tolerance": element.limit, "largest_error_N": first,
                 "largest_ratio": None if math.isnan(second) else second})
    return (f"{name}'s calculated diameter stayed more than {element.limit:.0%} off the "
            f"true one (largest {1000 * second:+.3g} mm)",
            {"tolerance": element.limit, "largest_error_m": first})


def interval_stats(time: np.ndarray, mask: np.ndarray, min_duration: float
                   ) -> IntervalStats | None:
    """``IntervalStats`` of the runs of True in ``mask`` over ``time`` [s]
    (``events.intervals``) that last at least ``min_duration`` [s]; None if none does."""
    spans = intervals(time, mask)
    lengths = spans[:, 1] - spans[:, 0]
    long = lengths >= min_duration
    if not long.any():
        return None
    spans, lengths = spans[long], lengths[long]
    return IntervalStats(len(spans), float(spans[0, 0]), float(spans[0, 1]),
                         float(lengths.sum()), float(lengths.max()))


def record_condition(result: Result, element: StateElement, before: np.ndarray
                     ) -> tuple[np.ndarray, Extremes]:
    """``element``'s condition per record of ``result`` within ``before`` (a mask over the
    records) and its extremes there (``Extremes``)."""
    if element.kind == DANCER:
        y = result.states[:, result.plan.state_names.index(f"{element.where}.position")]
        low = bool(np.any(before & (y <= 0.0)))
        return before & ((y <= 0.0) | (y >= element.limit)), (1.0 if low else -1.0, math.nan)
    if element.kind == TENSION:
        ref = result.tension_ref[:, element.span]
        tension = result.tension[:, element.span]
        error = np.abs(tension - ref)
        mask = before & (error > element.limit * np.abs(ref))
        if not mask.any():
            return mask, EXTREMES_START
        worst = int(np.argmax(np.where(mask, error, -1.0)))
        ratio = tension[worst] / ref[worst] if ref[worst] else math.nan
        return mask, (float(error[worst]), float(ratio))
    true = result.radius[:, element.node]
    error = 2.0 * (result.control_radius[:, element.drive] - true)
    mask = before & (np.abs(error) > element.limit * (2.0 * true))
    if not before.any():
        return mask, EXTREMES_START
    worst = int(np.argmax(np.where(before, np.abs(error), -1.0)))
    return mask, (float(abs(error[worst])), float(error[worst]))


def winder_state_findings(result: Result) -> list[Finding]:
    """A ``warning`` for each watched element whose condition holds for at least its
    minimum duration in one interval, up to the first web break (after it the break's
    finding speaks)."""
    time = result.time
    if len(time) < 2:
        return []
    before = time < window_end(result.line)
    duration = float(time[-1] - time[0])
    out = []
    for element in state_elements(result.plan):
        mask, extremes = record_condition(result, element, before)
        stats = interval_stats(time, mask, element.min_duration)
        if stats is not None:
            out.append(state_finding(result.line, element, stats, extremes, duration))
    return out
