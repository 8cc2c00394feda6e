"""Dancers in a branched line's compiled loop (docs/branching.md, "Dancers"; the chain's
``sim.elements.dancer_loop``, docs/winder.md D0-D2): the spans a carriage joins lengthen with
its excursion, and the carriage moves under its load, the spans' pull, its spring, damper and
end stops. Tables in ``sim.branches.loop.layout``."""

from __future__ import annotations

import numpy as np

from webline.sim.branches.loop import layout as B
from webline.sim.elements.signals import jit, profile_at


@jit
def span_motion(k: int, x: np.ndarray, nodes: np.ndarray, si: np.ndarray,
                sf: np.ndarray) -> tuple[float, float]:
    """(length [m], rate of lengthening [m/s]) of span ``k``: its file length plus
    g (y - y_set) of a dancer at either end (D0, g = (strands/2) cos(angle))."""
    length, rate = sf[k, B.SF_LENGTH], 0.0
    state = si[k, B.S_DANCEA]
    if state >= 0:
        gain = sf[k, B.SF_GAINA]
        length += gain * (x[state] - nodes[si[k, B.S_A], B.N_DSET])
        rate += gain * x[state + 1]
    state = si[k, B.S_DANCEB]
    if state >= 0:
        gain = sf[k, B.SF_GAINB]
        length += gain * (x[state] - nodes[si[k, B.S_B], B.N_DSET])
        rate += gain * x[state + 1]
    return length, rate


@jit
def moving_span_rate(k: int, x: np.ndarray, fixed_rate: float, nodes: np.ndarray,
                     si: np.ndarray, sf: np.ndarray, exact: bool) -> float:
    """d(stretch)/dt [N/s] of span ``k`` beside a dancer from ``fixed_rate``, the rate
    ``physics.span.stretch_rate`` gives at its file length: L ds/dt = EA (v_b - v_a) +
    T_in v_a - T v_b + (EA - s) dL/dt (docs/winder.md D1: d/dt[L (1 - s/EA)] is the web
    in less the web out). ``exact``: ``fixed_rate`` from ``physics.span.exact_stretch_rate``,
    whose (EA + s)² factor makes it L/L' x the moving span's, which gains (EA + s) dL/dt / L
    (d/dt[L/(1 + ε)])."""
    length, rate = span_motion(k, x, nodes, si, sf)
    if exact:
        return (fixed_rate * sf[k, B.SF_LENGTH] + (sf[k, B.SF_EA] + x[k]) * rate) / length
    return (fixed_rate * sf[k, B.SF_LENGTH] + (sf[k, B.SF_EA] - x[k]) * rate) / length


@jit
def carriage_rates(x: np.ndarray, felt: np.ndarray, held: np.ndarray, offsets: np.ndarray,
                   nodes: np.ndarray, si: np.ndarray, sf: np.ndarray, dx: np.ndarray) -> None:
    """dy/dt and dv/dt of every carriage into ``dx`` (D2): M dv/dt = load - g_in T_in -
    g_out T_out - k (y - y_set) - c v, plus an end-stop spring-damper beyond 0 and the
    travel; T the tensions the roller feels ``felt`` [N], the load [N] of dancer n held over
    the tick in ``held``, whose last entries are the dancers' loads."""
    first = offsets[B.O_DANCER]
    first_load = held.shape[0] - (offsets[B.O_DANCER_END] - first) // 2
    for k in range(si.shape[0]):
        state = si[k, B.S_DANCEB]
        if state < 0:
            continue
        i, out = si[k, B.S_B], si[k, B.S_DOUT]
        y, vy = x[state], x[state + 1]
        force = (held[first_load + (state - first) // 2] - sf[k, B.SF_GAINB] * felt[k]
                 - sf[out, B.SF_GAINA] * felt[out] - nodes[i, B.N_DK] * (y - nodes[i, B.N_DSET])
                 - nodes[i, B.N_DC] * vy)
        beyond = min(y, 0.0) + max(y - nodes[i, B.N_DTRAVEL], 0.0)
        if beyond != 0.0:
            force -= nodes[i, B.N_DSTOP] * beyond + nodes[i, B.N_DSTOPC] * vy
        dx[state] = vy
        dx[state + 1] = force * nodes[i, B.N_DINVM]


@jit
def position_error(node: int, x: np.ndarray, nodes: np.ndarray) -> float:
    """What a drive's tension loop reads from the dancer on ``node`` in position control
    (D3): y - y_set [m], in place of T_ref - T (gains in (m/s)/m)."""
    return x[int(nodes[node, B.N_DSTATE])] - nodes[node, B.N_DSET]


@jit
def sensed_tension(node: int, t: float, x: np.ndarray, offsets: np.ndarray, nodes: np.ndarray,
                   dist: np.ndarray, prof_t: np.ndarray, prof_v: np.ndarray,
                   prof_off: np.ndarray) -> float:
    """What a drive's tension loop reads from the dancer on ``node`` as a tension sensor
    (D3, the chain's ``dancer_measurement``): the carriage's static balance, T = (load -
    k (y - y_set)) / (g_in + g_out) [N], the load [N] its profile's value at ``t`` (the
    dancers' ``DIST_DANCER_LOAD`` rows come in the order of their states)."""
    n = (int(nodes[node, B.N_DSTATE]) - offsets[B.O_DANCER]) // 2
    load, m = 0.0, 0
    for r in range(dist.shape[0]):
        if int(dist[r, B.DS_KIND]) == B.DIST_DANCER_LOAD:
            if m == n:
                load = dist[r, B.DS_B] * profile_at(int(dist[r, B.DS_A]), t, prof_t, prof_v,
                                                    prof_off)
                break
            m += 1
    spring = nodes[node, B.N_DK] * (x[int(nodes[node, B.N_DSTATE])] - nodes[node, B.N_DSET])
    return (load - spring) / nodes[node, B.N_DGSUM]
