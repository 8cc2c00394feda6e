"""Bonded laminates in a branched line's compiled loop (docs/branching.md, (B2);
tables: ``sim.branches.laminates``, ``layout`` LI_SPAN .. LF_STRENGTH).

Each layer of a laminate span (law term t: raw web r, scale a, factor c) has its own stretch
u = a s + o [N] = EA_r ε_r, s the span's stretch and o the term's offset state. Its tension
is its raw web's law mirrored in compression (a bonded layer is held straight by the others,
classical lamination theory); the span's, their sum, at least 0 (the laminate as a whole
goes slack). The offset is advected as the strain is (first-order mass balance of each
layer, 6.8, less the span's own): L do/dt = v_a o_in - v_b o, and o_in makes the layer's
stretch in equal the stretch it leaves the span upstream with, u_up = a_up s_up + o_up,
so each layer's unstrained length is conserved through every nip.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from webline.physics import web_law
from webline.sim.branches.loop import layout as B
from webline.sim.branches.loop.dancer import span_motion
from webline.sim.elements.signals import jit

_law_tension: Any = jit(web_law.law_tension)


@jit
def layer_tension(t: int, u: float, lawi: np.ndarray, laws: np.ndarray) -> float:
    """Tension [N] of law term ``t``'s raw web at its own stretch ``u`` [N], its law
    mirrored in compression (F(-u) = -F(u))."""
    law = laws[lawi[t, B.LI_START] :]
    if u >= 0.0:
        return _law_tension(u, law)
    return -_law_tension(-u, law)


@jit
def bonded_tension(
    k: int, x: np.ndarray, si: np.ndarray, lawi: np.ndarray, lawf: np.ndarray, laws: np.ndarray
) -> float:
    """Elastic tension [N] of bonded span ``k``: Σ c F_r(a s + o) over its layers, at
    least 0."""
    first, count = si[k, B.S_LAW0], si[k, B.S_NLAW]
    total = 0.0
    for t in range(first, first + count):
        u = lawf[t, B.LF_SCALE] * x[k] + x[lawi[t, B.LI_STATE]]
        total += lawf[t, B.LF_FACTOR] * layer_tension(t, u, lawi, laws)
    return total if total > 0.0 else 0.0


@jit
def layer_rates(
    x: np.ndarray,
    dx: np.ndarray,
    lawi: np.ndarray,
    lawf: np.ndarray,
    sf: np.ndarray,
    tension: np.ndarray,
    s_in: np.ndarray,
    v_a: np.ndarray,
    v_b: np.ndarray,
    wound: np.ndarray,
    cut0: int,
    nodes: np.ndarray,
    si: np.ndarray,
    has_dancer: bool,
    exact: bool,
) -> None:
    """d/dt of every layer's offset [N/s] and of its unstrained length in and out [m/s]
    (module docstring); ``tension``: the spans' clipped stretches (a slack span leaves
    unstrained), ``s_in``: their stretches in; ``wound[cut0 + k]`` non-zero where span k is
    broken (its offsets stay; ``cut0`` < 0: no break in the run). Beside a dancer the span's
    length L moves: L do/dt = v_a o_in - v_b o - o dL/dt (docs/winder.md D1, per layer).

    ``exact`` (``web.transport``, errata E-6.6): each layer's own mass balance,
    d/dt[L EA/(EA + u)] = v_a EA/(EA + u_in) - v_b EA/(EA + u_out), solved for its stretch
    u = a s + o: du/dt = (EA + u)/L [dL/dt + (EA + u)(v_b/(EA + u_out) - v_a/(EA + u_in))],
    and do/dt = du/dt - a ds/dt with the laminate's ds/dt (already in ``dx``)."""
    for t in range(lawi.shape[0]):
        state = lawi[t, B.LI_STATE]
        if state < 0:
            continue
        k = lawi[t, B.LI_SPAN]
        a = lawf[t, B.LF_SCALE]
        up = lawi[t, B.LI_UP]
        u_in = lawf[t, B.LF_UPSCALE] * tension[up]
        if lawi[t, B.LI_UPSTATE] >= 0:
            u_in += x[lawi[t, B.LI_UPSTATE]]
        o_in = u_in - a * s_in[k]
        o = x[state]
        broken = cut0 >= 0 and wound[cut0 + k] != 0.0
        length, moving = sf[k, B.SF_LENGTH], 0.0
        if has_dancer and (si[k, B.S_DANCEA] >= 0 or si[k, B.S_DANCEB] >= 0):
            length, moving = span_motion(k, x, nodes, si, sf)
        ea = lawf[t, B.LF_EA]
        if exact:
            u = a * x[k] + o
            u_out = a * tension[k] + o
            flows = v_b[k] / (ea + u_out) - v_a[k] / (ea + u_in)
            dx[state] = (ea + u) * (moving + (ea + u) * flows) / length - a * dx[k]
        else:
            dx[state] = (v_a[k] * o_in - v_b[k] * o - o * moving) / length
        if broken:
            dx[state] = 0.0
        if exact:
            if lawi[t, B.LI_LIN] >= 0:
                dx[lawi[t, B.LI_LIN]] = v_a[k] * ea / (ea + u_in)
            if lawi[t, B.LI_LOUT] >= 0:
                dx[lawi[t, B.LI_LOUT]] = v_b[k] * ea / (ea + a * tension[k] + o)
            continue
        inv_ea = 1.0 / ea
        if lawi[t, B.LI_LIN] >= 0:
            dx[lawi[t, B.LI_LIN]] = v_a[k] * (1.0 - u_in * inv_ea)
        if lawi[t, B.LI_LOUT] >= 0:
            dx[lawi[t, B.LI_LOUT]] = v_b[k] * (1.0 - (a * tension[k] + o) * inv_ea)


@jit
def beyond_strength(x: np.ndarray, lawi: np.ndarray, lawf: np.ndarray) -> bool:
    """Whether any bonded layer's own stretch is beyond its strength's."""
    for t in range(lawi.shape[0]):
        state = lawi[t, B.LI_STATE]
        if state >= 0 and (
            lawf[t, B.LF_SCALE] * x[lawi[t, B.LI_SPAN]] + x[state] > lawf[t, B.LF_STRENGTH]
        ):
            return True
    return False


@jit
def cut_layers(x: np.ndarray, wound: np.ndarray, cut0: int, lawi: np.ndarray) -> None:
    """A broken span's layers carry nothing: their offsets to 0 with its stretch
    (``loop.breaks.cut``; ``wound[cut0 + k]`` non-zero where span k is broken)."""
    for t in range(lawi.shape[0]):
        if lawi[t, B.LI_STATE] >= 0 and wound[cut0 + lawi[t, B.LI_SPAN]] != 0.0:
            x[lawi[t, B.LI_STATE]] = 0.0
