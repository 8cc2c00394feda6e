"""The PI drives' draw coefficients of a branched line (``loop.draw``, docs/errata.md "One
loop"): how each drive's steady speed ratio moves with each loadcell's reference."""

from __future__ import annotations

import dataclasses

import numpy as np

from webline.sim.branches.equilibrium import BranchPoint, operating_point, references
from webline.sim.branches.loop import layout as B
from webline.sim.branches.loop.draw import draw_rows
from webline.sim.branches.plan import BranchPlan

#: The reference step [N] of the second operating point (the coefficient is the secant of the
#: mass-flow form, so any step gives it exactly where that form holds; 1 N keeps the solver's
#: 1e-13 tolerance 1e-9 of the ratio's change).
STEP = 1.0


def references_move(plan: BranchPlan) -> bool:
    """Whether a loadcell's reference can change during a run: a profile that is not
    constant, a taper, or the tension ramp (without any, the draw stays that of t = 0)."""
    if plan.offsets[B.O_RAMP] >= 0 or np.any(plan.df[:, B.D_TAPER_KIND] != 0.0):
        return True
    for p in plan.cells[:, 1]:
        values = plan.prof_v[plan.prof_off[p] : plan.prof_off[p + 1]]
        if np.ptp(values) > 0.0:
            return True
    return False


def fill_draw(plan: BranchPlan, point: BranchPoint, *, always: bool = False) -> None:
    """Fill ``plan.refs``' draw rows (``loop.draw``) from ``point``, the operating point at
    t = 0, and one more per loadcell with its reference ``STEP`` higher, for the PI and user
    drives (the decentralized ones follow ``loop.decentral``); nothing where no reference
    moves during the run, unless ``always`` (a ``Session``, whose references a user sets)."""
    n_s, n_d = len(plan.line.spans), plan.di.shape[0]
    pi = np.isin(plan.di[:, B.DI_FAMILY], (B.FAMILY_PI, B.FAMILY_USER))
    if not np.any(pi) or not (always or references_move(plan)):
        return
    first, start = draw_rows(n_s, n_d)
    refs0 = references(plan, 0.0)
    for c, (k, p, *_) in enumerate(plan.cells):
        if plan.cells.shape[1] > B.CELL_DANCER and plan.cells[c, B.CELL_DANCER] >= 0:
            continue  # a dancer's position is no tension reference
        plan.refs[start, 1 + c] = refs0[k]
        prof_v = plan.prof_v.copy()
        prof_v[plan.prof_off[p] : plan.prof_off[p + 1]] += STEP
        moved_plan = dataclasses.replace(plan, prof_v=prof_v)
        moved = operating_point(moved_plan, 0.0)
        step = references(moved_plan, 0.0)[k] - refs0[k]  # STEP times the taper and ramp
        for d in np.flatnonzero(pi):
            r0, r1 = point.ratio[d], moved.ratio[d]
            if r0 == 0.0 or r1 == r0:
                continue
            # a numerator (1 - ε_a) is linear in its reference, a denominator's reciprocal is
            plan.refs[first + d, 1 + c] = ((1.0 - r0 / r1) if r1 > r0 else (r1 / r0 - 1.0)) / step
    plan.refs[start, 0] = 1.0


def draw_coefficients(plan: BranchPlan) -> np.ndarray:
    """k_dc (``loop.draw``) per drive and loadcell, filling the plan's draw rows first where
    they are empty (the linear model's reference inputs: ∂(v ratio_d)/∂ref_c = v ratio_d k_dc,
    as the chain's draw term −V/(EA − T₀), docs/errata.md)."""
    n_s, n_d = len(plan.line.spans), plan.di.shape[0]
    first, start = draw_rows(n_s, n_d)
    if plan.refs[start, 0] == 0.0:  # into a copy: the plan's stay empty where no reference
        # moves, so that its run's draw factor is 1 without work (``loop.draw``; issue 33)
        plan = dataclasses.replace(plan, refs=plan.refs.copy())
        fill_draw(plan, operating_point(plan, 0.0), always=True)
    return plan.refs[first:first + n_d, 1:].copy()
