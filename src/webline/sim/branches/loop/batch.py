"""Many cases of one branched structure in one compiled call (the chain's ``sim.sweeps.batch``
for the branch loop): each case runs ``kernel.advance`` over its whole run into its own record
buffer, with the GIL released, so threads running disjoint ranges of cases use every core.

The integer tables are frozen into the compiled function as constants (as
``kernel.compiled_advance``), so a case runs exactly the arithmetic of a run alone; the float
tables, the states and the records carry a leading ``case`` axis.
"""

from __future__ import annotations

import functools
from typing import Any

import numba as nb
import numpy as np

from webline.sim.branches.loop.kernel import advance, structure_key, structure_tables
from webline.sim.elements.signals import _NO_NRT, FAST

batch_njit = nb.njit(cache=True, fastmath=FAST, error_model="numpy", nogil=True, **_NO_NRT)

#: the per-case float tables a batch stacks, in ``run_cases``' order (``BranchPlan`` fields)
CASE_TABLES = ("nodes", "sf", "rolls", "df", "clutch", "events", "dist", "prof_t", "prof_v",
               "prof_off", "lawf", "laws", "fb", "refs")
#: the integer tables frozen into the compiled batch (``BranchPlan`` fields)
FROZEN_TABLES = ("offsets", "si", "layers", "webs", "di", "cells", "cores", "lawi", "kv")


def batch_key(plan: Any) -> tuple[tuple[Any, ...], ...]:
    """The compiled batch's key of ``plan`` (a ``BranchPlan``): its frozen integer tables."""
    return structure_key(*(getattr(plan, name) for name in FROZEN_TABLES))


def compiled_cases(key: tuple[tuple[Any, ...], ...]) -> Any:
    """The batch function of the structure ``key`` (``batch_key``)."""
    return _compiled_cases(*key)


@functools.cache
def _compiled_cases(*key: tuple[Any, ...]) -> Any:
    offsets, si, layers, webs, di, cells, cores, lawi, kv = structure_tables(key)

    @batch_njit
    def run_cases(lo: int, hi: int, x: np.ndarray, istate: np.ndarray, wound: np.ndarray,
                  done: np.ndarray, rec: np.ndarray, cmd: np.ndarray, n_ticks: np.ndarray,
                  dt: np.ndarray, substeps: np.ndarray, every: np.ndarray,
                  speed_max: np.ndarray, nodes: np.ndarray, sf: np.ndarray, rolls: np.ndarray,
                  df: np.ndarray, clutch: np.ndarray, events: np.ndarray, dist: np.ndarray,
                  prof_t: np.ndarray, prof_v: np.ndarray, prof_off: np.ndarray,
                  lawf: np.ndarray, laws: np.ndarray, fb: np.ndarray, refs: np.ndarray,
                  stages: np.ndarray, work: np.ndarray, held: np.ndarray, n_rec: np.ndarray,
                  status: np.ndarray, t_fail: np.ndarray) -> None:
        for c in range(lo, hi):
            work[:] = 0.0  # as a run alone starts with fresh scratch (``BranchPlan.scratch``)
            n_rec[c], status[c], t_fail[c] = advance(
                x[c], istate[c], wound[c], done[c], rec[c], stages, cmd[c], work, held, 0,
                n_ticks[c], dt[c], substeps[c], every[c], True, speed_max[c], offsets,
                nodes[c], si, sf[c], layers, rolls[c], webs, di, df[c], cores, clutch[c],
                cells, events[c], dist[c], prof_t[c], prof_v[c], prof_off[c], lawi, lawf[c],
                laws[c], kv, fb[c], refs[c], None)

    return run_cases
