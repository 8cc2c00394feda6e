"""Kelvin-Voigt spans outside the compiled loop (docs/winder.md, Viscoelastic span): the
tension the rollers feel in recorded results and in the linear model.

A span's state stays its stretch s = EA ε, which mass conservation moves (thesis 6.8, the
upstream span's strain transported); the rollers, loadcells and dancers feel
T = s + τ ds/dt, τ the span's retardation time (``layout.S_TAU``, 0 for an elastic span).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from webline.sim import kernel
from webline.sim import layout as L
from webline.sim.signals import jit

if TYPE_CHECKING:
    from webline.sim.plan import Plan


def felt_tension(plan: Plan, time: np.ndarray, states: np.ndarray,
                 slipping: np.ndarray) -> np.ndarray:
    """Tension [N] each span's rollers feel at each record (time [s], states, stick/slip
    states), evaluated by the kernel's own right-hand side: s + τ ds/dt while taut, 0 slack
    or broken (``felt_records``)."""
    ns, ds, offsets = plan.structure()
    n_n = plan.nodes.shape[0]
    out = np.empty((len(time), n_n - 1))
    scratch = np.zeros((4, max(states.shape[1], 3 * n_n)))
    felt_records(np.asarray(time, dtype=float), np.asarray(states, dtype=float),
                 np.asarray(slipping, dtype=float), out, np.zeros(n_n, dtype=np.int64),
                 scratch, ns, ds, offsets, plan.nodes, plan.spans, plan.drives, plan.web,
                 plan.wound_ripple)
    return out


@jit
def felt_records(time: np.ndarray, states: np.ndarray, slipping: np.ndarray, out: np.ndarray,
                 slip: np.ndarray, scratch: np.ndarray, ns: np.ndarray, ds: np.ndarray,
                 offsets: np.ndarray, nodes: np.ndarray, spans: np.ndarray,
                 drives: np.ndarray, web: np.ndarray, wound_ripple: np.ndarray) -> None:
    """The felt tensions of ``felt_tension`` into ``out`` (records x spans), compiled: used
    by a ``Result`` and, inlined, by the batched kernel (``sim.batch``). No commands or drags
    act (the spans do not see them); a span is broken from its break time on. ``slip``:
    integer scratch per node; ``scratch``: 4 rows (commands, drags and flags, derivative,
    the right-hand side's work) of at least max(states, 3 x nodes)."""
    n_n = ns.shape[0]
    n_x = states.shape[1]
    cmd, drag = scratch[0, :ds.shape[0]], scratch[1, :3 * n_n]
    dx, work = scratch[2, :n_x], scratch[3, :3 * n_n]
    cmd[:] = 0.0
    drag[:] = 0.0
    for r in range(time.shape[0]):
        t = time[r]
        for k in range(n_n - 1 if offsets[L.O_BREAK] else 0):  # the kernel's flag
            drag[2 * n_n + k] = 1.0 if t >= spans[k, L.S_BREAK] else 0.0
        for i in range(n_n):
            slip[i] = int(slipping[r, i])
        kernel.rhs(kernel.wound_in(t, web, wound_ripple), states[r], cmd, drag, slip, ns, ds,
                   offsets, nodes, spans, drives, web, dx, work)
        for k in range(n_n - 1):
            out[r, k] = work[2 * n_n + k]


def felt_rows(plan: Plan, a: np.ndarray, e: np.ndarray,
              slopes: np.ndarray | None = None) -> np.ndarray:
    """Rows M [N per state unit] of the felt tensions T = M x (+ τ E t0) of a linear plant
    dx = A x + E t0 whose first n_s states are the span stretches and whose other rows were
    written with the felt tensions in the stretch columns; substitutes T = s + τ (A_s x +
    E_s t0) into those rows of ``a`` and ``e`` in place (span rows keep the stretch: mass
    conservation transports strain). ``slopes``: F'(s) [-] of each span at the operating
    point, for a nonlinear law (docs/nonlinear-web.md, N2: T = F(s) + τ ds/dt). Linear
    elastic lines are left untouched (M = [I 0])."""
    n_s = plan.spans.shape[0]
    tau = plan.spans[:, L.S_TAU]
    rows = np.eye(n_s, a.shape[1])
    if not plan.offsets[L.O_KV]:
        return rows
    extra, extra_e = tau[:, None] * a[:n_s], tau * e[:n_s, 0]
    if slopes is not None:  # a nonlinear law: δT = F'(s) δs
        extra[:, :n_s] += np.diag(slopes - 1.0)
    coef = a[n_s:, :n_s].copy()  # what the other rows take from the span tensions
    a[n_s:] += coef @ extra
    e[n_s:, 0] += coef @ extra_e
    return rows + extra


def measured(plan: Plan, gain: np.ndarray, felt: np.ndarray,
             e: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """A controller's gains ``gain`` (rows over the plant states, span tensions in the first
    n_s columns) acting on the felt tensions ``felt`` = M (``felt_rows``) instead, and the
    column they then take from the wound-in tension through τ E_s (plant ``e``)."""
    n_s = plan.spans.shape[0]
    tau = plan.spans[:, L.S_TAU]
    if not plan.offsets[L.O_KV]:
        return gain, np.zeros((gain.shape[0], 1))
    out = gain.copy()
    out[:, :felt.shape[1]] += gain[:, :n_s] @ (felt - np.eye(n_s, felt.shape[1]))
    return out, gain[:, :n_s] @ (tau * e[:n_s, 0])[:, None]

