"""The cascaded PI's draw on a branched line follows the tension references (docs/errata.md,
"One loop"): a drive's speed feedforward is line speed x its steady speed ratio at the
references it runs to now, not at those of t = 0.

Mass flow along a web makes a drive's steady ratio a product of strain factors: v_d (1 - ε_u)
= v_m (1 - ε_a) (the chain's ``speed_feedforward``: (EA - T_a) / (EA - T_u)), a reference
raising the ratio through a denominator (the strain of the web reaching the drive) and
lowering it through a numerator (the strain of the web at the master). The plan holds, per
drive d and loadcell c, a coefficient k_dc from two operating points (``drives.draw``); the
ratio is ratio_0 x Π_c g_c with g_c = 1 + k Δ_c for k <= 0 and 1 / (1 - k Δ_c) for k > 0,
Δ_c the loadcell's reference now less at t = 0: first order in Δ it is the operating point's
sensitivity, and it is exact where the ratio has the mass-flow form (every single web).

``refs`` rows (``sim.branches.plan``): the spans', the drives' (``loop.decentral``), then
``draw_rows``: one per drive (k_dc in column 1 + c), the loadcells' references at t = 0
(column 1 + c; column 0 is 1 where the tables are filled), the design point's and the
current deviations (``loop.decentral``).
"""

from __future__ import annotations

import numpy as np

from webline.sim.branches.loop import layout as B
from webline.sim.elements.signals import jit, profile_at


def draw_rows(n_s: int, n_d: int) -> tuple[int, int]:
    """(first row of the drives' draw coefficients, row of the references at t = 0) of a
    ``refs`` table of ``n_s`` spans and ``n_d`` drives (module docstring)."""
    return n_s + n_d, n_s + 2 * n_d


def refs_rows(n_s: int, n_d: int) -> int:
    """Rows of a plan's ``refs`` table (module docstring)."""
    return n_s + 2 * n_d + 3


@jit
def _reference_now(owner: int, c: int, t: float, istate: np.ndarray, cells: np.ndarray,
                   prof_t: np.ndarray, prof_v: np.ndarray, prof_off: np.ndarray) -> float:
    """Loadcell ``c``'s reference [N] as drive ``owner``'s loop reads it at ``t`` [s]: its
    profile times the drive's taper and ramp factor of the last tick (``I_FACTOR``)."""
    return istate[owner, B.I_FACTOR] * profile_at(cells[c, 1], t, prof_t, prof_v, prof_off)


@jit
def draw_factor(
    d: int,
    t: float,
    tick: int,
    istate: np.ndarray,
    di: np.ndarray,
    cells: np.ndarray,
    refs: np.ndarray,
    prof_t: np.ndarray,
    prof_v: np.ndarray,
    prof_off: np.ndarray,
) -> float:
    """Drive ``d``'s speed ratio now over its ratio at t = 0 (module docstring) at tick
    ``tick`` (time ``t`` [s]): each loadcell's reference is its profile at ``t`` times its
    drive's taper and ramp factor of the last tick (``I_FACTOR``); 1 at the first tick and
    where the plan's references never move (tables not filled)."""
    n_d = di.shape[0]
    start = refs.shape[0] - 3
    if tick == 0 or refs[start, 0] == 0.0:
        return 1.0
    row = start - n_d + d
    factor = 1.0
    for owner in range(n_d):
        for c in range(di[owner, B.DI_CELLS], di[owner, B.DI_CELLS] + di[owner, B.DI_NCELLS]):
            k = refs[row, 1 + c]
            if k == 0.0:
                continue
            change = (_reference_now(owner, c, t, istate, cells, prof_t, prof_v, prof_off)
                      - refs[start, 1 + c])
            factor *= 1.0 + k * change if k < 0.0 else 1.0 / (1.0 - k * change)
    return factor


@jit
def start_references(
    t: float,
    tick: int,
    istate: np.ndarray,
    di: np.ndarray,
    cells: np.ndarray,
    refs: np.ndarray,
    prof_t: np.ndarray,
    prof_v: np.ndarray,
    prof_off: np.ndarray,
) -> None:
    """At a run's first tick, after every drive set its factor: the loadcells' references as
    the loop reads them (a diameter calculator's taper at its own radius), so that a run
    whose references do not move keeps the draw of t = 0 exactly."""
    start = refs.shape[0] - 3
    if tick != 0 or refs[start, 0] == 0.0:
        return
    for owner in range(di.shape[0]):
        for c in range(di[owner, B.DI_CELLS], di[owner, B.DI_CELLS] + di[owner, B.DI_NCELLS]):
            refs[start, 1 + c] = _reference_now(owner, c, t, istate, cells, prof_t, prof_v,
                                                prof_off)
