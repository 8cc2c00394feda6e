"""The dancer's equations in the compiled loop (docs/winder.md, D1-D2): the lengths of the
spans a dancer joins and the force balance of its carriage."""

from __future__ import annotations

import numpy as np

from webline.sim.elements import layout as L
from webline.sim.elements.signals import jit


@jit
def span_motion(k: int, x: np.ndarray, ns: np.ndarray, nodes: np.ndarray,
                spans: np.ndarray) -> tuple[float, float]:
    """(length [m], rate of lengthening [m/s]) of span ``k``: its file length plus g times
    the excursion y - y_set of a dancer at either end (D0: g = (strands/2) cos(angle) of
    the dancer's downstream span (node k) or upstream span (node k + 1))."""
    length, rate = spans[k, L.S_LENGTH], 0.0
    for i in (k, k + 1):
        state = ns[i, L.NS_DANCER]
        if state >= 0:
            if ns[i, L.NS_DGEOM]:  # strands or angles (D0)
                gain = nodes[i, L.N_DGOUT] if i == k else nodes[i, L.N_DGIN]
                length += gain * (x[state] - nodes[i, L.N_DSET])
                rate += gain * x[state + 1]
            else:  # a plain dancer, g = 1
                length += x[state] - nodes[i, L.N_DSET]
                rate += x[state + 1]
    return length, rate


@jit
def dancer_rate(i: int, x: np.ndarray, ns: np.ndarray, nodes: np.ndarray, pull: float,
                load: float, dx: np.ndarray) -> None:
    """Carriage of the dancer on node ``i`` (docs/winder.md, D2): M d²y/dt² = load - (g_in T_in
    + g_out T_out) - k (y - y_set) - c dy/dt, plus an end-stop spring-damper beyond 0 and the
    travel; ``pull`` = g_in T_in + g_out T_out [N], ``load`` [N] held over the tick."""
    state = ns[i, L.NS_DANCER]
    y, vy = x[state], x[state + 1]
    force = load - pull - nodes[i, L.N_DK] * (y - nodes[i, L.N_DSET]) - nodes[i, L.N_DC] * vy
    beyond = min(y, 0.0) + max(y - nodes[i, L.N_DTRAVEL], 0.0)
    if beyond != 0.0:
        force -= nodes[i, L.N_DSTOP] * beyond + nodes[i, L.N_DSTOPC] * vy
    dx[state] = vy
    dx[state + 1] = force * nodes[i, L.N_DINVM]


@jit
def dancer_measurement(d: int, x: np.ndarray, ns: np.ndarray, ds: np.ndarray,
                       nodes: np.ndarray, refs: np.ndarray) -> float:
    """What drive ``d``'s tension loop reads from its zone's dancer (docs/winder.md, D3):
    as a tension sensor, T = (load - k (y - y_set)) / 2 [N]; for position control, the
    reference less the position error y - y_set, so that the loop's error T_ref - T_meas is
    y - y_set [m] (gains in (m/s)/m, ``sim.core.dancer.drive_columns``)."""
    i = ds[d, L.DS_DANCER]
    y = x[ns[i, L.NS_DANCER]] - nodes[i, L.N_DSET]
    if ds[d, L.DS_DUSE] == L.DANCER_TENSION:
        if ns[i, L.NS_DGEOM]:  # strands or angles (D2 at rest)
            return ((refs[int(nodes[i, L.N_DLOAD])] - nodes[i, L.N_DK] * y)
                    / (nodes[i, L.N_DGIN] + nodes[i, L.N_DGOUT]))
        return 0.5 * (refs[int(nodes[i, L.N_DLOAD])] - nodes[i, L.N_DK] * y)
    return refs[ds[d, L.DS_REF]] - y
