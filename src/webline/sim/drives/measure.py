"""What the drives measure (compiled): surface and angular speeds with the line's measurement
noise and resolution (``measurement_noise``), one path for the controllers and the diameter
calculators (docs/winder.md W2), so both see the same numbers."""

from __future__ import annotations

import numpy as np

from webline.sim.elements import layout as L
from webline.sim.elements.signals import gaussian, jit


@jit
def quantized(value: float, step: float) -> float:
    """``value`` rounded to a multiple of ``step`` (``step`` <= 0: unchanged)."""
    if step <= 0.0:
        return value
    return step * np.floor(value / step + 0.5)


@jit
def measured_speed(d: int, i: int, tick: int, radius: float, x: np.ndarray, ds: np.ndarray,
                   offsets: np.ndarray, drives: np.ndarray, web: np.ndarray) -> float:
    """Surface speed [m/s] drive ``d`` on node ``i`` measures at tick ``tick`` with the radius
    ``radius`` [m] it knows: r ω of its encoder (the motor's / n across a compliant
    transmission with motor-side feedback) times its encoder's scale (``spec.sensors``), plus
    the speed noise of channel 2 d, rounded to the speed resolution."""
    v_meas = radius * x[offsets[L.O_OMEGA] + i]
    if ds[d, L.DS_FEEDBACK] > 0 and ds[d, L.DS_TSTATE] >= 0:
        v_meas = radius * x[ds[d, L.DS_TSTATE]] / drives[d, L.D_RATIO]
    if offsets[L.O_SENSORS]:  # the encoder's scale (spec.sensors)
        v_meas *= drives[d, L.D_VSCALE]
    if offsets[L.O_NOISE]:
        if web[L.W_NOISE_V] > 0.0:
            v_meas += web[L.W_NOISE_V] * gaussian(int(web[L.W_SEED]), tick, 2 * d)
        v_meas = quantized(v_meas, web[L.W_RES_V])
    return v_meas


@jit
def measured_omega(d: int, i: int, tick: int, radius: float, x: np.ndarray, ds: np.ndarray,
                   offsets: np.ndarray, drives: np.ndarray, web: np.ndarray) -> float:
    """Angular speed [rad/s] of node ``i`` as drive ``d``'s encoder gives it: the same
    measurement as ``measured_speed`` (its noise and resolution, over ``radius`` [m])."""
    if not (offsets[L.O_NOISE] or offsets[L.O_SENSORS]) and not (
            ds[d, L.DS_FEEDBACK] > 0 and ds[d, L.DS_TSTATE] >= 0):
        return x[offsets[L.O_OMEGA] + i]
    return measured_speed(d, i, tick, radius, x, ds, offsets, drives, web) / radius


@jit
def roller_speed(i: int, tick: int, x: np.ndarray, ns: np.ndarray, ds: np.ndarray,
                 offsets: np.ndarray, nodes: np.ndarray, drives: np.ndarray,
                 web: np.ndarray) -> float:
    """Surface speed [m/s] of roller ``i`` (radius fixed) as measured: through its drive's
    encoder if it has one, else its own tachometer (noise channel 3 drives + i)."""
    radius = nodes[i, L.N_RADIUS]
    d = ns[i, L.NS_DRIVE]
    if d >= 0:
        return measured_speed(d, i, tick, radius, x, ds, offsets, drives, web)
    v_meas = radius * x[offsets[L.O_OMEGA] + i]
    if offsets[L.O_NOISE]:
        if web[L.W_NOISE_V] > 0.0:
            v_meas += web[L.W_NOISE_V] * gaussian(int(web[L.W_SEED]), tick,
                                                  3 * ds.shape[0] + i)
        v_meas = quantized(v_meas, web[L.W_RES_V])
    return v_meas
