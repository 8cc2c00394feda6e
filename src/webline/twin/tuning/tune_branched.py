"""``webline.tune`` on a branched line (docs/branching.md, "Tuning a branched line").

The chain's tuning (``tune``) with a branched line's pieces (``BRANCHED``):

* free values: every cascaded-PI drive's ``speed_bandwidth`` and, where the drive holds a
  tension zone (of a web, a laminate or a lane; a differential shaft's drive holds speed
  only), its ``tension_bandwidth`` (a dancer's position loop where the zone holds one), a
  third to three times their values, as on a chain;
* candidates run every scenario in the branch kernel (``sweeps.branch_study``); the
  objective's terms are per loadcell span, so per web and per lane: RMS error over its set
  tension, each weighing by its relative error as on a chain (a lane at 30 N and the
  laminate at 180 N count alike);
* stability at the line's operating point (``branches.equilibrium.analysis_time``: the end of
  a start-up ramp for a line that starts at rest) from the branched linear model
  (``branches.linear``): the continuous closed loop's modes and the sampled loop's (the hold
  can destabilise a fast mode), the damping of the modes the controllers take part in, and
  each drive's loop-at-a-time margins (``loop_margins.margins_of`` on the branched model),
  at ``Limits.roll_points`` points across the rolls (``roll_points``: every web runs at the
  line speed, so one wound length places every unwind and rewind);
* robustness: the chain's Monte Carlo (``tune_robust.robustness``, branched sweeps), each
  draw's modes, damping and margins checked as above (``stability_constraints``);
* the tuned line keeps its gains explicit (``frozen_gains``), a roll's scheduled speed gains
  tabulated over its diameter (``gain_table``).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from webline.errors import LineFileError
from webline.model.web_graph import BranchedLine, load_branched
from webline.sim.branches.equilibrium import analysis_time, operating_point
from webline.sim.branches.findings.web_findings import felt_records
from webline.sim.branches.linear import (
    branch_linear_model,
    integrator_names,
    sampled_closed_loop,
)
from webline.sim.branches.loop import layout as B
from webline.sim.branches.plan import BranchPlan, compile_branches
from webline.sim.sweeps.branch_study import derive_branched, run_branch_cases
from webline.spec.branched.check import kind_of
from webline.spec.schema import CascadedPISpec
from webline.twin.tuning.loop_margins import margins_of, split_feedback
from webline.twin.tuning.tune_constraints import (
    UNSTABLE,
    Constraint,
    Limits,
    Worst,
    record_point,
    worst_constraints,
)
from webline.twin.tuning.tune_robust import rollers_uncertain
from webline.twin.tuning.tune_space import FreeParameter, LineOps, pi_bandwidths
from webline.twin.tuning.tune_space import gain_table as chain_gain_table


def _shafts(plan: BranchPlan) -> set[int]:
    """Nodes of differential shafts (their drive holds speed; each lane's core slips)."""
    return {int(n) for n in plan.cores[:, B.C_NODE]}


def default_free(line: BranchedLine) -> list[FreeParameter]:
    """The default tuning variables of branched ``line`` (module docstring): a differential
    shaft holds speed, so it has no tension bandwidth to tune."""
    shafts = _shafts(compile_branches(line))
    return pi_bandwidths(line, lambda i: i in line.zones and i not in shafts)


def frozen_gains(line: BranchedLine) -> dict[str, float]:
    """Every cascaded-PI drive's gains as branched ``line`` compiles them [SI], as line paths:
    ``speed_kp``/``speed_ki`` of drives that do not schedule them with a roll, and the
    zone's ``tension_kp``/``tension_ki`` or its dancer's ``position_kp``/``position_ki``
    (as ``tune_space.frozen_gains`` on a chain)."""
    plan = compile_branches(line)
    shafts = _shafts(plan)
    out: dict[str, float] = {}
    for d, i in enumerate(line.drives):
        roller = line.spec.rollers[i]
        if not isinstance(getattr(roller, "controller", None), CascadedPISpec):
            continue
        row, base = plan.df[d], f"rollers.{roller.name}.controller"
        if row[B.D_ADAPTIVE] <= 0:
            out[f"{base}.speed_kp"] = float(row[B.D_KPS])
            out[f"{base}.speed_ki"] = float(row[B.D_KIS])
        if i not in line.zones or i in shafts:
            continue
        first = int(plan.di[d, B.DI_CELLS])
        dancer = int(plan.cells[first, B.CELL_DANCER]) if plan.di[d, B.DI_NCELLS] else -1
        if dancer >= 0:
            name = f"rollers.{line.spec.rollers[dancer].name}.dancer"
            out[f"{name}.position_kp"] = float(row[B.D_KPT])
            out[f"{name}.position_ki"] = float(row[B.D_KIT])
        else:
            out[f"{base}.tension_kp"] = float(row[B.D_KPT])
            out[f"{base}.tension_ki"] = float(row[B.D_KIT])
    return out


def set_tension(line: BranchedLine) -> np.ndarray:
    """Tension [N] of every span at the line's operating point at t = 0 (a loadcell span's:
    its set tension)."""
    plan = compile_branches(line)
    point = operating_point(plan, 0.0)
    return np.asarray(felt_records(plan, np.zeros(1), point.x[None, :])[0], dtype=float)


def closed_loop_modes(line: BranchedLine) -> tuple[BranchPlan, Any, float, np.ndarray,
                                                   np.ndarray, float]:
    """(plan, operating point, its time [s], continuous closed-loop eigenvalues [1/s], their
    share of participation held by controller states [1], the largest real part of the
    sampled loop's modes ln(μ)/dt [1/s]) of ``line`` at ``analysis_time``."""
    plan = compile_branches(line)
    t = analysis_time(line)
    point = operating_point(plan, t)
    model = branch_linear_model(plan, point, "closed")
    values, right = np.linalg.eig(np.asarray(model.a, dtype=float))
    participation = np.abs(right * np.linalg.inv(right).T)
    participation /= participation.sum(axis=0, keepdims=True)
    controllers = set(integrator_names(plan))
    rows = [j for j, name in enumerate(model.states) if name in controllers]
    mu = np.linalg.eigvals(sampled_closed_loop(plan, point)).astype(complex)
    sampled = float(np.max(np.log(mu).real)) / plan.dt
    return plan, point, t, values, participation[rows].sum(axis=0), sampled


def roll_points(line: BranchedLine, n: int) -> list[tuple[str, dict[str, float]]]:
    """``n`` points across the rolls of branched ``line``: (where, {roller radius path: r
    [m]}). Every web runs at the line speed, so one unstrained length ℓ [m] wound off every
    unwind and onto every rewind places them all: r² = r0² ∓ ℓ h / π (h the roll's web
    thickness; a shaft's lanes at their mean, they start at one radius), from the initial
    radii to 95 % of the ℓ at which the first unwind reaches its core or a rewind the
    largest initial roll radius (the chain's ``tune_space.roll_radii`` rule)."""
    rolls: dict[int, list[Any]] = {}
    for roll in line.rolls:
        rolls.setdefault(roll.node, []).append(roll)
    top = max((r.radius for r in line.rolls), default=0.0)
    room = math.inf
    thickness: dict[int, tuple[float, float, float]] = {}  # node: (h [m], r0 [m], ∓1)
    for node, on in rolls.items():
        h = float(np.mean([line.materials[r.web].thickness for r in on]))
        r0, sign = on[0].radius, on[0].direction
        thickness[node] = (h, r0, sign)
        if sign < 0:
            core = getattr(line.spec.rollers[node], "core_radius", 0.0) or 0.0
            room = min(room, math.pi * (r0**2 - core**2) / h)
        elif top > r0:
            room = min(room, math.pi * (top**2 - r0**2) / h)
    if not math.isfinite(room) or n <= 1:
        return [("initial radii", {})]
    out = []
    for length in np.linspace(0.0, 0.95 * room, n):
        radii = {f"rollers.{line.spec.rollers[node].name}.radius":
                 math.sqrt(r0**2 + sign * length * h / math.pi)
                 for node, (h, r0, sign) in thickness.items()}
        where = ", ".join(f"{path.split('.')[1]} r = {r:.3g} m" for path, r in radii.items())
        out.append((f"{length:.4g} m wound: {where}", radii))
    return out


def stability_constraints(line: BranchedLine, limits: Limits) -> list[Constraint]:
    """Modes, damping and loop margins of branched ``line`` (its gains explicit) at
    ``limits.roll_points`` points across its rolls (``roll_points``), the worst of each, as
    the chain's constraints name them (module docstring)."""
    worst: Worst = {}
    names = [line.spec.rollers[i].name for i in line.drives]
    for where, radii in roll_points(line, limits.roll_points):
        at = derive_branched(line, radii)
        plan, point, t, values, share, sampled = closed_loop_modes(at)
        open_ = branch_linear_model(plan, point, "open")
        a_cl = np.asarray(branch_linear_model(plan, point, "closed").a, dtype=float)
        b_full, k = split_feedback(np.asarray(open_.a),
                                   np.asarray(open_.b)[:, :len(line.drives)], a_cl)
        spot = f"t = {t:g} s, {where}"
        record_point(worst, values, share, margins_of(a_cl, b_full, k, plan.dt, names),
                     spot, limits)
        if sampled > worst[UNSTABLE][0]:  # the hold's delay: the sampled loop decides
            worst[UNSTABLE] = (sampled, f"{spot}, controllers sampled at {1 / plan.dt:.4g} Hz")
    return worst_constraints(worst, limits)


def default_uncertain(line: BranchedLine) -> dict[str, str]:
    """Uncertainties assumed when none are given (``tune_robust.default_uncertain``'s, per
    web): every raw web's stiffness ±10 % (its ``ea`` or ``modulus`` as the file gives it;
    laminates and lanes follow their webs), every driven roller's and roll's rotating inertia
    ±10 %, every dancer's damping ±30 % (one standard deviation each)."""
    out: dict[str, str] = {}
    for web in line.spec.webs:
        material, prefix = (web.web, f"webs.{web.name}.web") if web.web is not None else (
            line.spec.web, "web")  # (the line's own web, shared by the webs that give none)
        if kind_of(web) != "web" or material is None or f"{prefix}.ea" in out or (
                f"{prefix}.modulus" in out):
            continue
        key, value = ("ea", material.ea) if material.ea is not None else (
            "modulus", material.modulus)
        out[f"{prefix}.{key}"] = f"normal({value!r}, 10 %)"
    return {**out, **rollers_uncertain(line)}


def gain_table(line: BranchedLine, points: int = 9) -> list[dict[str, float | str]]:
    """Rows (drive, diameter [m], speed_kp, speed_ki) of every roll drive of branched
    ``line`` whose speed gains follow its diameter, at ``points`` diameters from just above
    its core to the largest initial roll radius (as ``tune_space.gain_table``)."""
    plan = compile_branches(line)
    top = max((r.radius for r in line.rolls), default=0.0)
    rows: list[dict[str, float | str]] = []
    for d, i in enumerate(line.drives):
        roller = line.spec.rollers[i]
        core = getattr(roller, "core_radius", None)
        if plan.df[d, B.D_ADAPTIVE] <= 0 or core is None:
            continue
        for r in np.linspace(core * 1.02, max(top, core * 1.05), points):
            try:
                row = compile_branches(derive_branched(
                    line, {f"rollers.{roller.name}.radius": float(r)})).df[d]
            except LineFileError:  # a radius this line refuses (a lane's own checks)
                continue
            rows.append({"drive": roller.name, "diameter_m": 2.0 * float(r),
                         "speed_kp": float(row[B.D_KPS]), "speed_ki": float(row[B.D_KIS])})
    return rows


def line_gain_table(line: Any) -> list[dict[str, float | str]]:
    """``tune_space.gain_table`` of a single-path line, ``gain_table`` of a branched one."""
    return gain_table(line) if isinstance(line, BranchedLine) else chain_gain_table(line)


def loadcell_errors(run: Any) -> tuple[np.ndarray, list[tuple[str, np.ndarray]]]:
    """(time [s], [(span name, tension minus its loadcell reference [N])]) of a branched
    run (``BranchResult``), its loadcell spans in span order."""
    plan = run.plan
    tension = run.dataset["tension"].values
    out = []
    for span, p in sorted(plan.cells[:, :2].astype(int).tolist()):
        a, b = plan.prof_off[p], plan.prof_off[p + 1]
        reference = np.interp(run.time, plan.prof_t[a:b], plan.prof_v[a:b])
        out.append((plan.line.spans[span].name, tension[:, span] - reference))
    return run.time, out


def _run_cases(line: BranchedLine, cases: Sequence[Mapping[str, object]], *,
               scenario: str | None = None, workers: int | None = None) -> Any:
    return run_branch_cases(line, cases, scenario=scenario, workers=workers)


BRANCHED = LineOps(load=load_branched, default_free=default_free, derive=derive_branched,
                   frozen_gains=frozen_gains, run_cases=_run_cases, set_tension=set_tension,
                   stability=stability_constraints,
                   default_uncertain=default_uncertain)
