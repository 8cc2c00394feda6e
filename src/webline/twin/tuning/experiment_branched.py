"""``webline experiment`` on a branched line (docs/branching.md, "Tuning a branched line"):
the chain's identification tests (``experiment``) laid out on a branched line's drives and
zones and simulated in the branch kernel.

The test signals are the chain's, with the chain's rules (``experiment_design``: ramps,
holds and logging rate from the linearized closed loop, here ``sim.branches.linear``'s)
computed from the branched line's own model: ``accel-ramps`` ramps the line speed (every
drive of every web follows it; the acceleration is 30 % of the weakest drive's torque limit
over its J/(n r)); ``tension-step`` ramps each tension zone's set point up by 10 % in turn
(every loadcell of the zone together: lanes on one shaft are controlled as their sum; a zone
held by a dancer in position control or a differential shaft's drive, which holds speed
only, is left out);
``dancer-step`` steps each dancer's load by 10 %. The traces (``results.csv``: every span's
tension, every roller's surface speed, every drive's torque and command, each dancer's
position, each loadcell's tension set point and the master's speed reference, with webline's
names and units) lay out the test to run on the machine, and ``replay`` and ``fit`` read them
back as they read a single-path line's.
"""

from __future__ import annotations

import json
import math
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from webline.errors import ArgumentError
from webline.model.web_graph import BranchedLine
from webline.profiles import breakpoints
from webline.sim.branches.equilibrium import operating_point
from webline.sim.branches.linear import branch_linear_model
from webline.sim.branches.loop import layout as B
from webline.sim.branches.plan import compile_branches
from webline.sim.sweeps.branch_study import derive_branched
from webline.spec.schema import CascadedPISpec, DancerSpec
from webline.twin.tuning.experiment import (
    EXPERIMENTS,
    MIN_HOLD,
    RAMP_TORQUE_SHARE,
    SETTLE,
    STEP,
    ExperimentPlan,
    _up,
    rate_of,
    speed_ramps,
    step_table,
)
from webline.twin.tuning.experiment_design import StepDesign, design_step, mode_rate


def _loop_times(line: BranchedLine) -> tuple[float, float]:
    """(slowest τ_s, slowest τ_t) [s] of the line's cascaded PIs (0 where none)."""
    tau_s = tau_t = 0.0
    for i in line.drives:
        c = getattr(line.spec.rollers[i], "controller", None)
        if isinstance(c, CascadedPISpec):
            tau_s = max(tau_s, 1.0 / (c.damping * c.speed_bandwidth))
            if i in line.zones:
                tau_t = max(tau_t, 1.0 / (c.damping * c.tension_bandwidth))
    return tau_s, tau_t


def _line_speed(line: BranchedLine) -> float:
    """The line's top reference speed [m/s]."""
    return float(np.max(breakpoints(line.spec.speed)[1]))


def accel_ramps(line: BranchedLine) -> ExperimentPlan:
    plan = compile_branches(line)
    v = _line_speed(line)
    tau_s, _ = _loop_times(line)
    # D_GAINNORM = J / (n r) of each drive at its initial radius [kg·m]: a = share x limit / it
    accel = min(RAMP_TORQUE_SHARE * plan.df[d, B.D_LIMIT] / plan.df[d, B.D_GAINNORM]
                for d in range(len(line.drives)))

    def design(level: float, ramp: float) -> StepDesign:
        return branched_step(derive_branched(line, {"speed": level}),
                             {"line_speed_ref": v / 3.0}, ramp)

    speed, duration, derivation, rate = speed_ramps(v, accel, tau_s, design)
    return ExperimentPlan(EXPERIMENTS["accel-ramps"], derive_branched(line, {"speed": speed}),
                          duration, derivation, ("speed[*]", "torque[*]", "tension[*]"), *rate)


def branched_step(line: BranchedLine, steps: dict[str, float], ramp: float | None = None
                  ) -> StepDesign:
    """``design_step`` on branched ``line``'s closed loop at its operating point: ``steps``
    of its inputs (``line_speed_ref`` [m/s], ``SPAN_tension_ref`` [N]: the size of each)."""
    plan = compile_branches(line)
    point = operating_point(plan, 0.0)
    return design_step(branch_linear_model(plan, point), steps,
                       [line.spec.rollers[i].name for i in line.drives], point.torque,
                       plan.df[:, B.D_LIMIT], ramp)


def tension_step(line: BranchedLine) -> ExperimentPlan:
    plan = compile_branches(line)
    shafts = {int(n) for n in plan.cores[:, B.C_NODE]}
    changes: dict[str, object] = {}
    stepped, designs, t = [], [], 1.0
    for d, i in enumerate(line.drives):
        first = int(plan.di[d, B.DI_CELLS])
        if i not in line.zones or i in shafts or (
                plan.di[d, B.DI_NCELLS] and plan.cells[first, B.CELL_DANCER] >= 0):
            continue  # no zone; a slip shaft holds speed; a dancer sets it: dancer-step
        refs = {}
        for k in line.zones[i].loadcells:
            span = line.spans[k]
            key = f"webs.{line.spec.webs[span.web].name}.spans.{span.k}.tension"
            ref = line.span_tension_spec(k)
            if not isinstance(ref, float | int):
                raise ArgumentError(f"{line.name}: {key}: tension-step needs a constant set "
                                    "point to step from")
            refs[k] = (key, float(ref))
        # the zone's loadcells step together, each by a tenth of its own set point
        design = branched_step(line, {f"{line.spans[k].name}_tension_ref": STEP * ref
                                      for k, (_, ref) in refs.items()})
        start = t
        for k, (key, ref) in refs.items():
            name = f"{line.spans[k].name} ({line.spec.rollers[i].name})"
            changes[key], t, words = step_table(name, ref, start, design)
            stepped.append(words)
        designs.append(design)
    if not stepped:
        raise ArgumentError(f"{line.name}: tension-step: no zone with a loadcell in tension "
                            "control (dancer zones: dancer-step)")
    rate = rate_of(designs)
    return ExperimentPlan(EXPERIMENTS["tension-step"], derive_branched(line, changes), t,
                          (*stepped, f"log at {rate[0]:g} Hz or faster: {rate[1]}"),
                          ("tension[*]", "speed[*]", "torque[*]"), *rate)


def dancer_step(line: BranchedLine) -> ExperimentPlan:
    _, tau_t = _loop_times(line)
    dancers = [(i, r) for i, r in enumerate(line.spec.rollers) if isinstance(r, DancerSpec)]
    if not dancers:
        raise ArgumentError(f"{line.name}: dancer-step: the line has no dancer")
    plan = compile_branches(line)
    changes: dict[str, object] = {}
    lines, t = [], 1.0
    for i, roller in dancers:
        c = roller.dancer
        decay = 2.0 * c.mass / c.damping if c.damping > 0 else math.inf
        hold = _up(max(SETTLE * decay if math.isfinite(decay) else MIN_HOLD,
                       SETTLE * tau_t, MIN_HOLD))
        if c.load is not None and not isinstance(c.load, float | int):
            raise ArgumentError(f"{line.name}: rollers.{roller.name}.dancer.load: "
                                "dancer-step needs a constant load to step from")
        # without a load of its own: its strands' gains x its zone's loadcell reference
        # (``branches.dancers.load_rows``), the load that holds the set position
        cell = next(row for row in plan.cells if int(row[B.CELL_DANCER]) == i)
        load = float(c.load) if c.load is not None else (
            sum(c.gains) * plan.profile(int(cell[1]), 0.0))
        changes[f"rollers.{roller.name}.dancer.load"] = {
            "type": "steps", "initial": load,
            "steps": [{"time": t, "value": load * (1 + STEP)}, {"time": t + hold,
                                                                 "value": load}]}
        lines.append(f"{roller.name}: load {load:g} -> {load * (1 + STEP):g} N at {t:g} s, "
                     f"back at {t + hold:g} s; held {hold:g} s = max(5 x 2m/c = "
                     f"{SETTLE * decay:.3g} s, 5 τ_t = {SETTLE * tau_t:.3g} s, {MIN_HOLD:g} s)")
        t += 2.0 * hold
    rate = mode_rate(branch_linear_model(plan, operating_point(plan, 0.0)))
    return ExperimentPlan(EXPERIMENTS["dancer-step"], derive_branched(line, changes), t,
                          (*lines, f"log at {rate[0]:g} Hz or faster: {rate[1]}"),
                          ("dancer_position[*]", "tension[*]", "speed[*]"), *rate)


PLANNERS: dict[str, Callable[[BranchedLine], ExperimentPlan]] = {
    "accel-ramps": accel_ramps, "tension-step": tension_step, "dancer-step": dancer_step}

#: the run's signals written to results.csv: (variable, its dimension)
SIGNALS = (("tension", "span"), ("speed", "node"), ("torque", "drive"),
           ("torque_cmd", "drive"), ("dancer_position", "dancer"))


def results_csv(result: Any, path: Path) -> None:
    """One column per signal and element, ``tension[film_zone] [N]``, time first (the
    chain's ``results.csv`` layout), and the references a replay is driven by, as a PLC logs
    them: each loadcell span's tension set point (``tension_ref[film_zone]``) and the
    master's speed reference, the line's speed (``speed_ref[nip]``)."""
    dataset = result.dataset
    headers, columns = ["time [s]"], [dataset["time"].values]
    for name, dim in SIGNALS:
        if name not in dataset:
            continue
        var = dataset[name]
        unit = var.attrs.get("units", "1")
        for j, element in enumerate(dataset[dim].values):
            headers.append(f"{name}[{element}] [{unit}]")
            columns.append(var.values[:, j])
    for j, span in enumerate(result.span_names):
        if np.isfinite(result.tension_ref[:, j]).all():
            headers.append(f"tension_ref[{span}] [N]")
            columns.append(result.tension_ref[:, j])
    master = result.line.spec.rollers[result.line.master].name
    headers.append(f"speed_ref[{master}] [m/s]")
    columns.append(np.interp(result.time, *breakpoints(result.line.spec.speed)))
    np.savetxt(path, np.column_stack(columns), delimiter=",", header=",".join(headers),
               comments="", fmt="%.9g")


def write_branched_experiment(line: BranchedLine, name: str, out: Path,
                              claim: Callable[[str], Path] | None = None
                              ) -> tuple[ExperimentPlan, Any]:
    """Simulate test ``name`` on branched ``line`` and write ``results.csv``,
    ``experiment.json`` and ``traces.png`` into ``out`` (as ``experiment.write_experiment``).
    Returns the plan and the ``BranchResult``."""
    import matplotlib.pyplot as plt

    from webline.sim.branches.run import simulate_branches

    place = claim or (lambda relative: out / relative)
    if name not in PLANNERS:
        raise ArgumentError(f"no experiment named {name!r}; known: {', '.join(PLANNERS)}")
    plan = PLANNERS[name](line)
    result = simulate_branches(plan.line, plan.duration, raise_on_failure=False,
                               record_interval=1.0 / plan.logging_rate)
    ds = result.dataset
    results_csv(result, place("results.csv"))
    data = plan.as_dict() | {"line": line.name, "verdict": result.verdict.headline}
    place("experiment.json").write_text(json.dumps(data, indent=2), encoding="utf-8")
    shown = ("speed", "torque") if name == "accel-ramps" else ("tension", "speed")
    fig, axes = plt.subplots(len(shown), 1, figsize=(8, 5), sharex=True)
    for ax, signal in zip(axes, shown, strict=True):
        dim = dict(SIGNALS)[signal]
        for j, element in enumerate(ds[dim].values):
            ax.plot(ds["time"].values, ds[signal].values[:, j], lw=0.9, label=str(element))
        ax.set_ylabel(f"{signal} [{ds[signal].attrs.get('units', '1')}]")
        ax.legend(fontsize=7, loc="upper right", ncol=2)
        ax.grid(alpha=0.3)
    axes[-1].set_xlabel("time [s]")
    fig.suptitle(f"{name} on {line.name}", fontsize=10)
    fig.savefig(place("traces.png"), dpi=100, bbox_inches="tight")
    plt.close(fig)
    return plan, result
