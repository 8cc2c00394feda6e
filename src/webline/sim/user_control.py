"""User controllers in the loop: the protocol (docs/controllers.md) and the run that calls them.

A controller is a Python object with ``reset(context)`` (once, before the run) and
``__call__(t, measurements, references) -> torques`` (every tick of ``context.sample_period``
[s]). ``measurements`` and ``references`` are float arrays named by ``context.measurement_names``
and ``context.reference_names`` (per drive ``"<drive>.speed"`` [m/s], ``".tension"`` [N],
``".radius"`` [m], ``".inertia"`` [kg·m²]; ``"<drive>.speed_reference"`` [m/s],
``".tension_reference"`` [N]); the arrays are reused every tick (copy what you keep). It
returns one torque command [N·m] per drive of ``context.drives`` (a float for one drive).

The run goes one tick per compiled call (``sim.core.user_step``) and allocates nothing per tick
but what the controller does itself.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from webline.control.pi import PIGains
from webline.line import Line
from webline.model.operating_point import OperatingPoint
from webline.sim.core.plan import Plan
from webline.sim.core.user_protocol import (  # (here too, where the docs name them)
    ENDINGS,
    MEASURED,
    REFERENCES,
    Controller,
    DriveInfo,
    Group,
    NamedReadings,
    argument_groups,
    controller_error,
    reset_all,
)
from webline.sim.core.user_protocol import shape_of as _shape
from webline.sim.core.user_step import (
    C_EVERY,
    C_INCLUDE_END,
    C_MEASURE,
    C_N_TICKS,
    C_STATUS,
    C_STORED,
    C_SUBSTEPS,
    C_TICK,
    C_WHERE,
    compiled_user_step,
    packed_run,
)
from webline.sim.drives.user_loop import N_MEASURED, N_REFERENCES, STATUS_USER_NONFINITE
from webline.sim.elements import layout as L


@dataclass(frozen=True)
class ControllerContext(NamedReadings):
    """What ``reset`` receives: the ``line``, its ``operating_point`` at t = 0, the
    ``sample_period`` [s], the ``drives`` commanded (torques in this order) and the names of
    the entries of ``measurements`` and ``references``."""

    line: Line
    operating_point: OperatingPoint
    sample_period: float
    drives: tuple[DriveInfo, ...]
    measurement_names: tuple[str, ...]
    reference_names: tuple[str, ...]


def user_groups(line: Line, controller: object | Mapping[str, object] | None,
                from_file: Mapping[int, Controller]) -> list[Group]:
    """The user controllers of a run: ``controller`` (one object for every drive, or a dict
    drive name -> object) and those the line file names (``from_file``, by drive index), in
    drive order. ``ArgumentError`` for an unknown drive name or an object without the
    protocol."""
    names = [line.node_name(i) for i in line.drives]
    groups = argument_groups(controller, names)
    taken = {d for g in groups for d in g.drives}
    groups += [Group(names[d], obj, (d,)) for d, obj in from_file.items() if d not in taken]
    return sorted(groups, key=lambda g: g.drives[0])


def user_plan(plan: Plan, drives: Sequence[int]) -> Plan:
    """``plan`` with ``drives`` (indices) run by user controllers (``FAMILY_USER``)."""
    table, structure = plan.drives.copy(), plan.drive_structure.copy()
    table[list(drives), L.D_FAMILY] = L.FAMILY_USER
    structure[list(drives), L.DRIVE_STRUCTURE.index(L.D_FAMILY)] = L.FAMILY_USER
    return dataclasses.replace(plan, drives=table, drive_structure=structure, memo={})


def builtin_stand_in(plan: Plan) -> Plan:
    """``plan`` with its user drives run by the cascaded PI (their columns hold its tuned
    gains): what sets the integration step and what a linear model can describe."""
    users = np.flatnonzero(plan.drives[:, L.D_FAMILY] == L.FAMILY_USER)
    if not users.size:
        return plan
    table, structure = plan.drives.copy(), plan.drive_structure.copy()
    table[users, L.D_FAMILY] = L.FAMILY_PI
    structure[users, L.DRIVE_STRUCTURE.index(L.D_FAMILY)] = L.FAMILY_PI
    return dataclasses.replace(plan, drives=table, drive_structure=structure, memo={})


def context_for(plan: Plan, group: Group,
                istate: np.ndarray | None = None) -> ControllerContext:
    """The ``ControllerContext`` of ``group`` in a run of ``plan``; ``istate``: the plan's
    initial controller memory where the caller has it (else computed again)."""
    line, op = plan.line, plan.op
    if istate is None:  # the built-in PI's integrators at the equilibrium
        istate = plan.initial_state(op)[1]
    infos = []
    for d in group.drives:
        i = line.drives[d]
        row = plan.drives[d]
        infos.append(DriveInfo(
            line.node_name(i), i, i in (0, line.n_nodes - 1),
            "tension" if row[L.D_ROLE] == L.ROLE_TENSION else "master",
            float(row[L.D_SIGMA]), float(row[L.D_LIMIT]), float(plan.nodes[i, L.N_RATIO]),
            float(op.radius[i]), float(op.inertia[i]),
            PIGains(*(float(row[c]) for c in (L.D_KPS, L.D_KIS, L.D_KPT, L.D_KIT))),
            float(row[L.D_GAINNORM]),
            float(istate[d, L.I_SPEED]), float(row[L.D_SIGMA] * istate[d, L.I_TENSION])))
    return ControllerContext(
        line, op, plan.dt, tuple(infos),
        tuple(f"{info.name}.{m}" for info in infos for m in MEASURED),
        tuple(f"{info.name}.{r}" for info in infos for r in REFERENCES))


@dataclass
class UserRun:
    """Where a user run stopped: records stored, kernel status (or
    ``STATUS_USER_NONFINITE``), time and place of a failure, final arrays, the error of a
    controller that failed (None if none did) and its name, and whether Ctrl-C stopped it."""

    stored: int
    status: int
    t_fail: float
    where: int
    x: np.ndarray
    istate: np.ndarray
    error: str | None = None
    controller: str = ""
    interrupted: bool = False


class UserLoop:
    """A run of ``plan`` (user drives ``FAMILY_USER``, commanded by ``groups``) from the
    state ``x0``, ``istate0``, ``slip0``, one tick at a time: ``tick`` calls the controllers
    with the sampled measurements, then the compiled step (``sim.core.user_step``). Records go
    every ``every`` ticks into the ``rec`` each call is given, from row ``stored``.
    ``reset=False``: the controllers are not reset (a copied session's, whose memory they
    carry)."""

    def __init__(self, plan: Plan, groups: Sequence[Group], x0: np.ndarray,
                 istate0: np.ndarray, slip0: np.ndarray, substeps: int, every: int,
                 record_width: int, reset: bool = True) -> None:
        self.plan, self.groups = plan, list(groups)
        self.users = np.array([d for g in groups for d in g.drives], dtype=np.int64)
        self.packed = packed_run(plan, x0, istate0, slip0, self.users, record_width)
        v = self.packed.views
        self.control, self.commands = v["control"], v["commands"]
        self.step = compiled_user_step(plan)
        self.views, first = [], 0  # each group's slices of the shared arrays, made once
        for g in groups:
            k = len(g.drives)
            self.views.append((g, v["measured"][N_MEASURED * first:N_MEASURED * (first + k)],
                               v["references"][N_REFERENCES * first:
                                               N_REFERENCES * (first + k)],
                               self.commands[first:first + k], k))
            first += k
        self.failed: tuple[str, str, float] | None = None
        ended = reset_all(groups, lambda g: context_for(plan, g)) if reset else None
        if ended is not None:  # a reset that failed ends the run before its first tick
            self.failed = (ended[0].name, ended[1], 0.0)
        self.control[C_SUBSTEPS], self.control[C_EVERY] = substeps, every
        self.control[C_MEASURE] = 1
        self.step(self.packed.floats, self.packed.ints, np.empty((1, record_width)))  # tick 0
        self.control[C_N_TICKS] = 1

    @property
    def tick_index(self) -> int:
        """The tick whose commands come next."""
        return int(self.control[C_TICK])

    @property
    def status(self) -> int:
        """The kernel's status after the last step (``layout.STATUS_*``)."""
        return int(self.control[C_STATUS])

    def tick(self, rec: np.ndarray, last: bool = False) -> str | None:
        """The controllers' commands of the next tick, then that tick (``last``: only
        sampled and recorded, as a run's end); the error of a controller that failed (one
        line), else None."""
        if self.failed is not None:  # (its reset failed)
            return self.failed[1]
        j = int(self.control[C_TICK])
        t = j * self.plan.dt
        for g, meas, refs, cmds, k in self.views:
            try:
                torque = g.controller(t, meas, refs)
            except ENDINGS as exc:  # the user's code: any error (sys.exit too) ends the run
                return self.failed_with(g, controller_error(g, j, t, exc))
            try:
                cmds[:] = torque
                if k > 1 and np.ndim(torque) == 0:
                    raise ValueError
            except (ValueError, TypeError):
                return self.failed_with(g, controller_error(g, j, t, None, (
                    f"returned {_shape(torque)} where {k} torque(s) [N·m] were due")))
        if last:
            self.control[C_N_TICKS], self.control[C_INCLUDE_END] = 0, 1
            self.control[C_MEASURE] = 0
        self.step(self.packed.floats, self.packed.ints, rec)
        if self.control[C_STATUS] == STATUS_USER_NONFINITE:
            return self.nonfinite_error()
        return None

    def nonfinite_error(self) -> str:
        """The error of the controller whose command the step refused as non-finite (its
        status ``STATUS_USER_NONFINITE``; the tick did not advance)."""
        where = int(self.control[C_WHERE])
        j = self.tick_index
        group = next(g for g, *_ in self.views if self.users[where] in g.drives)
        name = self.plan.line.node_name(self.plan.line.drives[self.users[where]])
        return self.failed_with(group, controller_error(
            group, j, j * self.plan.dt, None, f"returned a non-finite torque "
            f"{float(self.commands[where])} for {name}"))

    def failed_with(self, group: Group, error: str) -> str:
        """Record that ``group``'s controller failed with ``error``; returns it."""
        self.failed = (group.name, error, self.tick_index * self.plan.dt)
        return error

    def outcome(self) -> UserRun:
        """Where the run stands (``UserRun``)."""
        v = self.packed.views
        failed = self.failed
        if failed is not None:
            return UserRun(int(self.control[C_STORED]), STATUS_USER_NONFINITE, failed[2], -1,
                           v["x"].copy(), v["istate"].copy(), failed[1], failed[0])
        return UserRun(int(self.control[C_STORED]), int(self.control[C_STATUS]),
                       float(v["t_fail"][0]), int(self.control[C_WHERE]), v["x"].copy(),
                       v["istate"].copy())


def run_user(plan: Plan, groups: Sequence[Group], x0: np.ndarray, istate0: np.ndarray,
             slip0: np.ndarray, n_ticks: int, substeps: int, every: int,
             buffer: np.ndarray) -> UserRun:
    """Run ``plan`` (user drives ``FAMILY_USER``) for ``n_ticks`` ticks from its state
    ``x0``, ``istate0``, ``slip0``, records every ``every`` ticks into ``buffer``; each tick
    the controllers of ``groups`` compute their drives' commands from the sampled
    measurements. A controller that raises, returns a wrong shape or a non-finite torque
    stops the run there (``UserRun.error`` names it and the tick)."""
    loop = UserLoop(plan, groups, x0, istate0, slip0, substeps, every, buffer.shape[1])
    try:
        for j in range(n_ticks + 1):
            if loop.tick(buffer, last=j == n_ticks) is not None or loop.status != L.STATUS_OK:
                break
    except KeyboardInterrupt:  # Ctrl-C between ticks: keep what was computed
        run = loop.outcome()
        run.interrupted = True
        return run
    return loop.outcome()
