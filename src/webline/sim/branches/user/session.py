"""``webline.Session`` on a branched line (``Session`` hands a ``BranchedLine`` here): the line
at its operating point, advanced tick by tick by ``step``, its user controllers called every
tick (``sim.branches.user.loop``), snapshots to go back to, and the ``BranchResult`` so far.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from webline.errors import ArgumentError, ControllerError, SimulationError
from webline.model.web_graph import BranchedLine
from webline.sim.branches.drives.draw import fill_draw
from webline.sim.branches.findings.break_verdict import detection
from webline.sim.branches.findings.web_findings import strength_failure
from webline.sim.branches.loop import layout as B
from webline.sim.branches.result import BranchResult
from webline.sim.branches.run import _failure_text, plan_and_step, start_state
from webline.sim.branches.user.loop import BranchUserLoop, branch_groups
from webline.sim.core.session_contract import check_snapshot, session_settings
from webline.sim.core.user_protocol import Group
from webline.spec.ranges import reference_argument, session_identity

#: records the session's buffer starts with; it doubles when full
FIRST_ROWS = 4096


@dataclass(frozen=True)
class BranchSnapshot:
    """What ``BranchSession.restore`` goes back to: the live arrays, the tick, the records,
    the references and the traction rollers' stick/slip memory; a Python controller's own
    memory is its to keep."""

    live: np.ndarray
    tick: int
    records: np.ndarray
    prof_v: np.ndarray
    nodes: np.ndarray
    identity: str = ""
    line: str = ""


class BranchSession:
    """``line`` (a ``BranchedLine``) at its operating point, advanced by ``step``;
    ``controller``, ``scenario``, ``sample_rate`` [Hz] and ``substeps`` as in ``simulate``.
    Every tick is recorded (``result``)."""

    def __init__(self, line: BranchedLine, *, controller: object | Mapping[str, object]
                 | None = None, scenario: str | None = None, sample_rate: float | None = None,
                 substeps: int | None = None) -> None:
        rate, steps = session_settings(sample_rate, substeps)
        if scenario is not None:
            line = line.with_scenario(scenario)
        self._start(line, rate, steps, branch_groups(line, controller), reset=True)

    def _start(self, line: BranchedLine, rate: float | None, steps: int | None,
               groups: list[Group], reset: bool) -> None:
        """As ``Session._start``."""
        plan, point, self.substeps = plan_and_step(line, rate, steps)
        fill_draw(plan, point, always=True)  # set_reference moves the draw as a step would
        self._built = (line, rate, groups)
        x, istate = start_state(plan, point)
        self._loop = BranchUserLoop(plan, point, groups, x, istate,
                                    plan.wound.copy(), np.zeros(len(plan.events)),
                                    point.torque.copy(), self.substeps, 1, reset=reset)
        self.plan = self._loop.plan
        self._rec = np.empty((FIRST_ROWS, 1 + plan.n_x + 2 * plan.di.shape[0]))
        self._tick, self._stored, self._status, self._t_fail = 0, 0, B.STATUS_OK, math.nan
        self.identity = session_identity(
            line.spec.model_dump_json(exclude_none=True), line.scenario, self.plan.dt,
            self.substeps, [(g.name, g.drives) for g in groups])

    def __getstate__(self) -> dict[str, Any]:
        line, rate, groups = self._built
        return {"line": line, "rate": rate, "substeps": self.substeps, "groups": groups,
                "snapshot": self.snapshot(), "status": (self._status, self._t_fail)}

    def __setstate__(self, state: dict[str, Any]) -> None:
        self._start(state["line"], state["rate"], state["substeps"], state["groups"],
                    reset=False)
        self.restore(state["snapshot"])
        self._status, self._t_fail = state["status"]

    @property
    def t(self) -> float:
        """Time [s] of the state: ticks done x the sample period."""
        return self._tick * self.plan.dt

    def step(self, n: int = 1) -> None:
        """Advance ``n`` controller ticks. ``SimulationError`` (``partial``: the run so far)
        if the line leaves physical validity, ``ControllerError`` if a user controller
        fails; the session cannot go on from either but by ``restore``."""
        if n < 0 or int(n) != n:
            raise ArgumentError(f"step: n must be a whole number >= 0, got {n}")
        if self._tick == 0 and self._status == B.STATUS_OK and self._loop.failed is not None:
            raise ControllerError(f"{self.plan.line.name}: {self._loop.failed[1]}",
                                  partial=self.result())  # (a reset that failed)
        if self._status != B.STATUS_OK or self._loop.failed is not None:
            raise SimulationError(f"{self.plan.line.name}: the session stopped at t = "
                                  f"{self.t:.6g} s; restore a snapshot to go on")
        if self._stored + int(n) + 2 > len(self._rec):
            grown = np.empty((2 * (self._stored + int(n) + 2), self._rec.shape[1]))
            grown[:self._stored] = self._rec[:self._stored]
            self._rec = grown
        users = bool(self._loop.views)
        for _ in range(int(n) if users else int(n > 0)):  # no user drive: one compiled call
            count = 1 if users else int(n)
            stored, status, t_fail = (
                self._loop.tick(self._rec[self._stored:], self._tick, False) if users else
                self._loop.advance(self._rec[self._stored:], self._tick, count))
            self._stored += stored
            if status == B.STATUS_OK:
                self._tick += count
            else:  # (the session stays at the last tick it completed)
                self._status, self._t_fail = status, t_fail
                result = self.result()
                assert result.failure is not None
                error = ControllerError if self._loop.failed else SimulationError
                raise error(f"{self.plan.line.name}: {result.failure}", partial=result)

    def _names(self) -> list[tuple[str, int]]:
        """(name, index in the state) of the named states (``state``)."""
        line, off = self.plan.line, self.plan.offsets
        rollers = line.spec.rollers
        return ([(f"{s.name}.stretch", s.index) for s in line.spans]
                + [(f"{r.name}.omega", off[B.O_OMEGA] + i) for i, r in enumerate(rollers)]
                + [(f"{rollers[r.node].name}/{line.spec.webs[r.web].name}.radius",
                    off[B.O_RADIUS] + j) for j, r in enumerate(line.rolls)]
                + [(f"{rollers[i].name}.torque", off[B.O_TORQUE] + d)
                   for d, i in enumerate(line.drives)])

    @property
    def state(self) -> dict[str, float]:
        """The plant's main states at ``t``, SI: each span's stretch EA·ε [N]
        (``"<span>.stretch"``), each roller's speed ω [rad/s] (``"<roller>.omega"``), each
        roll's radius [m] (``"<roller>/<web>.radius"``), each drive's motor torque [N·m]
        (``"<drive>.torque"``)."""
        x = self._loop.live[0]
        return {name: float(x[k]) for name, k in self._names()}

    @property
    def measurements(self) -> dict[str, float]:
        """What the sensors would read at ``t`` without noise: each span's tension [N]
        (``"<span>.tension"``, its stretch where taut) and each roller's surface speed [m/s]
        (``"<roller>.speed"``, at its first web's radius); the user drives' readings of the
        last tick, noise included, by the names of docs/controllers.md, prefixed
        ``"measured."``."""
        line, x, plan = self.plan.line, self._loop.live[0], self.plan
        out = {f"{s.name}.tension": max(float(x[s.index]), 0.0) for s in line.spans}
        radius = plan.nodes[:, B.N_RADIUS].copy()
        for d, i in enumerate(line.drives):
            if plan.di[d, B.DI_ROLL] >= 0:
                radius[i] = x[plan.offsets[B.O_RADIUS] + plan.di[d, B.DI_ROLL]]
        for i, r in enumerate(line.spec.rollers):
            out[f"{r.name}.speed"] = float(radius[i] * x[plan.offsets[B.O_OMEGA] + i])
        for name, value in zip(self._loop.measurement_names, self._loop.readings,
                               strict=True):
            out[f"measured.{name}"] = float(value)
        return out

    def set_reference(self, name: str, value: float | str) -> None:
        """As ``Session.set_reference`` (the line file's ranges and messages)."""
        plan, line = self.plan, self.plan.line
        spans = {f"{line.spans[int(k)].name}.tension": int(p) for k, p, *_ in plan.cells}
        if name != "speed" and name not in spans:
            raise ArgumentError(f"set_reference: no reference {name!r}; there are "
                                f"speed, {', '.join(spans)}")
        value = reference_argument(name, value)
        p = 0 if name == "speed" else spans[name]
        plan.prof_v[plan.prof_off[p]:plan.prof_off[p + 1]] = value

    def apply(self, changes: Mapping[str, float]) -> None:
        """A disturbance: add each value [SI] to the named state now (``state``'s names, e.g.
        ``{"film_zone.stretch": 50.0}`` a 50 N tension kick)."""
        names = dict(self._names())
        for name, delta in changes.items():
            if name not in names:
                raise ArgumentError(f"apply: no state {name!r}; the states are "
                                    f"{', '.join(names)}")
            self._loop.live[0][names[name]] += float(delta)

    def snapshot(self) -> BranchSnapshot:
        """The session now (state, controller memory, references, records)."""
        return BranchSnapshot(self._loop.live_buffer.copy(), self._tick,
                              self._rec[:self._stored].copy(), self.plan.prof_v.copy(),
                              self.plan.nodes.copy(), self.identity, self.plan.line.name)

    def restore(self, snap: BranchSnapshot) -> None:
        """Go back to ``snap`` (of this session or a copy of it; another's is refused in one
        line, ``ArgumentError``)."""
        check_snapshot(snap, BranchSnapshot, self.identity, self.plan.line.name)
        self._loop.live_buffer[:] = snap.live
        self.plan.prof_v[:] = snap.prof_v
        self.plan.nodes[:] = snap.nodes
        self._tick, self._stored = snap.tick, len(snap.records)
        self._rec = np.empty((max(FIRST_ROWS, 2 * self._stored + 2), self._rec.shape[1]))
        self._rec[:self._stored] = snap.records
        self._status, self._t_fail, self._loop.failed = B.STATUS_OK, math.nan, None

    def result(self) -> BranchResult:
        """The ``BranchResult`` of the ticks run so far (the state at ``t`` its last record,
        as a run of that duration ends)."""
        plan, x, istate = self.plan, self._loop.live[0], self._loop.live[1]
        rows = self._rec[:self._stored]
        failure = None
        if self._loop.failed is not None:
            failure = self._loop.failed[1]
        elif self._status == B.STATUS_STRENGTH:
            failure = strength_failure(plan, x, self._t_fail)
        elif self._status != B.STATUS_OK:
            failure = _failure_text(self._status, self._t_fail)
        else:
            rows = np.vstack([rows, self._loop.sample(self._tick)])
        return BranchResult(plan, rows.copy(), failure,
                            {"duration": self.t, "dt": plan.dt, "substeps": self.substeps,
                             "record_every": 1, **detection(plan, istate)})
