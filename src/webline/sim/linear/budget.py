"""The work of a run, estimated before it starts, and refused beyond a bound.

A run costs ``ticks x sub-steps`` RK4 steps (ticks at the controllers' sample rate,
sub-steps set by the line's fastest mode) and ``records x columns x 8`` bytes of records.
The compiled loop does ~1e7 RK4 steps a second on one core for a 20-state line, so the
bound of ``MAX_RK4_STEPS`` = 2e9 steps is several minutes; ``MAX_RECORD_BYTES`` = 4 GB of
records is what a laptop can hold twice (the records and the result built from them). Beyond
either, the run is refused with a ``LineFileError`` naming the key that drives the cost: the
sample rate, or the key behind the fastest mode (a span's length, a drive's torque lag, a
transmission's stiffness, ...), found from the participation of the states in that mode.

A study (sweep, Monte Carlo) is checked before anything runs: its case count first, before
anything is allocated (``webline.limits.check_case_count``), then each probed case as a run
(``sim.sweeps.study_work``), then the whole (``check_study``: ``MAX_STUDY_RK4_STEPS``, which
``work_limit=False`` lifts, and ``limits.MAX_STUDY_BYTES``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from webline.errors import ArgumentError, LineFileError
from webline.limits import MAX_STUDY_BYTES
from webline.line import Line

#: Most RK4 steps (ticks x sub-steps) a run may take.
MAX_RK4_STEPS = 2_000_000_000
#: Most bytes of stored records a run may need.
MAX_RECORD_BYTES = 4_000_000_000


@dataclass(frozen=True)
class Work:
    """The estimated work of one run."""

    ticks: int
    substeps: int
    records: int
    columns: int

    @property
    def rk4_steps(self) -> int:
        return self.ticks * self.substeps

    @property
    def record_bytes(self) -> int:
        return self.records * self.columns * 8


def estimate(ticks: int, substeps: int, every: int, columns: int) -> Work:
    """The work of a run of ``ticks`` controller periods with ``substeps`` RK4 steps each,
    storing every ``every``-th tick in rows of ``columns`` floats."""
    return Work(ticks, substeps, ticks // every + 2, columns)


def check_work(line: Line, work: Work, dt: float, *, sample_rate_given: bool = False) -> None:
    """Raise ``LineFileError`` naming the key that drives the cost when ``work`` is beyond
    ``MAX_RK4_STEPS`` or ``MAX_RECORD_BYTES``; ``dt`` [s] is the controller period."""
    rate = "the sample_rate argument" if sample_rate_given else "control.sample_rate"
    duration = work.ticks * dt
    if work.rk4_steps > MAX_RK4_STEPS:
        if work.substeps > 1:
            key, why = fastest_mode_key(line)
            problem = (f"a {duration:.4g} s run needs {work.rk4_steps:.3g} RK4 steps "
                       f"({work.ticks} ticks x {work.substeps} sub-steps), more than "
                       f"{MAX_RK4_STEPS:.0e}: the step is set by the line's fastest mode, "
                       f"{why}; check this value or run for less time")
        else:
            key = rate
            problem = (f"a {duration:.4g} s run at {1 / dt:.4g} Hz needs {work.rk4_steps:.3g} "
                       f"RK4 steps, more than {MAX_RK4_STEPS:.0e}; lower the sample rate or "
                       "run for less time")
        raise LineFileError(line.source, key, problem)
    if work.record_bytes > MAX_RECORD_BYTES:
        raise LineFileError(line.source, "record_interval", (
            f"{work.records} records of {work.columns} values need "
            f"{work.record_bytes / 1e9:.3g} GB, more than {MAX_RECORD_BYTES / 1e9:.3g} GB; "
            "record less often or run for less time"))


def state_keys(line: Line) -> dict[str, str]:
    """Linear-model state name -> the line-file key that sets how fast that state moves."""
    keys: dict[str, str] = {}
    for k in range(line.n_spans):
        keys[f"{line.span_name(k)}_tension"] = f"spans[{k}].length"
    for i in range(line.n_nodes):
        name, here = line.node_name(i), f"rollers[{i}]"
        keys[f"{name}_omega"] = f"{here}.inertia"
        keys[f"{name}_torque"] = f"{here}.drive.torque_lag"
        keys[f"{name}_motor_omega"] = f"{here}.drive.transmission.stiffness"
        keys[f"{name}_twist"] = f"{here}.drive.transmission.stiffness"
        keys[f"{name}_speed_integral"] = f"{here}.controller.speed_bandwidth"
        keys[f"{name}_tension_integral"] = f"{here}.controller.tension_bandwidth"
    return keys


def fastest_mode_key(line: Line) -> tuple[str, str]:
    """(key, description) of the state that dominates the line's fastest mode (largest
    |eigenvalue| of the open- and closed-loop models), by its participation factor
    |v_i w_i| (unit-free, unlike the eigenvector itself)."""
    from webline.sim.linear.fastest import slip_rates
    from webline.sim.linear.linearize import linear_model

    best: tuple[float, str, str] = (0.0, "", "")
    for loop in ("open", "closed"):
        model = linear_model(line, loop=loop)
        values, vectors = np.linalg.eig(model.a)
        k = int(np.argmax(np.abs(values)))
        if abs(values[k]) <= best[0]:
            continue
        try:
            left = np.linalg.inv(vectors)[k]
        except np.linalg.LinAlgError:
            left = np.conj(vectors[:, k])
        state = model.states[int(np.argmax(np.abs(vectors[:, k] * left)))]
        best = (float(abs(values[k])), state, state_keys(line).get(state, "control.sample_rate"))
    for i, rate, key in slip_rates(line):
        if rate > best[0]:
            best = (rate, f"web slip over {line.node_name(i)}", key)
    return best[2], f"{best[0]:.3g} 1/s, which lives in {best[1]} ({best[2]})"


# --- studies ----------------------------------------------------------------------------------

#: Most RK4 steps a whole study (all its cases) may take unless its limit is lifted
#: (``work_limit=False``, ``--no-work-limit``): about 28 hours of one core at ~1e7 steps/s,
#: a night on a few cores. Beyond it a study is more likely a slip (a duration in ms read as
#: s, a range of 10^6 values) than a plan.
MAX_STUDY_RK4_STEPS = 1_000_000_000_000
#: RK4 steps a second of one core, for the estimate of a study's time in its refusal
STEPS_PER_SECOND = 1e7


@dataclass(frozen=True)
class StudyWork:
    """The estimated work of a study: ``cases`` runs of at most ``case`` each, holding
    ``case_bytes`` each in memory."""

    cases: int
    case: Work
    case_bytes: int

    @property
    def rk4_steps(self) -> int:
        return self.cases * self.case.rk4_steps

    @property
    def memory(self) -> int:
        return self.cases * self.case_bytes


def check_study(work: StudyWork, *, limit: bool = True) -> None:
    """Refuse a study whose memory exceeds ``MAX_STUDY_BYTES`` or (with ``limit``) whose RK4
    steps exceed ``MAX_STUDY_RK4_STEPS``: ``ArgumentError`` saying what it would take and
    how to go on. Each case is checked with ``check_work`` as a run (before this)."""
    if work.memory > MAX_STUDY_BYTES:
        raise ArgumentError(
            f"the study: {work.cases:,} cases of {work.case_bytes:,} bytes each (values, "
            f"metrics, traces) need {work.memory / 1e9:.3g} GB, more than "
            f"{MAX_STUDY_BYTES / 1e9:.3g} GB; run fewer cases or record traces less often")
    if limit and work.rk4_steps > MAX_STUDY_RK4_STEPS:
        hours = work.rk4_steps / STEPS_PER_SECOND / 3600
        raise ArgumentError(
            f"the study: {work.cases:,} cases of up to {work.case.rk4_steps:.3g} RK4 steps "
            f"need {work.rk4_steps:.3g} steps (about {hours:.2g} core-hours), more than the "
            f"study limit of {MAX_STUDY_RK4_STEPS:.0e}; run fewer or shorter cases, or lift "
            "the limit (--no-work-limit, work_limit=False)")
