"""The step of a user run (``sim.user_control``): one live tick of the compiled loop, then
the next tick's controller sample on a scratch copy (``sim.user_loop``), in one compiled call
so that a tick costs Python one dispatch."""

from __future__ import annotations

import functools
import math
from typing import TYPE_CHECKING, Any

import numpy as np

from webline.sim import layout as L
from webline.sim.kernel import advance
from webline.sim.signals import jit, loop_njit
from webline.sim.user_loop import (
    N_MEASURED,
    N_REFERENCES,
    STATUS_USER_NONFINITE,
    U_CMD,
    U_SPEED,
    U_VREF,
)

if TYPE_CHECKING:
    from webline.sim.plan import Plan


@jit
def _copy(dst: np.ndarray, src: np.ndarray) -> None:
    """``dst[...] = src`` for 2-d arrays of one shape, without numba's overlap copy (which
    allocates)."""
    for a in range(src.shape[0]):
        for b in range(src.shape[1]):
            dst[a, b] = src[a, b]


def compiled_user_step(plan: Plan) -> Any:
    """The user run's step (``_step``) compiled for ``plan``'s structure (as
    ``kernel.compiled_loop``: one cached step per structure)."""
    ns, ds, offsets = plan.structure()
    return _compiled_step(tuple(map(tuple, ns.tolist())), tuple(map(tuple, ds.tolist())),
                          tuple(offsets.tolist()))


@functools.cache
def _compiled_step(node_rows: tuple[tuple[int, ...], ...],
                   drive_rows: tuple[tuple[int, ...], ...], offset_row: tuple[int, ...]) -> Any:
    ns = np.array(node_rows, dtype=np.int64).reshape(len(node_rows), L.NS_COLS)
    ds = np.array(drive_rows, dtype=np.int64).reshape(len(drive_rows), L.DS_COLS)
    offsets = np.array(offset_row, dtype=np.int64)

    @loop_njit
    def step(live: tuple[Any, ...], scratch: tuple[Any, ...], rec: np.ndarray,
             rec_scratch: np.ndarray, users: np.ndarray, measured: np.ndarray,
             references: np.ndarray, commands: np.ndarray, tick: int, stored: int,
             n_ticks: int, include_end: bool, measure_next: bool, dt: float, substeps: int,
             record_every: int, params: tuple[Any, ...]) -> tuple[int, int, float, int]:
        """Write ``commands`` (one per user drive of ``users``) into the held command row,
        run ``n_ticks`` (0 or 1) live ticks from ``tick`` (records from row ``stored`` of
        ``rec``), then, with ``measure_next``, sample the controllers of tick ``tick +
        n_ticks`` on ``scratch`` into ``measured`` and ``references``. ``live`` and
        ``scratch``: (x, istate, slipping, out, stages, refs, work) as ``kernel.run`` makes
        them, ``out`` with ``U_ROWS`` rows; ``params``: ``Plan.params()``."""
        out = live[3]
        for k in range(users.shape[0]):
            if not math.isfinite(commands[k]):
                return 0, STATUS_USER_NONFINITE, tick * dt, k
            out[U_CMD, users[k]] = commands[k]
        n_rec, status, t_fail, where = 0, L.STATUS_OK, math.nan, -1
        for phase in range(2):  # one call site: the loop is inlined once
            if phase == 1:
                if not measure_next or status != L.STATUS_OK:
                    break
                _copy(scratch[0].reshape((1, -1)), live[0].reshape((1, -1)))
                _copy(scratch[1], live[1])
                _copy(scratch[2].reshape((1, -1)), live[2].reshape((1, -1)))
                _copy(scratch[3], live[3])
                _copy(scratch[6], live[6])
            arrays = live if phase == 0 else scratch
            n_rec_p, status_p, t_fail_p, where_p = advance(
                arrays[0], arrays[1], arrays[2], rec[stored:] if phase == 0 else rec_scratch,
                arrays[3], arrays[4], arrays[5], arrays[6], tick + phase * n_ticks,
                n_ticks if phase == 0 else 0, dt, substeps, record_every,
                include_end if phase == 0 else True, ns, ds, offsets, params[0], params[1],
                params[2], params[3], params[4], params[5], params[6], params[7], params[8])
            if phase == 0:
                n_rec, status, t_fail, where = n_rec_p, status_p, t_fail_p, where_p
        if measure_next and status == L.STATUS_OK:
            sampled = scratch[3]
            for k in range(users.shape[0]):
                for q in range(N_MEASURED):
                    measured[N_MEASURED * k + q] = sampled[U_SPEED + q, users[k]]
                for q in range(N_REFERENCES):
                    references[N_REFERENCES * k + q] = sampled[U_VREF + q, users[k]]
        return n_rec, status, t_fail, where

    return step
