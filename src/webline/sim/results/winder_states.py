"""Verdict findings of winder states (docs/winder.md, "Winder states in the verdict"): a
dancer on an end stop, a zone far from its set tension, a calculated diameter far from the
true one. Each is a ``warning`` naming where, when and how long.

A check is a function of the run giving ``StateCheck`` rows: the element, a mask over the
records and what to say; ``winder_state_findings`` turns every row whose condition holds
long enough into a finding. Add a check by appending a function to ``CHECKS``.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Protocol

import numpy as np

from webline.line import Line
from webline.sim.core.plan import Plan
from webline.sim.elements import layout as L
from webline.sim.results.events import intervals
from webline.spec.winder import WebBreak
from webline.verdict import Finding


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
    def node_names(self) -> list[str]: ...
    @property
    def span_names(self) -> list[str]: ...
    @property
    def tension(self) -> np.ndarray: ...
    @property
    def tension_ref(self) -> np.ndarray: ...
    @property
    def radius(self) -> np.ndarray: ...


@dataclass(frozen=True)
class StateCheck:
    """One element's condition over a run: ``kind`` of finding, ``where`` (element name),
    ``mask`` (records where it holds), ``what`` (the sentence's subject and condition,
    e.g. "dancer rested on an end stop"), ``min_duration`` [s] an interval must last to
    count, and ``details`` for the finding (its numbers)."""

    kind: str
    where: str
    mask: np.ndarray
    what: str
    min_duration: float
    details: dict[str, object] = field(default_factory=dict)


def dancer_end_stops(result: Result) -> list[StateCheck]:
    """A dancer's carriage on an end stop (y <= 0 or y >= travel, as the break monitor
    reads it): any touch counts (``checks.end_stop_time``, default 0 s)."""
    out = []
    nodes = result.plan.nodes
    for i in np.flatnonzero(nodes[:, L.N_DANCER] >= 0):
        name = result.node_names[i]
        y = result.states[:, result.plan.state_names.index(f"{name}.position")]
        travel = nodes[i, L.N_DTRAVEL]
        mask = (y <= 0.0) | (y >= travel)
        low = bool(np.any(y[mask] <= 0.0))
        out.append(StateCheck("dancer_end_stop", name, mask,
                              f"{name} rested on its end stop", result.line.spec.checks
                              .end_stop_time, {"travel_m": float(travel), "low_stop": low}))
    return out


def tension_off_set(result: Result) -> list[StateCheck]:
    """Each tension zone's loadcell span farther than ``checks.tension_tolerance`` x its set
    tension (``Result.tension_ref``, the controller's) from it: the measured tension where
    the zone's drive reads a loadcell, the true tension otherwise (open loop, an observer)."""
    out = []
    checks = result.line.spec.checks
    for d, i in enumerate(result.line.drives):
        row = result.plan.drives[d]
        if row[L.D_ROLE] != L.ROLE_TENSION:
            continue
        k = int(row[L.D_LOADCELL])
        ref = result.tension_ref[:, k]
        tension = result.tension[:, k]
        error = np.abs(tension - ref)
        mask = error > checks.tension_tolerance * np.abs(ref)
        read = row[L.D_FAMILY] != L.FAMILY_OPEN_LOOP and row[L.D_OBS] == 0.0
        source = "measured (loadcell)" if read else "true tension"
        words = "measured" if read else "true (no loadcell read)"
        worst = int(np.argmax(np.where(mask, error, -1.0)))
        out.append(StateCheck(
            "tension_off_set", result.span_names[k], mask,
            f"{result.span_names[k]}'s {words} tension stayed more than "
            f"{checks.tension_tolerance:.0%} off its set tension (the zone of "
            f"{result.node_names[i]})", checks.min_duration,
            {"source": source, "tolerance": checks.tension_tolerance,
             "largest_error_N": float(error[worst]),
             "largest_ratio": float(tension[worst] / ref[worst]) if ref[worst] else None}))
    return out


def diameter_error(result: Result) -> list[StateCheck]:
    """Each diameter calculator farther than ``checks.diameter_tolerance`` x the true
    diameter from it."""
    out = []
    checks = result.line.spec.checks
    for d, i in enumerate(result.line.drives):
        if result.plan.drives[d, L.D_DCALC] == L.DCALC_NONE:
            continue
        error = 2.0 * (result.control_radius[:, d] - result.radius[:, i])
        true = 2.0 * result.radius[:, i]
        mask = np.abs(error) > checks.diameter_tolerance * true
        worst = int(np.argmax(np.abs(error)))
        name = result.node_names[i]
        out.append(StateCheck(
            "diameter_error", name, mask,
            f"{name}'s calculated diameter stayed more than {checks.diameter_tolerance:.0%} "
            f"off the true one (largest {1000 * error[worst]:+.3g} mm)", checks.min_duration,
            {"tolerance": checks.diameter_tolerance,
             "largest_error_m": float(abs(error[worst]))}))
    return out


#: every check of a run's winder states, in the order their findings are listed
CHECKS: list[Callable[[Result], list[StateCheck]]] = [
    dancer_end_stops, tension_off_set, diameter_error]


def winder_state_findings(result: Result) -> list[Finding]:
    """A ``warning`` for each check that holds for at least its minimum duration in one
    interval, up to the first web break (after it the break's finding speaks)."""
    time = result.time
    if len(time) < 2:
        return []
    breaks = [b.at for b in result.line.spec.disturbances if isinstance(b, WebBreak)]
    before = time < min(breaks) if breaks else np.ones(len(time), dtype=bool)
    duration = float(time[-1] - time[0])
    out = []
    for check in CHECKS:
        for row in check(result):
            spans = intervals(time, row.mask & before)
            lengths = spans[:, 1] - spans[:, 0]
            long = lengths >= row.min_duration if row.min_duration > 0 else lengths >= 0
            if not long.any():
                continue
            spans, lengths = spans[long], lengths[long]
            total = float(lengths.sum())
            times = "once" if len(spans) == 1 else f"{len(spans)} times"
            message = (f"{row.what} {times}, first from t = {spans[0, 0]:.4g} s to "
                       f"{spans[0, 1]:.4g} s, {total:.3g} s in all "
                       f"({total / duration:.1%} of the run)")
            details = {"first_s": float(spans[0, 0]), "total_s": total,
                       "longest_s": float(lengths.max()), "count": len(spans),
                       "fraction": total / duration, **row.details}
            out.append(Finding("warning", row.kind, row.where, message, float(spans[0, 0]),
                               details))
    return out
