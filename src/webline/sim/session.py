"""``webline.Session``: a line driven by hand, tick by tick (co-simulation, hardware in the
loop, notebooks). The plant and the built-in controllers still run compiled between ticks
(``sim.core.user_step``); user controllers (docs/controllers.md) are called every tick."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from webline.errors import ArgumentError, ControllerError, SimulationError
from webline.line import Line, load_line
from webline.model.lines import load_line as load_any
from webline.sim.compiled_control import CompiledController
from webline.sim.core import kernel
from webline.sim.core.plan import compile_plan, equilibrium_plan_state
from webline.sim.core.session_contract import check_snapshot, session_settings
from webline.sim.core.user_step import C_STORED
from webline.sim.elements import layout as L
from webline.sim.results.failure import Failure, kernel_failure
from webline.sim.results.result import Result
from webline.sim.simulate import _result, choose_substeps
from webline.sim.user_control import (
    Group,
    UserLoop,
    builtin_stand_in,
    user_groups,
    user_plan,
)
from webline.sim.user_objects import file_controllers
from webline.spec.ranges import reference_argument, session_identity

if TYPE_CHECKING:
    from webline.model.web_graph import BranchedLine

#: records the session's buffer starts with; it doubles when full
FIRST_ROWS = 4096


@dataclass(frozen=True)
class Snapshot:
    """Everything a session needs to go back to a tick (``Session.restore``), compiled laws'
    ``state`` included; a Python controller's own memory is its to keep. ``identity``: the
    digest of the line and plan it came from (``spec.ranges.session_identity``), ``line``
    that line's name: a session of another line or plan refuses it."""

    floats: np.ndarray
    ints: np.ndarray
    records: np.ndarray
    law_states: tuple[np.ndarray, ...] = ()
    identity: str = ""
    line: str = ""


class Session:
    """``line`` at its operating point, advanced by ``step``. ``controller`` as in
    ``simulate`` (one object for every drive, or a dict per drive name); ``scenario``,
    ``sample_rate`` [Hz], ``substeps`` and ``allow_code`` (consent to the line file's own
    Python code, docs/security.md) as there, checked as there. Every tick is recorded
    (``result``). A branched line (``[[webs]]``) gives a
    ``sim.branches.user.session.BranchSession``, with the same methods and a
    ``BranchResult``.

    ``copy.deepcopy`` and ``pickle`` copy a session with its state, records and controllers
    (their memory included: they are copied, not reset; pickling needs them picklable)."""

    def __new__(cls, line: Line | str | Path | BranchedLine | None = None,
                **options: Any) -> Any:
        loaded = None if line is None else load_any(line)  # (None: a copy being made)
        if loaded is not None and loaded.branched:
            from webline.sim.branches.user.session import BranchSession
            from webline.sim.user_objects import branched_controllers

            branched = loaded
            options["controller"] = branched_controllers(branched, options.get("controller"),
                                                         options.pop("allow_code", None))
            return BranchSession(branched, **options)
        return super().__new__(cls)

    def __init__(self, line: Line | str | Path, *, controller: object | Mapping[str, object]
                 | None = None, scenario: str | None = None, sample_rate: float | None = None,
                 substeps: int | None = None, allow_code: bool | None = None) -> None:
        rate, steps = session_settings(sample_rate, substeps)
        line = load_line(line)
        if scenario is not None:
            line = line.with_scenario(scenario)
        groups = user_groups(line, controller, file_controllers(line, allow_code))
        self._start(line, rate, steps, groups, reset=True)

    def _start(self, line: Line, rate: float | None, steps: int | None,
               groups: list[Group], reset: bool) -> None:
        """Build the session of ``line`` (its scenario applied) at sample rate ``rate``
        [Hz] (None: the file's) with ``steps`` RK4 sub-steps (None: chosen) and user
        ``groups``; ``reset=False`` leaves the controllers as they are (a copy's)."""
        plan = compile_plan(line, sample_rate=rate)
        self._built = (line, rate, groups)
        self.substeps = steps or choose_substeps(builtin_stand_in(plan))
        self.plan = user_plan(plan, [d for g in groups for d in g.drives]) if groups else plan
        x, istate = equilibrium_plan_state(self.plan)
        self._width = kernel.record_width(self.plan.n_x, self.plan.drives.shape[0],
                                          self.plan.nodes.shape[0])
        self._rec = np.empty((FIRST_ROWS, self._width))
        self._loop = UserLoop(self.plan, groups, x, istate, kernel.initial_slip(self.plan, x),
                              self.substeps, 1, self._width, reset=reset)
        self._views = self._loop.packed.views
        #: the compiled laws, whose memory (``state``) snapshots keep
        self._laws = [g.controller for g in groups if isinstance(g.controller,
                                                                  CompiledController)]
        self.identity = session_identity(
            line.spec.model_dump_json(exclude_none=True), self.plan.dt, self.substeps,
            [(g.name, g.drives) for g in groups])

    def __getstate__(self) -> dict[str, Any]:
        line, rate, groups = self._built
        return {"line": line, "rate": rate, "substeps": self.substeps, "groups": groups,
                "snapshot": self.snapshot()}

    def __setstate__(self, state: dict[str, Any]) -> None:
        self._start(state["line"], state["rate"], state["substeps"], state["groups"],
                    reset=False)
        self.restore(state["snapshot"])

    @property
    def t(self) -> float:
        """Time [s] of the state: ticks done x the sample period."""
        return self._loop.tick_index * self.plan.dt

    def step(self, n: int = 1) -> None:
        """Advance ``n`` controller ticks. ``SimulationError`` (``partial``: the run so far)
        if the line leaves physical validity, ``ControllerError`` if a user controller
        fails; the session cannot go on from either but by ``restore``."""
        if n < 0:
            raise ArgumentError(f"step: n must be >= 0, got {n}")
        for _ in range(n):
            stored = int(self._loop.control[C_STORED])
            if stored + 2 > len(self._rec):
                self._rec = np.concatenate([self._rec, np.empty_like(self._rec)])
            error = self._loop.tick(self._rec)
            if error is not None:
                raise ControllerError(error, partial=self.result())
            if self._loop.status != L.STATUS_OK:
                result = self.result()
                raise SimulationError(result.message, partial=result)

    @property
    def state(self) -> dict[str, float]:
        """The plant's state by name (``plan.state_names``, SI) at ``t``."""
        return dict(zip(self.plan.state_names, self._views["x"].tolist(), strict=True))

    @property
    def measurements(self) -> dict[str, float]:
        """What the line's sensors would read at ``t`` without noise: every span's tension
        [N] (``"<span>.tension"``: what its rollers feel, 0 while slack or broken, as a
        ``Result``'s ``tension``) and every roller's surface speed [m/s]
        (``"<node>.speed"``), and the user drives' sampled measurements (noise included) by
        the names of docs/controllers.md, prefixed ``"measured."``."""
        line, x, off = self.plan.line, self._views["x"], self.plan.offsets
        if off[L.O_KV]:  # a damper or a nonlinear law: the kernel's own felt tensions
            from webline.sim.core.viscoelastic import felt_tension

            tension = felt_tension(self.plan, np.array([self.t]), x[None, :],
                                   self._views["slip"][None, :].astype(float))[0]
        else:  # a slack span carries nothing (its stretch is negative)
            tension = np.maximum(x[:line.n_spans], 0.0)
        out = {f"{line.span_name(k)}.tension": float(tension[k]) for k in range(line.n_spans)}
        for i in range(line.n_nodes):
            radius = (x[off[L.O_RADIUS]] if i == 0 else x[off[L.O_RADIUS] + 1]
                      if i == line.n_nodes - 1 else self.plan.nodes[i, L.N_RADIUS])
            out[f"{line.node_name(i)}.speed"] = float(radius * x[off[L.O_OMEGA] + i])
        for g, meas, _refs, _cmds, _k in self._loop.views:
            names = [f"{line.node_name(line.drives[d])}.{m}" for d in g.drives
                     for m in ("speed", "tension", "radius", "inertia")]
            out |= {f"measured.{n}": float(v) for n, v in zip(names, meas, strict=True)}
        return out

    def set_reference(self, name: str, value: float | str) -> None:
        """From now on, hold reference ``name`` at ``value`` [SI, or a string with units]:
        ``"speed"`` (the line speed [m/s]) or a zone's tension [N] by the name of its
        loadcell span (``"<span>.tension"``), in the ranges of the line file's ``speed``
        and ``spans[].tension`` (``spec.ranges.reference_argument``). The reference steps
        there at the next tick."""
        line = self.plan.line
        value = reference_argument(name, value) if name == "speed" or name.endswith(
            ".tension") else value
        if name == "speed":
            p = 0
        else:
            spans = [f"{line.span_name(z.loadcell)}.tension" for z in line.zones]
            if name not in spans:
                raise ArgumentError(f"set_reference: no reference {name!r}; there are "
                                    f"speed, {', '.join(spans)}")
            p = 1 + spans.index(name)
        off = self._views["prof_off"]
        self._views["prof_v"][off[p]:off[p + 1]] = value

    def apply(self, changes: Mapping[str, float]) -> None:
        """A disturbance: add each value [SI] to the named state now (``state`` names, e.g.
        ``{"span2.stretch": 50.0}`` a 50 N tension kick, ``{"idle1.omega": -1.0}``)."""
        names = list(self.plan.state_names)
        for name, delta in changes.items():
            if name not in names:
                raise ArgumentError(f"apply: no state {name!r}; the states are "
                                    f"{', '.join(names)}")
            self._views["x"][names.index(name)] += float(delta)

    def snapshot(self) -> Snapshot:
        """The session now (state, controller memory, references, records)."""
        stored = int(self._loop.control[C_STORED])
        return Snapshot(self._loop.packed.floats.copy(), self._loop.packed.ints.copy(),
                        self._rec[:stored].copy(),
                        tuple(law.state.copy() for law in self._laws), self.identity,
                        self.plan.line.name)

    def restore(self, snap: Snapshot) -> None:
        """Go back to ``snap`` (of this session, or of a copy of it; another line's or
        plan's is refused in one line, ``ArgumentError``)."""
        check_snapshot(snap, Snapshot, self.identity, self.plan.line.name)
        self._loop.packed.floats[:] = snap.floats
        self._loop.packed.ints[:] = snap.ints
        for law, state in zip(self._laws, snap.law_states, strict=True):
            law.state[:] = state
        self._rec = np.empty((max(FIRST_ROWS, 2 * len(snap.records) + 2), self._width))
        self._rec[:len(snap.records)] = snap.records
        self._loop.failed = None

    def result(self) -> Result:
        """The ``Result`` of the ticks run so far."""
        run = self._loop.outcome()
        failure = kernel_failure(self.plan, run.status, run.t_fail, run.where, run.x) \
            if run.error is None else Failure("controller", run.controller, run.t_fail,
                                              run.error)
        records = self._rec[:run.stored].copy()
        return _result(self.plan, records, failure,
                       {"duration": self.t, "dt": self.plan.dt, "substeps": self.substeps,
                        "record_every": 1},
                       (float(run.istate[0, L.I_DETECT]), int(run.istate[0, L.I_METHOD]))
                       if len(run.istate) else (-1.0, 0))
