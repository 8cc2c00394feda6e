"""The diameter calculator in the compiled loop (docs/winder.md, W2): one update per tick of
the radius a roll drive's controllers use."""

from __future__ import annotations

import math

import numpy as np

from webline.sim.drives.measure import measured_omega, roller_speed
from webline.sim.elements import layout as L
from webline.sim.elements.signals import jit


@jit
def preset_radius(d: int, t: float, dt: float, true_radius: float, istate: np.ndarray,
                  drives: np.ndarray) -> None:
    """Set drive ``d``'s calculated radius at the first tick at or after a preset's time
    (W2a): to the preset diameter / 2, or to ``true_radius`` [m] for a measured one; the
    break monitor's extreme restarts there (a preset is no web break)."""
    for k in range(int(drives[d, L.D_PRESETN])):
        at = drives[d, L.D_PRESETT + k]
        if t - dt < at <= t:
            diameter = drives[d, L.D_PRESETD + k]
            radius = true_radius if diameter <= 0.0 else 0.5 * diameter
            istate[d, L.I_RADIUS] = radius
            istate[d, L.I_REXTREME] = radius


@jit
def update_radius(d: int, i: int, tick: int, dt: float, true_radius: float, x: np.ndarray,
                  istate: np.ndarray, ns: np.ndarray, ds: np.ndarray, offsets: np.ndarray,
                  nodes: np.ndarray, drives: np.ndarray, web: np.ndarray,
                  refs: np.ndarray) -> float:
    """Advance drive ``d``'s calculated radius [m] by one tick ``dt`` [s] and return it; a
    drive without a calculator uses ``true_radius``.

    Both speeds are measured as the controllers measure them (``sim.drives.measure``: noise,
    resolution, the spindle's encoder): ω of the spindle with the radius known so far, and
    v_line from the master roller, a measuring roller or the line-speed reference
    ``refs[0]`` (``D_DSOURCE``). Speed ratio: R_raw = v_line / ω; R follows R_raw through a
    first-order filter (time constant τ: R += (R_raw - R) min(dt/τ, 1)) whose step is
    limited to rate_limit dt / 2, and holds while |v_line| is below hold_below (the ratio of
    two small, noisy speeds means nothing). Thickness: R += ±δ ω dt / 2π (one thickness per
    revolution on the radius), - on the unwind.
    """
    method = drives[d, L.D_DCALC]
    if method == L.DCALC_NONE:
        istate[d, L.I_RADIUS] = true_radius
        return true_radius
    radius = istate[d, L.I_RADIUS]
    omega = measured_omega(d, i, tick, radius, x, ds, offsets, drives, web)
    if method == L.DCALC_THICKNESS:
        sign = -1.0 if ns[i, L.NS_KIND] == L.KIND_UNWIND else 1.0
        radius += sign * web[L.W_THICK] * abs(omega) * dt / (2.0 * math.pi)
    else:
        v_line = line_speed(d, tick, x, ns, ds, offsets, nodes, drives, web, refs)
        if abs(v_line) >= drives[d, L.D_DHOLD] and abs(omega) > 1e-9:
            step = (abs(v_line / omega) - radius) * min(dt / drives[d, L.D_DFILTER], 1.0)
            limit = 0.5 * drives[d, L.D_DRATE] * dt
            radius += min(max(step, -limit), limit)
    radius = max(radius, nodes[i, L.N_CORE])  # no calculator reports less than the core
    istate[d, L.I_RADIUS] = radius
    return radius


@jit
def line_speed(d: int, tick: int, x: np.ndarray, ns: np.ndarray, ds: np.ndarray,
               offsets: np.ndarray, nodes: np.ndarray, drives: np.ndarray, web: np.ndarray,
               refs: np.ndarray) -> float:
    """The line speed [m/s] drive ``d``'s speed-ratio calculator divides: the reference, or
    the measured surface speed of the master or of a measuring roller."""
    source = int(drives[d, L.D_DSOURCE])
    if source == L.DSOURCE_REFERENCE:
        return refs[0]
    node = offsets[L.O_MASTER] if source == L.DSOURCE_MASTER else source
    return roller_speed(node, tick, x, ns, ds, offsets, nodes, drives, web)
