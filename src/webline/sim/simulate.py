"""``webline.simulate``: the front door to the compiled simulation."""

from __future__ import annotations

import math
import signal
import threading
import time
from collections.abc import Callable, Iterator, Mapping
from contextlib import contextmanager
from pathlib import Path
from typing import TYPE_CHECKING, overload

import numpy as np

from webline.errors import (
    ControllerError,
    LineFileError,
    SimulationError,
    SimulationInterrupted,
)
from webline.line import Line
from webline.model.lines import load_line
from webline.sim.compiled_control import CompiledController, run_compiled
from webline.sim.core import kernel
from webline.sim.core.plan import Plan, compile_plan, equilibrium_plan_state
from webline.sim.core.session_contract import session_settings
from webline.sim.elements import layout as L
from webline.sim.elements.web_state import slip_column
from webline.sim.linear import budget
from webline.sim.linear.fastest import slip_rates
from webline.sim.linear.linearize import fastest_mode
from webline.sim.linear.steps import STEP_LIMIT, record_every, substeps_for, too_stiff
from webline.sim.results.failure import Failure, kernel_failure
from webline.sim.results.result import Result
from webline.sim.user_control import Group, builtin_stand_in, run_user, user_groups, user_plan
from webline.sim.user_objects import file_controllers
from webline.spec.ranges import argument, whole_argument

if TYPE_CHECKING:  # a single-path run does not import the branched line's modules
    from webline.model.web_graph import BranchedLine
    from webline.sim.branches.result import BranchResult



#: Ticks of the first chunk of a run; later chunks are sized from its wall time.
FIRST_CHUNK = 2000
#: Wall time a chunk aims at [s]: the compiled loop only returns to Python (where Ctrl-C is
#: seen) between chunks, so this bounds the delay of an interrupt; the overhead of a chunk is
#: a few microseconds, negligible at this size.
CHUNK_SECONDS = 0.1
#: ``status`` code of a run stopped by KeyboardInterrupt (the kernel's codes are >= 0).
STATUS_INTERRUPTED = -1

def choose_substeps(plan: Plan, rate: float | None = None) -> int:
    """RK4 sub-steps per controller period ``plan.dt`` [s]: enough for the plan's fastest mode
    (``rate`` [1/s] if already known, else ``linearize.fastest_mode``) and for the spans round
    any slipping roller (``physics.slip.slip_rate``)."""
    line, dt = plan.line, plan.dt
    rate = fastest_mode(plan) if rate is None else rate
    for i, rate_i, key in slip_rates(line):
        if too_stiff(rate_i, dt):
            raise LineFileError(line.source, key, (
                f"web slip over {line.node_name(i)} would need a step below "
                f"{STEP_LIMIT / rate_i:.2g} s; raise the viscous traction coefficient"))
        rate = max(rate, rate_i)
    return substeps_for(rate, dt)


def next_chunk(count: int, seconds: float, n_ticks: int, progress: bool) -> int:
    """Ticks of the next chunk after ``count`` ticks took ``seconds`` [s] of wall time: about
    ``CHUNK_SECONDS`` of work, at least ``FIRST_CHUNK // 4`` (a first chunk slowed by
    compiling the loop only makes the second one small); with a progress bar also at most 1 %
    of the run."""
    rate = count / max(seconds, 1e-6)
    chunk = max(FIRST_CHUNK // 4, int(rate * CHUNK_SECONDS))
    if progress:
        chunk = min(chunk, max(1000, math.ceil(n_ticks / 100)))
    return chunk


@contextmanager
def deferred_interrupt() -> Iterator[Callable[[], int]]:
    """Within the block, a first Ctrl-C (SIGINT) only records the signal (the yielded function
    returns its number, 0 before any), so the chunk loop stops cleanly after the chunk under
    way, keeping its records; a second Ctrl-C raises KeyboardInterrupt at once (e.g. while the
    loop still compiles). Only where Python's default SIGINT handler is in place in the main
    thread; elsewhere the function returns 0 and Ctrl-C raises as usual. A SIGTERM handled by
    ``webline.errors.terminate_as_interrupt`` arrives here as Ctrl-C does, with its own number."""
    pressed: list[int] = []
    default = signal.default_int_handler
    if (threading.current_thread() is not threading.main_thread()
            or signal.getsignal(signal.SIGINT) is not default):
        yield lambda: 0
        return

    def handler(signum: int, frame: object) -> None:
        if pressed:
            default(signum, frame)  # type: ignore[arg-type]
        pressed.append(signum)

    signal.signal(signal.SIGINT, handler)
    try:
        yield lambda: pressed[0] if pressed else 0
    finally:
        signal.signal(signal.SIGINT, default)


def interrupt_text(signum: int, end: float) -> str:
    """Why a run stopped at ``end`` [s] on signal ``signum`` (SIGINT: Ctrl-C, or SIGTERM)."""
    if signum == signal.SIGTERM:
        return f"stopped by SIGTERM (a scheduler's or kill's stop) at t = {end:.4g} s"
    return f"interrupted by the user (Ctrl-C) at t = {end:.4g} s"


@overload
def simulate(line: BranchedLine, duration: float | str | None = None, *,
             scenario: str | None = None, sample_rate: float | str | None = None,
             substeps: int | None = None, record_interval: float | str | None = None,
             progress: Callable[[float], None] | None = None,
             raise_on_failure: bool = True,
             controller: object | Mapping[str, object] | None = None,
             allow_code: bool | None = None) -> BranchResult: ...


@overload
def simulate(line: Line | str | Path, duration: float | str | None = None, *,
             scenario: str | None = None, sample_rate: float | str | None = None,
             substeps: int | None = None, record_interval: float | str | None = None,
             progress: Callable[[float], None] | None = None,
             raise_on_failure: bool = True,
             controller: object | Mapping[str, object] | None = None,
             allow_code: bool | None = None) -> Result: ...


def simulate(line: Line | BranchedLine | str | Path, duration: float | str | None = None, *,
             scenario: str | None = None, sample_rate: float | str | None = None,
             substeps: int | None = None, record_interval: float | str | None = None,
             progress: Callable[[float], None] | None = None,
             raise_on_failure: bool = True,
             controller: object | Mapping[str, object] | None = None,
             allow_code: bool | None = None,
             ) -> Result | BranchResult:
    """Simulate ``line`` for ``duration`` [s] from equilibrium at its initial references.

    ``duration``, ``sample_rate`` and ``record_interval`` take numbers [SI], strings with
    units (``"2 min"``, ``"500 Hz"``) or pint quantities; a wrong one raises ``ArgumentError``.
    A run that would need more than ``budget.MAX_RK4_STEPS`` RK4 steps or
    ``budget.MAX_RECORD_BYTES`` of records is refused (``LineFileError`` naming the key).
    ``scenario`` applies a named scenario of the line file (its duration is the default);
    ``sample_rate`` [Hz] overrides the controllers' rate; ``substeps`` the RK4 sub-steps per
    controller period (default: from the fastest mode); ``record_interval`` [s] how often the
    state is stored (default every tick, up to 200 000 records). ``progress``, if given, is
    called with the fraction done (0..1) as the run proceeds in chunks. If the run leaves physical
    validity (a runaway out of the line's physical envelope, a non-finite state, the unwind
    roll empty, a tension beyond ``web.strength``) it stops there and raises
    ``SimulationError`` whose ``partial`` is the ``Result`` so far (or, with
    ``raise_on_failure=False``, returns it with its ``failure`` set). The run's ``verdict``
    also covers warnings (``webline.sim.results.events``) and the linear stability of the line.

    The run goes in chunks of about 0.1 s of wall time, so Ctrl-C is seen within a chunk: it
    stops the run after that chunk, and the ``Result`` so far has ``status`` "interrupted"; it
    is raised as ``SimulationInterrupted`` (a KeyboardInterrupt, ``partial`` = the result) or,
    with ``raise_on_failure=False``, returned. A second Ctrl-C (e.g. while the loop still
    compiles) raises a plain KeyboardInterrupt at once.

    ``controller``: a user's controller (docs/controllers.md) for every drive, or a dict
    drive name -> controller; drives the line file gives ``type = "python"`` run theirs. The
    run then goes one tick at a time through Python (``sim.user_control``), or, where every
    user controller is a ``CompiledController``, in the compiled loop; a controller that
    raises or returns a wrong shape or a non-finite torque stops it with ``ControllerError``
    (``partial``: the run so far). The step is chosen for the line with its built-in
    controllers in place of the user's (``substeps`` overrides it).

    ``allow_code``: consent to import the Python code the line file names (its
    ``type = "python"`` controllers) from the line file's own folder; None: as the
    surrounding ``spec.code_consent.allowing_code`` says, or the per-user allow-list
    (docs/security.md). Without consent such a line is refused (``LineFileError``) before
    anything is imported. Objects passed as ``controller`` are the caller's own: no consent.

    A branched line (``[[webs]]``; docs/branching.md) runs through
    ``sim.branches`` and returns a ``BranchResult`` (an xarray Dataset and a verdict per web
    and lane; a user ``controller`` per drive or for all, docs/controllers.md "On a branched
    line"); ``progress`` is called there too, after each chunk of the run.
    """
    line = load_line(line)
    if line.branched:
        from webline.sim.branches.run import simulate_branches  # scipy: only when needed
        from webline.sim.user_objects import branched_controllers

        sample_rate, substeps = session_settings(sample_rate, substeps)  # (as the chain's)
        controller = branched_controllers(line, controller, allow_code)  # (and the file's)
        return simulate_branches(line, duration, scenario=scenario,
                                 sample_rate=sample_rate, substeps=substeps,
                                 record_interval=record_interval,
                                 raise_on_failure=raise_on_failure, controller=controller,
                                 progress=progress)
    duration, sample_rate, record_interval = (  # units and checks as the CLI's
        None if value is None else argument(value, kind, name, within=key)
        for value, kind, name, key in ((duration, "time", "duration", "scenario.duration"),
                                       (sample_rate, "frequency", "sample_rate",
                                        "control.sample_rate"),
                                       (record_interval, "time", "record_interval", None)))
    if scenario is not None:
        line = line.with_scenario(scenario)
        if duration is None:
            duration = line.spec.scenarios[scenario].duration
    if duration is None:
        duration = 10.0
    plan = compile_plan(line, sample_rate=sample_rate)
    n_ticks = max(1, round(duration / plan.dt))
    groups = user_groups(line, controller, file_controllers(line, allow_code))
    if substeps is None:
        substeps = choose_substeps(builtin_stand_in(plan))
    else:
        substeps = whole_argument(substeps, "substeps", 1,
                                  "expected a whole number of RK4 steps per controller period")
    every = record_every(n_ticks, plan.dt, record_interval)
    columns = kernel.record_width(plan.n_x, plan.drives.shape[0], line.n_nodes)
    budget.check_work(line, budget.estimate(n_ticks, substeps, every, columns), plan.dt,
                      sample_rate_given=sample_rate is not None)
    x, istate = equilibrium_plan_state(plan)
    slipping = kernel.initial_slip(plan, x)
    # one buffer for the whole run, filled chunk by chunk (no concatenation)
    buffer = np.empty((n_ticks // every + 2, kernel.record_width(
        plan.n_x, plan.drives.shape[0], plan.nodes.shape[0])))
    if groups:
        return _user_result(user_plan(plan, [d for g in groups for d in g.drives]), groups,
                            x, istate, slipping, n_ticks, substeps, every, buffer,
                            {"duration": duration, "dt": plan.dt, "substeps": substeps,
                             "record_every": every}, raise_on_failure)
    status, t_fail, where, done, stored = L.STATUS_OK, math.nan, -1, 0, 0
    chunk = FIRST_CHUNK
    if progress is not None:
        chunk = min(chunk, max(1000, math.ceil(n_ticks / 100)))
    signum = 0  # the signal that stopped the run, if one did
    with deferred_interrupt() as interrupted:
        try:
            while done < n_ticks and status == L.STATUS_OK and not interrupted():
                count = min(chunk, n_ticks - done)
                last = done + count == n_ticks
                started = time.perf_counter()
                _, n_rec, status, t_fail, where, x, istate, slipping = kernel.run(
                    plan, x, istate, slipping, done, count, substeps, every, last,
                    buffer[stored:])
                stored += n_rec
                done += count
                chunk = next_chunk(count, time.perf_counter() - started, n_ticks,
                                   progress is not None)
                if progress is not None:
                    progress(done / n_ticks)
        except KeyboardInterrupt as stop:  # where no deferring handler could be installed
            if not stored:
                raise  # nothing computed yet: a plain Ctrl-C
            status = STATUS_INTERRUPTED
            signum = getattr(stop, "signum", 0) or interrupted() or signal.SIGINT
        if interrupted() and status == L.STATUS_OK and done < n_ticks:
            status = STATUS_INTERRUPTED
        signum = signum or interrupted()
    # a run that stopped early keeps only its records, not the whole buffer
    records = buffer[:stored] if stored >= len(buffer) - 2 else buffer[:stored].copy()
    if status == STATUS_INTERRUPTED:
        end = float(records[-1, 0]) if len(records) else 0.0
        failure: Failure | None = Failure(
            "interrupted", line.name, end, interrupt_text(signum, end))
    else:
        failure = kernel_failure(plan, status, t_fail, where, x)
    result = _result(plan, records, failure,
                     {"duration": duration, "dt": plan.dt, "substeps": substeps,
                      "record_every": every},
                     (float(istate[0, L.I_DETECT]), int(istate[0, L.I_METHOD]))
                     if len(istate) else (-1.0, 0))
    if status == STATUS_INTERRUPTED and raise_on_failure:
        raise SimulationInterrupted(result.message, partial=result)
    if failure is not None and raise_on_failure:
        raise SimulationError(result.message, partial=result)
    return result


def _user_result(plan: Plan, groups: list[Group], x: np.ndarray, istate: np.ndarray,
                 slipping: np.ndarray, n_ticks: int, substeps: int, every: int,
                 buffer: np.ndarray, settings: dict[str, float],
                 raise_on_failure: bool) -> Result:
    """``simulate`` with user controllers (``sim.user_control.run_user``)."""
    if all(isinstance(g.controller, CompiledController) for g in groups):  # in the loop
        run = run_compiled(plan, groups, x, istate, slipping, n_ticks, substeps, every, buffer)
    else:  # one tick at a time through Python (a compiled law called from there)
        run = run_user(plan, groups, x, istate, slipping, n_ticks, substeps, every, buffer)
    if run.error is not None and run.stored == 0:  # (a reset failed): the start alone
        run.stored = kernel.run(builtin_stand_in(plan), x.copy(), istate.copy(),
                                slipping.copy(), 0, 0, substeps, every, True, buffer)[1]
    records = buffer[:run.stored].copy() if run.stored < len(buffer) - 2 else buffer[:run.stored]
    if run.interrupted and run.error is None:
        end = float(records[-1, 0]) if len(records) else 0.0
        failure: Failure | None = Failure("interrupted", plan.line.name, end,
                                          interrupt_text(signal.SIGINT, end))
    elif run.error is not None:
        failure = Failure("controller", run.controller, run.t_fail, run.error)
    else:
        failure = kernel_failure(plan, run.status, run.t_fail, run.where, run.x)
    result = _result(plan, records, failure, settings,
                     (float(run.istate[0, L.I_DETECT]), int(run.istate[0, L.I_METHOD]))
                     if len(run.istate) else (-1.0, 0))
    if run.interrupted and run.error is None and raise_on_failure:
        raise SimulationInterrupted(result.message, partial=result)
    if run.error is not None and raise_on_failure:
        raise ControllerError(run.error, partial=result)
    if failure is not None and raise_on_failure:
        raise SimulationError(result.message, partial=result)
    return result


def _result(plan: Plan, rec: np.ndarray, failure: Failure | None,
            settings: dict[str, float], monitor: tuple[float, int] = (-1.0, 0)) -> Result:
    n_x, n_d = plan.n_x, plan.drives.shape[0]
    block = [rec[:, 1 + n_x + q * n_d:1 + n_x + (q + 1) * n_d] for q in range(6)]
    n_n = plan.nodes.shape[0]
    col = slip_column(n_x, n_d)
    slipping = rec[:, col:col + n_n]
    adapted = rec[:, col + n_n:].reshape(len(rec), n_d, 3)
    mrac = (plan.drives[:, L.D_FAMILY] == L.FAMILY_MRAC)[None, :, None]
    return Result(
        plan=plan, time=rec[:, 0], states=rec[:, 1:1 + n_x], torque_cmd=block[0],
        speed_feedforward=block[1], trim=block[2], equilibrium_input=block[3],
        friction_estimate=block[4], control_radius=block[5], slipping=slipping,
        mrac_gains=np.where(mrac, adapted, np.nan), failure=failure, settings=settings,
        break_monitor=monitor,
    )
