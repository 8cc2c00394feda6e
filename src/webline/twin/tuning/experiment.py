"""``webline experiment``: the identification tests drive engineers run on a line, simulated.

Each test drives the line with references an engineer can command (line speed ramps, a
zone's tension set point, a dancer's loading pressure) and records what every drive logs.
Its durations follow from the line's own time scales, computed here:

* a speed loop's closed-loop time constant τ_s = 1/(ζ ω_s) and a tension loop's
  τ_t = 1/(ζ ω_t) (the bandwidths and damping of each cascaded PI): a response has settled
  to e⁻⁵ < 1 % after 5 of them;
* a zone's transport time L/v (its web length over the line speed): the open-loop tension
  dynamics of a span;
* a dancer carriage's decay time 2m/c (mass over damping): its free motion dies out in 5.

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
from webline.spec.schema import CascadedPISpec, DancerSpec

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

    def as_dict(self) -> dict[str, object]:
        return {"experiment": self.experiment.name, "title": self.experiment.title,
                "identifies": list(self.experiment.identifies),
                "duration_rule": self.experiment.duration_rule, "duration_s": self.duration,
                "derivation": list(self.derivation), "record": list(self.record)}


EXPERIMENTS = {e.name: e for e in (
    Experiment("accel-ramps", "acceleration and deceleration ramps at three speeds",
               ("inertia of every driven roller and roll", "viscous friction of every drive",
                "Coulomb (speed-independent) losses"),
               "ramps of acceleration a = the smallest over drives of 30 % of the torque "
               "limit x n r / J (and no shorter than 5 speed-loop time constants); holds of "
               "max(5 τ_t, 5 τ_s, 3 L/v, 2 s) at 1/3, 2/3 and 3/3 of the line speed"),
    Experiment("tension-step", "a +10 % step of each loadcell zone's tension set point",
               ("web modulus EA (the draw per tension)", "each tension loop's bandwidth "
                "and damping"),
               "each step held max(5 τ_t, 10 L/v, 2 s), zones one after the other"),
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


def _zone_transport(line: Line, speed: float) -> float:
    """Longest zone length over the line speed [s]."""
    longest = max(sum(line.spec.spans[k].length for k in z.spans) for z in line.zones)
    return longest / speed


def _up(value: float, step: float = 0.5) -> float:
    """``value`` rounded up to a multiple of ``step`` (times an engineer types)."""
    return math.ceil(value / step - 1e-9) * step


def accel_ramps(line: Line) -> ExperimentPlan:
    plan = compile_plan(line)
    v = plan.op.line_speed
    tau_s, tau_t = _loop_times(line)
    accel = math.inf
    for d, i in enumerate(line.drives):
        roller = line.spec.rollers[i]
        drive = roller.drive  # type: ignore[union-attr]
        inertia = float(plan.op.inertia[i])
        radius = float(plan.op.radius[i])
        accel = min(accel, RAMP_TORQUE_SHARE * plan.drives[d, L.D_LIMIT] * drive.ratio
                    * radius / inertia)
    speed, duration, derivation = speed_ramps(v, accel, tau_s, tau_t, _zone_transport(line, v))
    return ExperimentPlan(EXPERIMENTS["accel-ramps"], line.replace({"speed": speed}), duration,
                          derivation, ("speed[*]", "torque[*]", "tension[*]"))


def speed_ramps(v: float, accel: float, tau_s: float, tau_t: float, transport: float
                ) -> tuple[dict[str, object], float, tuple[str, ...]]:
    """The accel-ramps test's speed profile from rest to line speed ``v`` [m/s] in three
    ramps of v/3 at most ``accel`` [m/s²] (each at least 5 ``tau_s`` [s]), each held 5 loop
    times (``tau_s``, ``tau_t`` [s]), 3 zone transports (``transport`` [s]) or ``MIN_HOLD``,
    then back to rest at the same rate: (the line file's ``speed`` table, the test's
    duration [s], the derivation's lines)."""
    step_v = v / 3.0
    ramp = _up(max(step_v / accel, SETTLE * tau_s))
    hold = _up(max(SETTLE * tau_t, SETTLE * tau_s, 3.0 * transport, MIN_HOLD))
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
        f"holds {hold:g} s = max(5 τ_t = {SETTLE * tau_t:.3g} s, 5 τ_s = {SETTLE * tau_s:.3g} s,"
        f" 3 L/v = {3 * transport:.3g} s, {MIN_HOLD:g} s)",
        f"total {duration:g} s: rest 1 s, three ramps and holds, deceleration {3 * ramp:g} s, "
        f"rest {hold:g} s")
    return {"type": "table", "time": times, "value": values}, duration, derivation


def tension_step(line: Line) -> ExperimentPlan:
    plan = compile_plan(line)
    v = plan.op.line_speed
    _, tau_t = _loop_times(line)
    hold = _up(max(SETTLE * tau_t, 10.0 * _zone_transport(line, v), MIN_HOLD))
    changes: dict[str, object] = {}
    t = 1.0
    stepped = []
    for zone in line.zones:
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
        changes[f"spans.{name}.tension"] = {
            "type": "steps", "initial": ref,
            "steps": [{"time": t, "value": ref * (1 + STEP)}, {"time": t + hold, "value": ref}]}
        stepped.append(f"{name} {ref:g} -> {ref * (1 + STEP):g} N at {t:g} s, back at "
                       f"{t + hold:g} s")
        t += 2.0 * hold
    if not stepped:
        raise ArgumentError(f"{line.name}: tension-step: no zone with a loadcell in tension "
                            "control (dancer zones: dancer-step)")
    derivation = (f"each step held {hold:g} s = max(5 τ_t = {SETTLE * tau_t:.3g} s, "
                  f"10 L/v = {10 * _zone_transport(line, v):.3g} s, {MIN_HOLD:g} s)",
                  *stepped)
    return ExperimentPlan(EXPERIMENTS["tension-step"], line.replace(changes), t, derivation,
                          ("tension[*]", "speed[*]", "torque[*]"))


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
    return ExperimentPlan(EXPERIMENTS["dancer-step"], line.replace(changes), t, tuple(lines),
                          ("dancer_position[*]", "tension[*]", "speed[*]"))


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
    result = simulate(plan.line, plan.duration, raise_on_failure=False)
    result.to_csv(place("results.csv"))
    data = plan.as_dict() | {"line": line.name, "verdict": result.verdict.headline}
    place("experiment.json").write_text(json.dumps(data, indent=2), encoding="utf-8")
    signals = ("speed", "torque") if name == "accel-ramps" else ("tension", "speed")
    figure = result.plot(signals)
    figure.savefig(place("traces.png"), dpi=100, bbox_inches="tight")
    return plan, result
