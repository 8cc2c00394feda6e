"""The wound rolls a branched run leaves on its rewinds (docs/wound-roll.md, "Branched
lines"): each rewind with a ``roll_stress`` table, and each lane on a shared shaft, gets the
chain's roll (``sim.results.wound_roll.recorded_roll``) from its own records: its roll's
radius, the tension of the span entering it, its web's (or lane's, or laminate's) width,
thickness and modulus, its zone's set tension for that web and the rewind's taper."""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING

import numpy as np

from webline.sim.branches.loop import layout as B
from webline.sim.results.wound_roll import WoundRoll, recorded_roll
from webline.spec.schema import RewindSpec

if TYPE_CHECKING:
    from webline.sim.branches.plan import BranchPlan


def roll_name(plan: BranchPlan, j: int) -> str:
    """Roll ``j`` as the dataset names it: ``roller/web``."""
    line = plan.line
    roll = line.rolls[j]
    return f"{line.spec.rollers[roll.node].name}/{line.spec.webs[roll.web].name}"


def _set_cell(plan: BranchPlan, node: int, span_web: int) -> int | None:
    """The loadcell row of ``node``'s drive that holds web ``span_web``'s zone tension (a
    shaft's lanes: one row each), or None (no drive, or no tension loop on that web)."""
    line = plan.line
    if node not in line.drives:
        return None
    d = line.drives.index(node)
    first = int(plan.di[d, B.DI_CELLS])
    for c in range(first, first + int(plan.di[d, B.DI_NCELLS])):
        if line.spans[int(plan.cells[c, 0])].web == span_web:
            return c
    return None


def _slip_tension(torque: float) -> Callable[[np.ndarray], np.ndarray]:
    """A differential shaft's lane tension [N] at radius r [m]: its clutch's slip torque
    ``torque`` [N·m] over r (the clutch slips all run long)."""
    return lambda r: torque / np.asarray(r, dtype=float)


def branch_wound_rolls(plan: BranchPlan, time: np.ndarray, radius: np.ndarray,
                       tension: np.ndarray) -> dict[str, WoundRoll]:
    """Each rewound roll with a ``roll_stress`` table, by ``roll_name``: ``time`` [s],
    ``radius`` [m] (records x rolls) and span ``tension`` [N] (records x spans) as the run
    recorded them. Its steady roll takes its zone's set tension for its web at the end of
    the run (before taper; without a tension loop on that web, the last recorded tension)
    times the rewind's taper; a lane on a differential shaft its slip torque over the
    radius."""
    line = plan.line
    out: dict[str, WoundRoll] = {}
    if len(time) < 2:
        return out
    for j, roll in enumerate(line.rolls):
        rewind = line.spec.rollers[roll.node]
        spec = getattr(rewind, "roll_stress", None)
        if not isinstance(rewind, RewindSpec) or spec is None:
            continue
        material = line.materials[roll.web]
        entering = line.web_spans(roll.web)[-1]
        cell = _set_cell(plan, roll.node, roll.web)
        base: float | Callable[[np.ndarray], np.ndarray]
        if rewind.shaft is not None:  # a differential shaft: each lane at Q / its radius
            base = _slip_tension(rewind.shaft.slip_torque)
        elif cell is None:
            base = float(tension[-1, entering])
        else:
            base = plan.profile(int(plan.cells[cell, 1]), float(time[-1]))
        name = roll_name(plan, j)
        out[name] = recorded_roll(
            name, spec, time=time, radius=radius[:, j], tension=tension[:, entering],
            core_radius=rewind.core_radius, thickness=material.thickness,
            width=material.width,
            modulus=material.ea / (material.width * material.thickness),
            set_tension=base, taper=rewind.taper,
            taper_acts=cell is not None)
    return out
