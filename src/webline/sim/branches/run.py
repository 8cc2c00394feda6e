"""``simulate_branches``: run a branched line from its operating point (docs/branching.md)."""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from pathlib import Path

import numpy as np

from webline.errors import ControllerError, SimulationError
from webline.model.web_graph import BranchedLine, load_branched
from webline.sim.branches.drives.decentral import prepare, start_memory
from webline.sim.branches.drives.draw import fill_draw
from webline.sim.branches.drives.observer import start_observers
from webline.sim.branches.equilibrium import BranchPoint, operating_point
from webline.sim.branches.findings.break_verdict import detection
from webline.sim.branches.findings.web_findings import strength_failure
from webline.sim.branches.linear import fastest_rate
from webline.sim.branches.loop import layout as B
from webline.sim.branches.loop.kernel import new_records
from webline.sim.branches.plan import BranchPlan, compile_branches
from webline.sim.branches.result import BranchResult
from webline.sim.branches.sensor_views import start_sensors
from webline.sim.branches.winder import initial_compensation
from webline.sim.linear.steps import MAX_SUBSTEPS, record_every, substeps_for
from webline.spec.ranges import argument, whole_argument

#: controller ticks per call of the compiled loop (a run returns to Python between two)
CHUNK = 20_000


def simulate_branches(line: BranchedLine | str | Path, duration: float | str | None = None, *,
                      scenario: str | None = None, sample_rate: float | str | None = None,
                      substeps: int | None = None, record_interval: float | str | None = None,
                      raise_on_failure: bool = True,
                      controller: object | Mapping[str, object] | None = None,
                      progress: Callable[[float], None] | None = None) -> BranchResult:
    """Simulate a branched line for ``duration`` [s] from its operating point at t = 0.

    Arguments as ``webline.simulate`` (``scenario`` applies a named scenario, whose duration
    is the default; ``substeps`` RK4 steps per controller period, default from the fastest
    mode of its open- and closed-loop linear models, ``sim.branches.linear``). A run that
    leaves physical validity (non-finite state, an empty unwind, a runaway) raises
    ``SimulationError`` with the run so far as ``partial`` (or, with
    ``raise_on_failure=False``, returns it with its ``failure`` set). ``controller``: a
    user's controller for every drive or a dict drive name -> controller (docs/controllers.md,
    "On a branched line"; ``sim.branches.user``): the run goes one tick at a time through
    Python, and a controller that fails stops it with ``ControllerError``. ``progress``, if
    given, is called with the fraction done (0..1) after each chunk (then at most 1 % of the
    run, as the chain's).
    """
    line = load_branched(line)
    duration = None if duration is None else argument(duration, "time", "duration")
    rate = None if sample_rate is None else argument(sample_rate, "frequency", "sample_rate")
    every_s = None if record_interval is None else argument(record_interval, "time",
                                                            "record_interval")
    if scenario is not None:
        line = line.with_scenario(scenario)
        if duration is None:
            duration = line.spec.scenarios[scenario].duration
    duration = 10.0 if duration is None else duration
    plan, point, substeps = plan_and_step(line, rate, substeps)
    n_ticks = max(1, round(duration / plan.dt))
    every = record_every(n_ticks, plan.dt, every_s)
    x, istate, wound, done, cmd = run_start(plan, point)
    rec = new_records(n_ticks, every, plan.n_x, plan.di.shape[0])
    users = None
    if controller is not None:  # user controllers: one tick at a time (sim.branches.user)
        from webline.sim.branches.user.loop import BranchUserLoop, branch_groups

        users = BranchUserLoop(plan, point, branch_groups(line, controller), x, istate, wound,
                               done, cmd, substeps, every, in_loop=True)
        plan, (x, istate, wound, done, cmd) = users.plan, users.live
    status, t_fail, n_rec, tick = B.STATUS_OK, math.nan, 0, 0
    interrupted = False
    chunk = CHUNK if progress is None else min(CHUNK, max(1000, math.ceil(n_ticks / 100)))
    try:  # in chunks: Ctrl-C is seen between two, and the run keeps what it computed
        while tick < n_ticks and status == B.STATUS_OK:
            count = min(chunk, n_ticks - tick)
            if users is None:
                stored, status, t_fail = plan.run(x, istate, wound, done, rec[n_rec:], cmd,
                                                  tick, count, substeps, every,
                                                  tick + count == n_ticks)
            else:
                stored, status, t_fail, count = users.ticks(rec[n_rec:], tick, count,
                                                            tick + count == n_ticks)
            n_rec += stored
            tick += count
            if progress is not None:
                progress(tick / n_ticks)
    except KeyboardInterrupt:
        if users is not None:  # (the ticks of the user run's chunk so far)
            n_rec += users.stored_in_chunk
        if not n_rec:
            raise
        interrupted = True
    if users is not None and users.failed is not None and not n_rec:  # (a reset failed)
        rec[0] = users.sample(0)[0]  # the start alone
        n_rec = 1
    failure = (users.failed[1] if status not in (B.STATUS_OK, B.STATUS_STRENGTH)
               and users is not None and users.failed is not None
               else run_failure(plan, x, status, t_fail))
    if interrupted:
        failure = f"interrupted by the user (Ctrl-C) at t = {rec[n_rec - 1, 0]:.4g} s"
    result = run_result(plan, rec[:n_rec].copy(), failure, istate[:plan.di.shape[0]],
                        duration, substeps, every)  # (the drives' memory: no laws' rows)
    if failure is not None and raise_on_failure:
        if users is not None and users.failed is not None:
            raise ControllerError(f"{line.name}: {failure}", partial=result)
        raise SimulationError(f"{line.name}: {failure}", partial=result)
    return result


def plan_and_step(line: BranchedLine, rate: float | None,
                  substeps: int | None) -> tuple[BranchPlan, BranchPoint, int]:
    """``line``'s plan at sample rate ``rate`` [Hz] (None: the file's), its operating point
    at t = 0 and the RK4 sub-steps per controller period (``substeps``, or chosen from the
    fastest mode of its linear models, with the file's controllers)."""
    plan = compile_branches(line, rate)
    prepare(plan)  # the decentralized drives' designs and references (none: nothing)
    point = operating_point(plan)
    fill_draw(plan, point)  # the PI drives' draw follows their references (loop.draw)
    if substeps is None:
        substeps = substeps_for(fastest_rate(plan, point), plan.dt)
        if substeps > MAX_SUBSTEPS:
            raise SimulationError(f"{line.name}: the line's fastest mode needs {substeps} "
                                  f"RK4 steps per controller period (at most {MAX_SUBSTEPS})")
    else:
        substeps = whole_argument(substeps, "substeps", 1, "expected a whole number")
    return plan, point, substeps


def start_state(plan: BranchPlan, point: BranchPoint) -> tuple[np.ndarray, np.ndarray]:
    """The state and controller memory a run of ``plan`` starts from at ``point`` (sets the
    drives' speed feedforward ``D_FF`` in ``plan``)."""
    plan.df[:, B.D_FF] = point.ratio
    x = point.x.copy()
    istate = np.zeros((plan.di.shape[0], B.I_COLS))
    istate[:, B.I_SPEED] = point.torque  # the speed integrators hold the torques
    istate[:, B.I_SPEED] -= initial_compensation(plan, point)  # (less a winder's, W3)
    istate[:, B.I_RADIUS] = plan.radius0
    istate[:, B.I_DETECT] = -1.0  # no web break detected yet
    start_memory(plan, istate)  # the decentralized families' (sim.branches.drives.decentral)
    start_observers(plan, istate, x)  # (section observers: at the initial state)
    start_sensors(plan, point.torque, x, istate)  # (delays full, an encoder's scale trimmed)
    return x, istate


def run_start(plan: BranchPlan, point: BranchPoint) -> tuple[np.ndarray, ...]:
    """What ``kernel.advance`` advances in place from the start of a run of ``plan`` at
    ``point``: the state, the controller memory (``start_state``), the wound-in tensions and
    drags, the roll changes made (none) and the torque commands (the operating point's)."""
    x, istate = start_state(plan, point)
    return x, istate, plan.wound.copy(), np.zeros(len(plan.events)), point.torque.copy()


def run_failure(plan: BranchPlan, x: np.ndarray, status: int, t_fail: float) -> str | None:
    """Why a run of ``plan`` that ended with ``status`` (``layout`` STATUS_*) at ``t_fail``
    [s] in state ``x`` stopped, in words; None for a run that ran to its end."""
    if status == B.STATUS_OK:
        return None
    if status == B.STATUS_STRENGTH:
        return strength_failure(plan, x, t_fail)
    return _failure_text(status, t_fail)


def run_result(plan: BranchPlan, records: np.ndarray, failure: str | None,
               istate: np.ndarray, duration: float, substeps: int,
               every: int) -> BranchResult:
    """The ``BranchResult`` of a run of ``plan`` for ``duration`` [s] that stored
    ``records`` and ended with controller memory ``istate``."""
    return BranchResult(plan, records, failure,
                        {"duration": duration, "dt": plan.dt, "substeps": substeps,
                         "record_every": every, **detection(plan, istate)})


def _failure_text(status: int, t_fail: float) -> str:
    what = {B.STATUS_NONFINITE: "the state stopped being finite",
            B.STATUS_UNWIND_EMPTY: "an unwind roll ran out of web",
            B.STATUS_RUNAWAY: "a runaway: a strain beyond 5 % or a speed beyond 3x the top "
                              "reference"}[status]
    return f"{what} at t = {t_fail:.4g} s"
