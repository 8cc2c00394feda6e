"""``webline experiment``: the identification tests drive engineers run on a line, simulated.

Each test drives the line with references an engineer can command (line speed ramps, a
zone's tension set point, a dancer's loading pressure) and records what every drive logs.
Its timing follows from the line's linearized closed loop (``experiment_design``): each
step of a reference is a ramp, the shortest that keeps every drive's torque within 80 % of
its limit (from the drives' inertias, loops and the step's size, all in the closed loop's
step response); each hold lasts until every logged signal has settled to 1 % (or
``MIN_HOLD``, to average the noise); and the logging rate is 10 samples per period of the
fastest closed-loop mode the logged signals show above their sensor noise. A dancer's
carriage decays in 2m/c (mass over damping): its free motion dies out in 5.

``accel-ramps`` identifies inertias and friction: during a ramp of acceleration a the drive
torque carries J a/(n r) above the steady torque; at constant speed it carries b ω plus the
tension torques, so three speeds separate the viscous friction b from the speed-independent
part, and the deceleration ramp the Coulomb part (its sign flips with the acceleration's
while J a does too). ``tension-step`` identifies the web modulus (after a step ΔT of a
zone's reference, the steady speed draw between its rollers changes by v ΔT/EA) and each
tension loop's response (bandwidth and damping from the transient). ``dancer-step``
identifies a dancer's damping and moving mass (frequency and decay of the carriage mode
after a step of its load) and its zone's position loop.
"""

from __future__ import annotations

import json
import math
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from webline.errors import ArgumentError
from webline.line import Line
from webline.sim.core.plan import compile_plan
from webline.sim.elements import layout as L
from webline.sim.linear.linearize import plan_linear_model
from webline.spec.schema import CascadedPISpec, DancerSpec
from webline.twin.tuning.experiment_design import StepDesign, design_step, mode_rate

#: settled after this many time constants (e⁻⁵ < 1 %)
SETTLE = 5.0
#: the inertial torque of a ramp, as a share of the drive's torque limit: well above the
#: friction and noise of the steady torque, well below saturation
RAMP_TORQUE_SHARE = 0.3
#: the size of a tension or dancer-load step [1]: a tenth, inside the loops' linear range
STEP = 0.1
#: the shortest hold at a constant speed or level [s]: enough samples to average the noise
MIN_HOLD = 2.0


@dataclass(frozen=True)
class Experiment:
    """One test: what it identifies and how its durations are derived."""

    name: str
    title: str
    identifies: tuple[str, ...]
    duration_rule: str


@dataclass(frozen=True)
class ExperimentPlan:
    """A test laid out on a line: the line with the test's references, its duration [s], the
    derivation of its times in words and numbers, and the columns to record."""

    experiment: Experiment
    line: Any  # a Line, or a BranchedLine (``experiment_branched``)
    duration: float
    derivation: tuple[str, ...]
    record: tuple[str, ...] = field(default_factory=tuple)
    logging_rate: float = 0.0  #: the rate the record needs [Hz]
    rate_reason: str = ""  #: the mode that sets it, in words

    def as_dict(self) -> dict[str, object]:
        return {"experiment": self.experiment.name, "title": self.experiment.title,
                "identifies": list(self.experiment.identifies),
                "duration_rule": self.experiment.duration_rule, "duration_s": self.duration,
                "derivation": list(self.derivation), "record": list(self.record),
                "logging_rate_hz": self.logging_rate, "logging_rate_reason": self.rate_reason}


EXPERIMENTS = {e.name: e for e in (
    Experiment("accel-ramps", "acceleration and deceleration ramps at three speeds",
               ("inertia of every driven roller and roll", "viscous friction of every drive",
                "Coulomb (speed-independent) losses"),
               "ramps of acceleration a = the smallest over drives of 30 % of the torque "
               "limit x n r / J (and no shorter than 5 speed-loop time constants); holds at "
               "1/3, 2/3 and 3/3 of the line speed until the linearized closed loop has "
               "settled to 1 % (at least 2 s)"),
    Experiment("tension-step", "a +10 % step of each loadcell zone's tension set point, "
               "ramped within the drives' torque limits",
               ("web modulus EA (the draw per tension)", "each tension loop's bandwidth "
                "and damping"),
               "each step a ramp keeping every drive within 80 % of its torque limit, held "
               "until the linearized closed loop has settled to 1 % (at least 2 s), zones "
               "one after the other"),
    Experiment("dancer-step", "a +10 % step of each dancer's load (loading pressure)",
               ("dancer damping and moving mass (carriage mode)", "the zone's position "
                "loop response"),
               "each step held max(5 x 2m/c, 5 τ_t, 2 s)"),
)}


def _loop_times(line: Line) -> tuple[float, float]:
    """(slowest τ_s, slowest τ_t) [s] of the line's cascaded PIs (0 where none)."""
    tau_s = tau_t = 0.0
    for i in line.drives:
        c = getattr(line.spec.rollers[i], "controller", None)
        if isinstance(c, CascadedPISpec):
            tau_s = max(tau_s, 1.0 / (c.damping * c.speed_bandwidth))
            if line.controlled_zone(i) is not None:
                tau_t = max(tau_t, 1.0 / (c.damping * c.tension_bandwidth))
    return tau_s, tau_t


def _up(value: float, step: float = 0.5) -> float:
    """``value`` rounded up to a multiple of ``step`` (times an engineer types)."""
    return math.ceil(value / step - 1e-9) * step


def accel_ramps(line: Line) -> ExperimentPlan:
    plan = compile_plan(line)
    v = plan.op.line_speed
    tau_s, _ = _loop_times(line)
    accel = math.inf
    for d, i in enumerate(line.drives):
        roller = line.spec.rollers[i]
        drive = roller.drive  # type: ignore[union-attr]
        inertia = float(plan.op.inertia[i])
        radius = float(plan.op.radius[i])
        accel = min(accel, RAMP_TORQUE_SHARE * plan.drives[d, L.D_LIMIT] * drive.ratio
                    * radius / inertia)

    def design(level: float, ramp: float) -> StepDesign:
        return chain_step(line.replace({"speed": level}), {"line_speed_ref": v / 3.0}, ramp)

    speed, duration, derivation, rate = speed_ramps(v, accel, tau_s, design)
    return ExperimentPlan(EXPERIMENTS["accel-ramps"], line.replace({"speed": speed}), duration,
                          derivation, ("speed[*]", "torque[*]", "tension[*]"), *rate)


def chain_step(line: Line, steps: dict[str, float], ramp: float | None = None) -> StepDesign:
    """``design_step`` on ``line``'s closed loop at its operating point: ``steps`` of its
    inputs (``line_speed_ref`` [m/s], ``zoneN_tension_ref`` [N]: the size of each)."""
    plan = compile_plan(line)
    return design_step(plan_linear_model(plan), steps,
                       [line.spec.rollers[i].name for i in line.drives], plan.op.torque,
                       plan.drives[:, L.D_LIMIT], ramp)


def rate_of(designs: list[StepDesign]) -> tuple[float, str]:
    """The logging rate [Hz] a test of these steps needs, and why."""
    top = max(designs, key=lambda d: d.rate)
    if top.fastest == 0.0:
        return top.rate, (f"10 samples across each {top.ramp:g} s ramp (no closed-loop mode "
                          "moves a logged signal above its noise)")
    why = (f"10 samples per period of its fastest visible closed-loop mode "
           f"({top.fastest / (2 * math.pi):.3g} Hz, {top.fastest_state}) and across each "
           f"{top.ramp:g} s ramp")
    return top.rate, why


def speed_ramps(v: float, accel: float, tau_s: float,
                design: Callable[[float, float], StepDesign]
                ) -> tuple[dict[str, object], float, tuple[str, ...], tuple[float, str]]:
    """The accel-ramps test's speed profile from rest to line speed ``v`` [m/s] in three
    ramps of v/3 at most ``accel`` [m/s²] (each at least 5 ``tau_s`` [s]), each held until
    the closed loop at that speed has settled (``design(speed, ramp)``: the step's
    ``StepDesign``) or ``MIN_HOLD``, then back to rest at the same rate: (the line file's
    ``speed`` table, the test's duration [s], the derivation's lines, the logging rate [Hz]
    and why)."""
    step_v = v / 3.0
    ramp = _up(max(step_v / accel, SETTLE * tau_s))
    designs = [design(k * step_v, ramp) for k in (1, 2, 3)]
    settle = max(d.settle for d in designs) - ramp  # after the ramp's end
    hold = _up(max(settle, MIN_HOLD))
    rate = rate_of(designs)
    times, values, t = [0.0, 1.0], [0.0, 0.0], 1.0
    for k in (1, 2, 3):
        t += ramp
        times.append(t)
        values.append(k * step_v)
        t += hold
        times.append(t)
        values.append(k * step_v)
    t += 3.0 * ramp  # the deceleration from full speed at the same rate
    times.append(t)
    values.append(0.0)
    duration = t + hold
    derivation = (
        f"acceleration a = {step_v / ramp:.4g} m/s² (30 % of the weakest drive's torque "
        f"limit allows {accel:.4g} m/s²; a ramp of v/3 = {step_v:.4g} m/s lasts at least "
        f"5 τ_s = {SETTLE * tau_s:.3g} s): each ramp {ramp:g} s",
        f"holds {hold:g} s = max(settled {settle:.3g} s after a ramp's end (linearized closed "
        f"loop at each speed), {MIN_HOLD:g} s); torques at most "
        f"{100 * max(d.peak_share for d in designs):.0f} % of the limits",
        f"total {duration:g} s: rest 1 s, three ramps and holds, deceleration {3 * ramp:g} s, "
        f"rest {hold:g} s",
        f"log at {rate[0]:g} Hz or faster: {rate[1]}")
    return {"type": "table", "time": times, "value": values}, duration, derivation, rate


def tension_step(line: Line) -> ExperimentPlan:
    plan = compile_plan(line)
    changes: dict[str, object] = {}
    t = 1.0
    stepped, designs = [], []
    for z, zone in enumerate(line.zones):
        d = line.drives.index(zone.controller)
        row = plan.drives[d]
        if row[L.D_DANCER] >= 0 and row[L.D_DUSE] == L.DANCER_POSITION:
            continue  # the dancer sets this zone's tension: dancer-step
        k = zone.loadcell
        name = line.span_name(k)
        ref = line.spec.spans[k].tension
        if not isinstance(ref, float | int):
            raise ArgumentError(f"{line.name}: spans.{name}.tension: tension-step needs a "
                                "constant set point to step from")
        design = chain_step(line, {f"zone{z + 1}_tension_ref": STEP * ref})
        changes[f"spans.{name}.tension"], t, words = step_table(name, float(ref), t, design)
        stepped.append(words)
        designs.append(design)
    if not stepped:
        raise ArgumentError(f"{line.name}: tension-step: no zone with a loadcell in tension "
                            "control (dancer zones: dancer-step)")
    rate = rate_of(designs)
    return ExperimentPlan(EXPERIMENTS["tension-step"], line.replace(changes), t,
                          (*stepped, f"log at {rate[0]:g} Hz or faster: {rate[1]}"),
                          ("tension[*]", "speed[*]", "torque[*]"), *rate)


def step_table(name: str, ref: float, t: float, design: StepDesign
               ) -> tuple[dict[str, object], float, str]:
    """A set point ``ref`` [N] stepped by ``STEP`` at ``t`` [s] as ``design``'s ramp, held
    until settled (at least ``MIN_HOLD``), ramped back and held again: (the profile as a
    line-file table, the time after it [s], the derivation's line for ``name``)."""
    hold = _up(max(design.settle, MIN_HOLD))
    top, ramp = ref * (1 + STEP), design.ramp
    table: dict[str, object] = {
        "type": "table", "time": [0.0, t, t + ramp, t + hold, t + hold + ramp],
        "value": [ref, ref, top, top, ref]}
    words = (f"{name} {ref:g} -> {top:g} N at {t:g} s, back at {t + hold:g} s: "
             f"{design.words()}; held {hold:g} s")
    return table, t + 2.0 * hold, words


def dancer_step(line: Line) -> ExperimentPlan:
    plan = compile_plan(line)
    _, tau_t = _loop_times(line)
    changes: dict[str, object] = {}
    lines, t = [], 1.0
    dancers = [(i, r) for i, r in enumerate(line.spec.rollers) if isinstance(r, DancerSpec)]
    if not dancers:
        raise ArgumentError(f"{line.name}: dancer-step: the line has no dancer")
    holds = []
    for i, roller in dancers:
        c = roller.dancer
        decay = 2.0 * c.mass / c.damping if c.damping > 0 else math.inf
        hold = _up(max(SETTLE * decay if math.isfinite(decay) else MIN_HOLD,
                       SETTLE * tau_t, MIN_HOLD))
        holds.append(hold)
        load = c.load if isinstance(c.load, float | int) else 2.0 * float(
            plan.op.tension[line.zone_of_span(i)])
        if c.load is not None and not isinstance(c.load, float | int):
            raise ArgumentError(f"{line.name}: rollers.{roller.name}.dancer.load: "
                                "dancer-step needs a constant load to step from")
        changes[f"rollers.{roller.name}.dancer.load"] = {
            "type": "steps", "initial": float(load),
            "steps": [{"time": t, "value": load * (1 + STEP)}, {"time": t + hold,
                                                                 "value": float(load)}]}
        lines.append(f"{roller.name}: load {load:g} -> {load * (1 + STEP):g} N at {t:g} s, "
                     f"back at {t + hold:g} s; held {hold:g} s = max(5 x 2m/c = "
                     f"{SETTLE * decay:.3g} s, 5 τ_t = {SETTLE * tau_t:.3g} s, {MIN_HOLD:g} s)")
        t += 2.0 * hold
    rate = mode_rate(plan_linear_model(plan))
    return ExperimentPlan(EXPERIMENTS["dancer-step"], line.replace(changes), t,
                          (*lines, f"log at {rate[0]:g} Hz or faster: {rate[1]}"),
                          ("dancer_position[*]", "tension[*]", "speed[*]"), *rate)


PLANNERS: dict[str, Callable[[Line], ExperimentPlan]] = {
    "accel-ramps": accel_ramps, "tension-step": tension_step, "dancer-step": dancer_step}


def plan_experiment(line: Line, name: str) -> ExperimentPlan:
    """The test ``name`` laid out on ``line``; ``ArgumentError`` for an unknown name or a
    line the test does not apply to."""
    if name not in PLANNERS:
        raise ArgumentError(f"no experiment named {name!r}; known: {', '.join(PLANNERS)}")
    return PLANNERS[name](line)


def write_experiment(line: Line, name: str, out: Path,
                     claim: Callable[[str], Path] | None = None) -> tuple[ExperimentPlan, Any]:
    """Simulate the test ``name`` on ``line`` and write into ``out``: ``results.csv`` (the
    run's signals with webline's names and units, what ``load_measurements`` reads),
    ``experiment.json`` (what it identifies, its duration and how it was derived, the
    columns to record; a dancer's carriage position is among the run's signals) and
    ``traces.png``. Returns the plan and the ``Result``."""
    from webline.sim.simulate import simulate

    place = claim or (lambda relative: out / relative)
    plan = plan_experiment(line, name)
    result = simulate(plan.line, plan.duration, raise_on_failure=False,
                      record_interval=1.0 / plan.logging_rate)
    result.to_csv(place("results.csv"))
    data = plan.as_dict() | {"line": line.name, "verdict": result.verdict.headline}
    place("experiment.json").write_text(json.dumps(data, indent=2), encoding="utf-8")
    signals = ("speed", "torque") if name == "accel-ramps" else ("tension", "speed")
    figure = result.plot(signals)
    figure.savefig(place("traces.png"), dpi=100, bbox_inches="tight")
    return plan, result
