"""Sensors in the loop (``spec.sensors``): what a drive's controller reads from its loadcell
and its encoder. The calibration sits in the drive table (``D_TGAIN``, ``D_TOFFSET``,
``D_VSCALE``); the loop reads it only where ``offsets[O_SENSORS]`` is 1, so a line with ideal
sensors compiles and runs exactly as before sensors existed."""

from __future__ import annotations

import numpy as np

from webline.errors import LineFileError
from webline.line import Line
from webline.sim.elements import layout as L
from webline.sim.elements.signals import jit
from webline.spec.sensors import LoadcellSensor


def delay_samples(source: str, key: str, delay: float, dt: float) -> int:
    """A sensor's ``delay`` [s] as a whole number of controller periods ``dt`` [s] (the
    nearest); ``LineFileError`` naming ``key`` (``sensors[s].delay``) of the line file
    ``source`` beyond ``MAX_DELAY``. Every line's sensors (the chain's and a branched
    line's, ``sim.branches.sensors``)."""
    samples = round(delay / dt)
    if samples > L.MAX_DELAY:
        raise LineFileError(source, key, f"{delay:g} s is {samples} controller samples of "
                            f"{dt:g} s; at most {L.MAX_DELAY} are modelled")
    return samples


def sensor_columns(drives: np.ndarray, line: Line, dt: float) -> bool:
    """Fill every drive row's sensor columns from the line's ``[[sensors]]`` (ideal where
    none is given), delays in whole controller periods ``dt`` [s]; True if any sensor is
    other than ideal."""
    drives[:, L.D_TGAIN] = 1.0
    drives[:, L.D_TOFFSET] = 0.0
    drives[:, L.D_VSCALE] = 1.0
    drives[:, L.D_TDELAY] = 0.0
    drives[:, L.D_VDELAY] = 0.0
    spans = {line.span_name(k): k for k in range(line.n_spans)}
    nodes = {line.node_name(i): i for i in range(line.n_nodes)}
    for s, sensor in enumerate(line.spec.sensors):
        samples = delay_samples(line.source, f"sensors[{s}].delay", sensor.delay, dt)
        if isinstance(sensor, LoadcellSensor):
            k = spans[sensor.span]
            for d in range(len(line.drives)):
                if int(drives[d, L.D_LOADCELL]) == k:
                    _loop_reads_loadcell(line, drives, d, s)
                    drives[d, L.D_TGAIN], drives[d, L.D_TOFFSET] = sensor.gain, sensor.offset
                    drives[d, L.D_TDELAY] = samples
        else:
            d = line.drives.index(nodes[sensor.roller])
            drives[d, L.D_VSCALE], drives[d, L.D_VDELAY] = sensor.scale, samples
    ideal = np.array([1.0, 0.0, 1.0, 0.0, 0.0])
    return bool(np.any(drives[:, L.D_TGAIN:L.D_VDELAY + 1] != ideal))


def _loop_reads_loadcell(line: Line, drives: np.ndarray, d: int, s: int) -> None:
    """``LineFileError`` where drive ``d``'s zone is held by something other than the
    loadcell of sensor ``s`` (a dancer, an observer, open-loop control): its calibration
    would not act, and the operating point would hold the wrong tension."""
    reader = ("a dancer" if drives[d, L.D_DANCER] >= 0 else "a tension observer"
              if drives[d, L.D_OBS] > 0 else "open-loop (indirect) control"
              if drives[d, L.D_FAMILY] == L.FAMILY_OPEN_LOOP else "")
    if reader:
        raise LineFileError(line.source, f"sensors[{s}].span",
                            f"roller {line.node_name(line.drives[d])!r} controls this zone "
                            f"with {reader}, not this loadcell: its calibration would not act")


def fill_delays(drives: np.ndarray, istate: np.ndarray, tension: np.ndarray,
                speed: np.ndarray) -> None:
    """Start every drive's delay buffers at its readings of the initial state: ``tension``
    [N] (its loadcell span's, NaN for none) and ``speed`` [m/s] per drive."""
    reading = drives[:, L.D_TGAIN] * tension + drives[:, L.D_TOFFSET]
    fill_buffers(istate, L.I_TBUF, L.I_VBUF, np.where(np.isnan(reading), 0.0, reading),
                 drives[:, L.D_VSCALE] * speed)


def fill_buffers(istate: np.ndarray, tension_first: int, speed_first: int,
                 tension: np.ndarray, speed: np.ndarray) -> None:
    """Fill each drive's ring buffers of ``delayed`` (``DELAY_SLOTS`` columns of ``istate``
    from ``tension_first`` and from ``speed_first``) with its reading at the start: the
    loadcell's ``tension`` [N] and the encoder's ``speed`` [m/s] per drive (a line steady
    before its start shows the same readings all along)."""
    for d in range(istate.shape[0]):
        istate[d, tension_first:tension_first + L.DELAY_SLOTS] = tension[d]
        istate[d, speed_first:speed_first + L.DELAY_SLOTS] = speed[d]


@jit
def delayed(d: int, tick: int, value: float, first: int, samples: float,
            istate: np.ndarray) -> float:
    """``value`` of tick ``tick`` put in drive ``d``'s ring buffer starting at column
    ``first`` of ``istate``; returns the value of ``samples`` ticks before (this one for 0)."""
    istate[d, first + tick % L.DELAY_SLOTS] = value
    return istate[d, first + (tick - int(samples)) % L.DELAY_SLOTS]


@jit
def loadcell_reading(d: int, tension: float, drives: np.ndarray) -> float:
    """The tension [N] drive ``d``'s loadcell shows when the web carries ``tension`` [N]."""
    return drives[d, L.D_TGAIN] * tension + drives[d, L.D_TOFFSET]


def late(time: np.ndarray, values: np.ndarray, delay: float) -> np.ndarray:
    """``values`` over ``time`` [s] as seen ``delay`` [s] late (the first value before)."""
    return values if delay == 0.0 else np.interp(time - delay, time, values)


def measured_tensions(line: Line, drives: np.ndarray, dt: float, time: np.ndarray,
                      tension: np.ndarray) -> np.ndarray:
    """Span tensions (records at ``time`` [s] x spans) [N] as the loadcells show them
    (without their noise): gain T + offset, ``D_TDELAY`` controller periods ``dt`` [s] late,
    on each calibrated loadcell span; the true tension elsewhere."""
    out = np.array(tension, dtype=float, copy=True)
    for d in range(len(line.drives)):
        k = int(drives[d, L.D_LOADCELL])
        if k >= 0:
            reading = drives[d, L.D_TGAIN] * tension[:, k] + drives[d, L.D_TOFFSET]
            out[:, k] = late(time, reading, drives[d, L.D_TDELAY] * dt)
    return out


def measured_speeds(line: Line, drives: np.ndarray, dt: float, time: np.ndarray,
                    speed: np.ndarray) -> np.ndarray:
    """Node speeds (records at ``time`` [s] x nodes) [m/s] as the encoders show them
    (without their noise): scale x speed, ``D_VDELAY`` periods ``dt`` [s] late, on each
    driven node; the true speed elsewhere."""
    out = np.array(speed, dtype=float, copy=True)
    for d, i in enumerate(line.drives):
        out[:, i] = late(time, drives[d, L.D_VSCALE] * speed[:, i],
                          drives[d, L.D_VDELAY] * dt)
    return out
