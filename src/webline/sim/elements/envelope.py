"""The physical envelope a run must stay inside, checked every tick in the compiled loop, and
the effective radius of a node it needs (``webline.sim.core.kernel``, issue 11's runaway checks)."""

from __future__ import annotations

import math

import numpy as np

from webline.sim.elements import layout as L
from webline.sim.elements.signals import jit


@jit
def node_radius(i: int, x: np.ndarray, ns: np.ndarray, offsets: np.ndarray,
                nodes: np.ndarray) -> float:
    """Radius [m] a drive works with: the roll radius state, or the nominal roller radius."""
    kind = ns[i, L.NS_KIND]
    if kind == L.KIND_UNWIND:
        return x[offsets[L.O_RADIUS]]
    if kind == L.KIND_REWIND:
        return x[offsets[L.O_RADIUS] + 1]
    return nodes[i, L.N_RADIUS]


@jit
def node_arm(i: int, x: np.ndarray, ns: np.ndarray, offsets: np.ndarray,
             nodes: np.ndarray) -> float:
    """Effective radius [m] of node ``i``: roll radius state or roller radius, plus an
    eccentricity e cos(angle) (an out-of-round roll rides it on its changing radius,
    docs/winder.md E1)."""
    ecc_state = ns[i, L.NS_ECCSTATE]
    if ecc_state >= 0:
        kind = ns[i, L.NS_KIND]
        base = nodes[i, L.N_RADIUS]
        if kind == L.KIND_UNWIND or kind == L.KIND_REWIND:
            base = node_radius(i, x, ns, offsets, nodes)
        return base + nodes[i, L.N_ECC] * math.cos(x[ecc_state])
    return node_radius(i, x, ns, offsets, nodes)



@jit
def envelope(x: np.ndarray, ns: np.ndarray, ds: np.ndarray, offsets: np.ndarray,
             nodes: np.ndarray, drives: np.ndarray, web: np.ndarray) -> tuple[int, int]:
    """(status, where) of a finite state against the physical envelope (``layout`` W_STRENGTH,
    W_STRETCH_MAX, W_SPEED_MAX): the web's strength [N] per span, the runaway stretch [N] per
    span, the runaway surface speed [m/s] per node and, through the ratio, per motor of a
    compliant transmission; (STATUS_OK, -1) inside it."""
    strength, stretch_max, speed_max = web[L.W_STRENGTH], web[L.W_STRETCH_MAX], web[L.W_SPEED_MAX]
    for k in range(ns.shape[0] - 1):
        if x[k] > strength:
            return L.STATUS_STRENGTH, k
        if abs(x[k]) > stretch_max:
            return L.STATUS_RUNAWAY_STRETCH, k
    off_w = offsets[L.O_OMEGA]
    for i in range(ns.shape[0]):
        if abs(node_arm(i, x, ns, offsets, nodes) * x[off_w + i]) > speed_max:
            return L.STATUS_RUNAWAY_SPEED, i
    for d in range(ds.shape[0]):
        state = ds[d, L.DS_TSTATE]
        if state >= 0:
            arm = node_arm(ds[d, L.DS_NODE], x, ns, offsets, nodes)
            if abs(x[state] / drives[d, L.D_RATIO] * arm) > speed_max:
                return L.STATUS_RUNAWAY_MOTOR, d
    return L.STATUS_OK, -1
