"""``webline.simulate``: the front door to the compiled simulation."""

from __future__ import annotations

import math
from collections.abc import Callable
from pathlib import Path

import numpy as np

from webline.errors import LineFileError, SimulationError
from webline.line import Line, load_line
from webline.profiles import breakpoints
from webline.sim import budget, kernel
from webline.sim import layout as L
from webline.sim.plan import Plan, compile_plan, equilibrium_plan_state
from webline.sim.result import Result
from webline.units import argument

#: RK4 sub-steps are chosen so that h·|λ|max stays below this (RK4 is accurate to ~1e-4 per
#: step there and stable up to 2.78).
STEP_LIMIT = 0.5
#: Default cap on stored records; longer runs are decimated (the integration is not).
MAX_RECORDS = 200_000


#: Most RK4 sub-steps per controller period before a line is refused as too stiff.
MAX_SUBSTEPS = 200


def choose_substeps(line: Line, dt: float) -> int:
    """RK4 sub-steps per controller period ``dt`` [s]: enough for the line's fastest mode and
    for the spans round any slipping roller (``physics.slip.slip_rate``)."""
    rate = line.fastest_mode
    for i, rate_i, key in slip_rates(line):
        if dt * rate_i / STEP_LIMIT > MAX_SUBSTEPS:
            raise LineFileError(line.source, key, (
                f"web slip over {line.node_name(i)} would need a step below "
                f"{STEP_LIMIT / rate_i:.2g} s; raise the viscous traction coefficient"))
        rate = max(rate, rate_i)
    return max(1, math.ceil(dt * rate / STEP_LIMIT))


def slip_rates(line: Line) -> list[tuple[int, float, str]]:
    """(node, fastest rate [1/s], key) of the two spans round each roller that may slip."""
    from webline.physics.slip import slip_rate

    top_speed = float(np.max(breakpoints(line.spec.speed)[1]))
    out = []
    for i, roller in enumerate(line.spec.rollers):
        contact = getattr(roller, "contact", None)
        if contact is None or contact.type != "traction":
            continue
        kinetic = contact.friction if contact.kinetic_friction is None else contact.kinetic_friction
        wrap = float(getattr(roller, "wrap", 0.0))  # check_spec: a traction contact has a wrap
        rate = slip_rate(line.ea, contact.viscous, line.spec.spans[i - 1].length,
                         line.spec.spans[i].length, contact.friction, kinetic, wrap,
                         1.1 * top_speed)
        out.append((i, rate, f"rollers[{i}].contact.viscous"))
    return out


def simulate(line: Line | str | Path, duration: float | str | None = None, *,
             scenario: str | None = None, sample_rate: float | str | None = None,
             substeps: int | None = None, record_interval: float | str | None = None,
             progress: Callable[[float], None] | None = None,
             raise_on_failure: bool = True) -> Result:
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
    validity (non-finite state, unwind roll empty) it stops there and raises
    ``SimulationError`` whose ``partial`` is the ``Result`` so far (or, with
    ``raise_on_failure=False``, returns it with ``status`` set).
    """
    line = load_line(line)
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
    if substeps is None:
        substeps = choose_substeps(line, plan.dt)
    if record_interval is None:
        every = max(1, math.ceil((n_ticks + 1) / MAX_RECORDS))
    else:
        every = max(1, round(record_interval / plan.dt))
    columns = 1 + plan.n_x + 5 * plan.drives.shape[0] + line.n_nodes  # as kernel.run stores
    budget.check_work(line, budget.estimate(n_ticks, substeps, every, columns), plan.dt,
                      sample_rate_given=sample_rate is not None)
    x, istate = equilibrium_plan_state(plan)
    slipping = plan.initial_slip(x)
    chunk = n_ticks if progress is None else max(1000, math.ceil(n_ticks / 100))
    blocks, status, t_fail, done = [], L.STATUS_OK, math.nan, 0
    while done < n_ticks and status == L.STATUS_OK:
        count = min(chunk, n_ticks - done)
        last = done + count == n_ticks
        rec, n_rec, status, t_fail, x, istate, slipping = kernel.run(
            plan, x, istate, slipping, done, count, substeps, every, last)
        blocks.append(rec[:n_rec])
        done += count
        if progress is not None:
            progress(done / n_ticks)
    records = blocks[0] if len(blocks) == 1 else np.concatenate(blocks)
    result = _result(plan, records, status, t_fail,
                     {"duration": duration, "dt": plan.dt, "substeps": substeps,
                      "record_every": every})
    if status != L.STATUS_OK and raise_on_failure:
        raise SimulationError(result.message, partial=result)
    return result


def _result(plan: Plan, rec: np.ndarray, status: int, t_fail: float,
            settings: dict[str, float]) -> Result:
    n_x, n_d = plan.n_x, plan.drives.shape[0]
    text, message = "ok", ""
    if status == L.STATUS_NONFINITE:
        text, message = "diverged", f"the state stopped being finite at t = {t_fail:.4g} s"
    elif status == L.STATUS_UNWIND_EMPTY:
        text = "unwind-empty"
        message = f"the unwind roll ran out of web (reached its core) at t = {t_fail:.4g} s"
    block = [rec[:, 1 + n_x + q * n_d:1 + n_x + (q + 1) * n_d] for q in range(5)]
    slipping = rec[:, 1 + n_x + 5 * n_d:]
    return Result(
        plan=plan, time=rec[:, 0], states=rec[:, 1:1 + n_x], torque_cmd=block[0],
        speed_feedforward=block[1], trim=block[2], equilibrium_input=block[3],
        friction_estimate=block[4], slipping=slipping, status=text, message=message,
        settings=settings,
    )
