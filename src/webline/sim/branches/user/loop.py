"""A branched line's run with user controllers (docs/controllers.md, "On a branched line").

Each tick the compiled loop (``loop.kernel.advance``) first samples the tick on a scratch copy
of the run's arrays (``n_ticks`` = 0: events, held inputs and every drive's tick, nothing
integrated), which yields exactly the readings the live tick will take (measurement noise is
a function of seed, tick and channel; the calculated radius, break monitor and splices are
deterministic); Python calls the controllers with those readings, writes their commands into
the user drives' memory (``layout.I_UCMD``), and the live arrays advance one tick. The
drives without a user controller keep their compiled controllers. Where every controller of
a run is a compiled law (``in_loop``), no Python runs per tick: the laws run inside the
compiled loop (``loop.user.law_step``), their buffer in rows of the controller memory after
the drives'.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from webline.control.pi import PIGains
from webline.errors import ArgumentError
from webline.model.web_graph import BranchedLine
from webline.sim.branches.equilibrium import BranchPoint
from webline.sim.branches.loop import layout as B
from webline.sim.branches.loop import transmission as TR
from webline.sim.branches.loop.plant import node_inertia
from webline.sim.branches.plan import BranchPlan
from webline.sim.core.laws import LawBuffer, all_compiled
from webline.sim.core.user_protocol import (
    ENDINGS,
    MEASURED,
    REFERENCES,
    DriveInfo,
    Group,
    NamedReadings,
    argument_groups,
    controller_error,
    reset_all,
    shape_of,
)
from webline.sim.drives.user_loop import STATUS_USER_NONFINITE

#: the readings stored per user drive, in ``MEASURED`` then ``REFERENCES`` order
READINGS = (B.I_USPEED, B.I_UTENSION, B.I_URADIUS, B.I_UINERTIA, B.I_UVREF, B.I_UTREF)


@dataclass(frozen=True)
class BranchControllerContext(NamedReadings):
    """What ``reset`` receives on a branched line: as ``sim.user_control.ControllerContext``
    with the ``BranchedLine`` and its ``BranchPoint`` (state, torques and speed ratios at
    t = 0)."""

    line: BranchedLine
    operating_point: BranchPoint
    sample_period: float
    drives: tuple[DriveInfo, ...]
    measurement_names: tuple[str, ...]
    reference_names: tuple[str, ...]


def drive_names(line: BranchedLine) -> list[str]:
    """The names of ``line``'s drives (its driven rollers), in drive order."""
    return [line.spec.rollers[i].name for i in line.drives]


def branch_groups(line: BranchedLine, controller: object | Mapping[str, object] | None
                  ) -> list[Group]:
    """The user controllers of a run: ``controller`` one object for every drive, or a dict
    drive name -> object, in drive order; ``ArgumentError`` for an unknown drive name, an
    object without the protocol or a drive in open-loop tension control (it has no
    command to take)."""
    names = drive_names(line)
    groups = argument_groups(controller, names)
    for g in groups:
        for d in g.drives:
            winder = getattr(line.spec.rollers[line.drives[d]], "winder", None)
            if winder is not None and winder.mode == "open_loop":
                raise ArgumentError(f"controller: {names[d]!r} runs open-loop tension "
                                    f"control (rollers.winder.mode); it takes no command")
    return sorted(groups, key=lambda g: g.drives[0])


def user_branch_plan(plan: BranchPlan, groups: Sequence[Group]) -> BranchPlan:
    """``plan`` with the drives of ``groups`` run by their user controllers
    (``FAMILY_USER``); a new structure, compiled once."""
    di = plan.di.copy()
    for g in groups:
        di[list(g.drives), B.DI_FAMILY] = B.FAMILY_USER
    return dataclasses.replace(plan, di=di)


def branch_context(plan: BranchPlan, point: BranchPoint, group: Group,
                   istate: np.ndarray) -> BranchControllerContext:
    """The context of ``group`` in a run of ``plan`` from ``point`` with controller memory
    ``istate`` at t = 0."""
    line, infos = plan.line, []
    for d in group.drives:
        i, row = int(plan.di[d, B.DI_NODE]), plan.df[d]
        j = int(plan.di[d, B.DI_ROLL])
        radius = float(point.x[plan.offsets[B.O_RADIUS] + j]) if j >= 0 else float(
            plan.nodes[i, B.N_RADIUS])
        inertia = float(node_inertia(i, point.x, plan.const.offsets, plan.nodes, plan.rolls)
                        + TR.reflected_motor(d, plan.const.di, plan.df))
        infos.append(DriveInfo(
            line.spec.rollers[i].name, i, j >= 0,
            "tension" if row[B.D_SIGMA] != 0.0 and plan.di[d, B.DI_NCELLS] > 0 else "master",
            float(row[B.D_SIGMA]), float(row[B.D_LIMIT]), float(row[B.D_RATIO]), radius,
            inertia, PIGains(*(float(row[c]) for c in (B.D_KPS, B.D_KIS, B.D_KPT, B.D_KIT))),
            float(row[B.D_GAINNORM]), float(istate[d, B.I_SPEED]),
            float(row[B.D_SIGMA] * istate[d, B.I_TENSION])))
    return BranchControllerContext(
        line, point, plan.dt, tuple(infos),
        tuple(f"{info.name}.{m}" for info in infos for m in MEASURED),
        tuple(f"{info.name}.{r}" for info in infos for r in REFERENCES))


class BranchUserLoop:
    """The live arrays of a branched run with user controllers (module docstring): ``x``,
    ``istate``, ``wound``, ``done`` and ``cmd`` as ``BranchPlan.run`` takes them, advanced
    tick by tick by ``tick``; ``plan`` has the user drives' ``FAMILY_USER``."""

    def __init__(self, plan: BranchPlan, point: BranchPoint, groups: Sequence[Group],
                 x: np.ndarray, istate: np.ndarray, wound: np.ndarray, done: np.ndarray,
                 cmd: np.ndarray, substeps: int, every: int, reset: bool = True,
                 in_loop: bool = False) -> None:
        self.plan = user_branch_plan(plan, groups)
        self.groups = list(groups)
        self.failed: tuple[str, str, float] | None = None
        ended = (reset_all(groups, lambda g: branch_context(self.plan, point, g, istate))
                 if reset else None)  # (reset=False: a copied session's controllers)
        if ended is not None:  # a reset that failed ends the run before its first tick
            self.failed = (ended[0].name, ended[1], 0.0)
        #: with ``in_loop`` and every controller a compiled law: the laws, which run inside
        #: the compiled loop (``loop.user.law_step``), their buffer in rows of the controller
        #: memory after the drives' (``live[1]``); None: each controller called from Python
        self.laws = (LawBuffer.of(groups) if in_loop and ended is None and all_compiled(groups)
                     else None)
        if self.laws is not None:
            rows = -(-self.laws.size // istate.shape[1])
            istate = np.vstack([istate, np.zeros((rows, istate.shape[1]))])
        # the live arrays in one buffer and their scratch copy in another: one copy a tick
        arrays = (x, istate, wound, done, cmd)
        self.live_buffer = np.concatenate([a.ravel() for a in arrays])
        self.scratch_buffer = self.live_buffer.copy()
        self.live, self.scratch = (_views(buffer, arrays) for buffer in (
            self.live_buffer, self.scratch_buffer))
        self.substeps, self.every = substeps, every
        self.users = np.array([d for g in groups for d in g.drives], dtype=np.int64)
        # where each reading lies in the buffers (istate's rows follow x's entries)
        at = x.size + self.users[:, None] * istate.shape[1]
        self.reading_at = (at + np.array(READINGS[:len(MEASURED)])).ravel()
        self.reference_at = (at + np.array(READINGS[len(MEASURED):])).ravel()
        self.readings = np.empty(self.reading_at.size)  # (reused every tick)
        self.references = np.empty(self.reference_at.size)
        if self.laws is not None:  # the laws' params and state: views of the live memory
            start = x.size + len(cmd) * istate.shape[1]
            self.law_memory = self.live_buffer[start:start + self.laws.size]
            self.laws.attach(self.law_memory)
        self.loop = self.plan.loop(None if self.laws is None else (self.laws.users,
                                                                   self.laws.key))
        p = self.plan
        self.stages, self.work = np.empty((5, p.n_x)), p.scratch()
        self.held, self.rec_s = np.empty_like(wound), np.empty((2, 1 + p.n_x + 2 * len(cmd)))
        self.tail = (p.speed_max, p.nodes, p.sf, p.rolls, p.df, p.clutch, p.events, p.dist,
                     p.prof_t, p.prof_v, p.prof_off, p.lawf, p.laws, p.fb, p.refs)
        self.views: list[tuple[Any, ...]] = []  # each group's slices of the readings, made once
        first = 0
        for g in groups:
            k = len(g.drives)
            self.views.append((g, self.readings[len(MEASURED) * first:len(MEASURED) * (first + k)],
                               self.references[len(REFERENCES) * first:
                                               len(REFERENCES) * (first + k)], k,
                               x.size + self.users[first:first + k] * istate.shape[1]
                               + B.I_UCMD))
            first += k
        self.stored_in_chunk = 0  # records ``ticks`` wrote in its current call
        #: the names of ``readings``, as the controllers' contexts name them
        self.measurement_names = tuple(
            f"{self.plan.line.spec.rollers[self.plan.line.drives[d]].name}.{m}"
            for d in self.users for m in MEASURED)

    def _call(self, arrays: tuple[np.ndarray, ...], rec: np.ndarray, tick: int, n_ticks: int,
              include_end: bool) -> tuple[int, int, float]:
        x, istate, wound, done, cmd = arrays
        out: tuple[int, int, float] = self.loop(
            x, istate, wound, done, rec, self.stages, cmd, self.work, self.held, tick, n_ticks,
            self.plan.dt, self.substeps, self.every, include_end, *self.tail)
        return out

    def advance(self, rec: np.ndarray, tick: int, count: int) -> tuple[int, int, float]:
        """``count`` ticks from ``tick`` in one compiled call, without a controller to call
        (a session of a line without user drives); as ``BranchPlan.run``."""
        return self._call(self.live, rec, tick, count, False)

    def sample(self, tick: int) -> np.ndarray:
        """The record row of tick ``tick`` as a run that ends there writes it (sampled on
        the scratch copy: the live arrays stay where they are)."""
        self.scratch_buffer[:] = self.live_buffer
        self._call(self.scratch, self.rec_s, tick, 0, True)
        return self.rec_s[:1].copy()

    def tick(self, rec: np.ndarray, tick: int, last: bool) -> tuple[int, int, float]:
        """Tick ``tick``: sample it, call the controllers, then advance the live arrays one
        tick, recording into ``rec`` (``last``: the run's end, only sampled and recorded).
        Returns (records, status, time of failure) as ``BranchPlan.run``; a controller that
        fails leaves ``failed`` (its name, the error line, the time) and status -1."""
        if self.failed is not None:  # (its reset failed)
            return 0, -1, self.failed[2]
        self.scratch_buffer[:] = self.live_buffer
        self._call(self.scratch, self.rec_s, tick, 0, True)
        self.scratch_buffer.take(self.reading_at, out=self.readings, mode="clip")
        self.scratch_buffer.take(self.reference_at, out=self.references,
                                 mode="clip")  # (unbuffered: the indices are valid)
        t = tick * self.plan.dt
        for g, meas, refs, k, rows in self.views:
            error = self._command(g, meas, refs, k, tick, t)
            if error is not None:
                self.failed = (g.name, error, t)
                return 0, -1, t
            self.live_buffer[rows] = self._last
        return self._call(self.live, rec, tick, 0 if last else 1, last)

    def _command(self, g: Group, meas: np.ndarray, refs: np.ndarray, k: int, tick: int,
                 t: float) -> str | None:
        """Call ``g``'s controller; its commands in ``_last``, or the error line."""
        try:
            torque: Any = g.controller(t, meas, refs)
        except ENDINGS as exc:  # the user's code: any error (sys.exit too) ends the run
            return controller_error(g, tick, t, exc)
        values = torque
        if not (type(torque) is np.ndarray and torque.shape == (k,)):  # (the fast path)
            try:
                values = np.asarray(torque, dtype=float)
                if values.ndim > 1 or (values.ndim == 1 and values.shape[0] != k) or (
                        values.ndim == 0 and k > 1):
                    raise ValueError
            except (ValueError, TypeError):
                return controller_error(g, tick, t, None, f"returned {shape_of(torque)} "
                                        f"where {k} torque(s) [N·m] were due")
        if not math.isfinite(values.sum()):  # (any nan or inf makes the sum one)
            each = np.broadcast_to(values, (k,)).astype(float)
            bad = int(np.flatnonzero(~np.isfinite(each))[0])
            name = self.plan.line.spec.rollers[self.plan.line.drives[g.drives[bad]]].name
            return controller_error(g, tick, t, None, f"returned a non-finite torque "
                                    f"{each[bad]} for {name}")
        self._last = values
        return None

    def ticks(self, rec: np.ndarray, tick0: int, count: int,
              include_end: bool) -> tuple[int, int, float, int]:
        """``count`` ticks from ``tick0`` (and, with ``include_end``, the sample of the run's
        last tick), recording into ``rec``; (records, status, time of failure, ticks done)."""
        stored = self.stored_in_chunk = 0  # (what a Ctrl-C between two ticks keeps)
        if self.laws is not None and self.failed is None:  # the laws in the loop: one call
            stored, status, t_fail = self._call(self.live, rec, tick0, count, include_end)
            self.stored_in_chunk = stored
            if status == STATUS_USER_NONFINITE:
                self.failed = (*self._law_failure(t_fail), t_fail)
            return stored, status, t_fail, count
        for j in range(count + int(include_end)):
            n, status, t_fail = self.tick(rec[stored:], tick0 + j, j == count)
            stored += n
            self.stored_in_chunk = stored
            if status != B.STATUS_OK:
                return stored, status, t_fail, j
        return stored, B.STATUS_OK, math.nan, count

    def _law_failure(self, t: float) -> tuple[str, str]:
        """(controller name, one-line error) of a compiled law that raised or gave a
        non-finite command at time ``t`` [s] (``sim.core.laws.LawBuffer.failure``)."""
        assert self.laws is not None
        istate = self.live[1]
        where = next((d for d in sorted(self.users)
                      if not math.isfinite(istate[d, B.I_UCMD])), -1)
        return self.laws.failure(
            self.law_memory, where, t, self.plan.dt,
            lambda d: self.plan.line.spec.rollers[self.plan.line.drives[d]].name)


def _views(buffer: np.ndarray, arrays: tuple[np.ndarray, ...]) -> tuple[np.ndarray, ...]:
    """Views of ``buffer`` shaped as ``arrays``, which lie in it one after the other."""
    out, start = [], 0
    for a in arrays:
        out.append(buffer[start:start + a.size].reshape(a.shape))
        start += a.size
    return tuple(out)
