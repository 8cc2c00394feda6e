"""The compiled loop with users' control laws inside its tick (``sim.compiled_control``).

A compiled law ``law(t, meas, refs, params, state, out)`` runs where a built-in controller
runs: ``controllers.control_tick`` measures every drive as usual (a user drive's measurements
and references go into ``out``'s ``user_loop.U_*`` rows), then calls one compiled function,
the *hook*, which gathers the user drives' measurements into the laws' arrays, calls each
law on its drives' slices and writes their commands back; ``control_tick`` then issues them
through the drive's limit and compensation, and the plant's torque lag and hold follow.

The hook is a ``numba.cfunc`` handed to the loop as a first-class function (numba's
``FunctionType``, an indirect call per tick): the loop's type does not depend on the laws,
so it is compiled and disk-cached once per line structure like the built-in loop, and only
the small hook is compiled per set of laws (in memory; numba has no stable cache key for a
closure over another function). A built-in run passes ``None`` and its loop folds the hook
away.
"""

from __future__ import annotations

import functools
from typing import TYPE_CHECKING, Any

import numba as nb
import numpy as np

from webline.sim.core.kernel import advance
from webline.sim.core.laws import LawKey, buffer_layout, chained_laws
from webline.sim.core.plan import StructureKey, structure_arrays
from webline.sim.drives.user_loop import (
    N_MEASURED,
    N_REFERENCES,
    U_CMD,
    U_ROWS,
    U_SPEED,
    U_VREF,
)
from webline.sim.elements import layout as L
from webline.sim.elements.signals import _NO_NRT, FAST, loop_njit
from webline.sim.elements.web_state import record_width

if TYPE_CHECKING:
    from webline.sim.core.plan import Plan

#: the hook's type: (t [s], out (``U_ROWS`` x drives), buffer) -> None
HOOK_SIGNATURE = nb.void(nb.float64, nb.float64[:, ::1], nb.float64[::1])


@functools.cache
def law_hook(users: tuple[int, ...], laws: LawKey) -> Any:
    """The hook (module docstring) for user drives ``users`` (indices into the drive table,
    in group order) and ``laws`` (``laws.chained_laws``: per group its dispatcher, number of
    drives, of parameters and of state values). Compiled once per (users, laws) in a
    process."""
    layout = buffer_layout(len(users), sum(p for _, _, p, _ in laws),
                           sum(s for _, _, _, s in laws))
    call = chained_laws(laws)
    drive_of = np.array(users, dtype=np.int64)
    (m0, m1), (r0, r1), (c0, c1) = layout["meas"], layout["refs"], layout["commands"]
    (q0, q1), (s0, s1), (f0, f1) = layout["params"], layout["state"], layout["raised"]

    @nb.cfunc(HOOK_SIGNATURE, fastmath=FAST, error_model="numpy", **_NO_NRT)
    def hook(t: float, out: np.ndarray, buf: np.ndarray) -> None:
        meas, refs, commands = buf[m0:m1], buf[r0:r1], buf[c0:c1]
        for u in range(drive_of.shape[0]):
            for q in range(N_MEASURED):
                meas[N_MEASURED * u + q] = out[U_SPEED + q, drive_of[u]]
            for q in range(N_REFERENCES):
                refs[N_REFERENCES * u + q] = out[U_VREF + q, drive_of[u]]
        call(t, meas, refs, buf[q0:q1], buf[s0:s1], commands, buf[f0:f1])
        for u in range(drive_of.shape[0]):  # NaN after a law raised: the loop stops there
            out[U_CMD, drive_of[u]] = commands[u] if buf[f0] == 0.0 else np.nan

    return hook


def run(plan: Plan, x0: np.ndarray, istate0: np.ndarray, slip0: np.ndarray, tick0: int,
        n_ticks: int, substeps: int, record_every: int, include_end: bool, rec: np.ndarray,
        hook: Any, buf: np.ndarray,
        ) -> tuple[int, int, float, int, np.ndarray, np.ndarray, np.ndarray]:
    """``kernel.run`` with the user drives' laws in the loop (``hook``, its buffer ``buf``):
    returns (records written into ``rec``, status, time of failure [s], where, final state,
    controller memory, stick/slip states). Status ``user_loop.STATUS_USER_NONFINITE``: a law
    gave drive ``where`` a non-finite command at the time of failure, before that tick was
    recorded."""
    n_x, n_d, n_n = x0.shape[0], plan.drives.shape[0], plan.nodes.shape[0]
    assert rec.shape[1] == record_width(n_x, n_d, n_n)
    x, istate, slipping = x0.copy(), istate0.copy(), slip0.copy()
    out = np.zeros((U_ROWS, n_d))
    stages = np.empty((5, n_x))
    refs = np.empty((4, max(plan.prof_off.shape[0] - 1, n_n)))
    work = np.zeros((2, 3 * n_n))
    n_rec, status, t_fail, where = compiled_law_loop(plan)(
        x, istate, slipping, rec, out, stages, refs, work, tick0, n_ticks, plan.dt, substeps,
        record_every, include_end, *plan.params(), hook, buf)
    return n_rec, status, t_fail, where, x, istate, slipping


def compiled_law_loop(plan: Plan) -> Any:
    """The loop with a hook, compiled for ``plan``'s structure (as ``kernel.compiled_loop``;
    a structure with user drives, ``layout.FAMILY_USER``)."""
    ds = plan.drive_structure
    assert (ds[:, L.DS_FAMILY] == L.FAMILY_USER).any()
    return _compiled(plan.structure_key())


@functools.cache
def _compiled(key: StructureKey) -> Any:
    ns, ds, offsets = structure_arrays(key)  # as ``kernel._compiled``: one loop per structure

    @loop_njit
    def loop(x: np.ndarray, istate: np.ndarray, slipping: np.ndarray, rec: np.ndarray,
             out: np.ndarray, stages: np.ndarray, refs: np.ndarray, work: np.ndarray,
             tick0: int, n_ticks: int, dt: float, substeps: int, record_every: int,
             include_end: bool, nodes: np.ndarray, spans: np.ndarray, drives: np.ndarray,
             web: np.ndarray, wound_ripple: np.ndarray, speed_ripple: np.ndarray,
             prof_t: np.ndarray, prof_v: np.ndarray, prof_off: np.ndarray, hook: Any,
             buf: np.ndarray) -> tuple[int, int, float, int]:
        return advance(x, istate, slipping, rec, out, stages, refs, work, tick0, n_ticks, dt,
                       substeps, record_every, include_end, ns, ds, offsets, nodes, spans,
                       drives, web, wound_ripple, speed_ripple, prof_t, prof_v, prof_off,
                       hook, buf)

    return loop
