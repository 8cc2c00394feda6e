"""Sensors in the loop (``spec.sensors``): what a drive's controller reads from its loadcell
and its encoder. The calibration sits in the drive table (``D_TGAIN``, ``D_TOFFSET``,
``D_VSCALE``); the loop reads it only where ``offsets[O_SENSORS]`` is 1, so a line with ideal
sensors compiles and runs exactly as before sensors existed."""

from __future__ import annotations

import numpy as np

from webline.line import Line
from webline.sim.elements import layout as L
from webline.sim.elements.signals import jit
from webline.spec.sensors import LoadcellSensor


def sensor_columns(drives: np.ndarray, line: Line) -> bool:
    """Fill every drive row's sensor columns from the line's ``[[sensors]]`` (ideal where
    none is given); True if any sensor is other than ideal."""
    drives[:, L.D_TGAIN] = 1.0
    drives[:, L.D_TOFFSET] = 0.0
    drives[:, L.D_VSCALE] = 1.0
    spans = {line.span_name(k): k for k in range(line.n_spans)}
    nodes = {line.node_name(i): i for i in range(line.n_nodes)}
    for sensor in line.spec.sensors:
        if isinstance(sensor, LoadcellSensor):
            k = spans[sensor.span]
            for d in range(len(line.drives)):
                if int(drives[d, L.D_LOADCELL]) == k:
                    drives[d, L.D_TGAIN], drives[d, L.D_TOFFSET] = sensor.gain, sensor.offset
        else:
            drives[line.drives.index(nodes[sensor.roller]), L.D_VSCALE] = sensor.scale
    return bool(np.any(drives[:, L.D_TGAIN] != 1.0) or np.any(drives[:, L.D_TOFFSET] != 0.0)
                or np.any(drives[:, L.D_VSCALE] != 1.0))


@jit
def loadcell_reading(d: int, tension: float, drives: np.ndarray) -> float:
    """The tension [N] drive ``d``'s loadcell shows when the web carries ``tension`` [N]."""
    return drives[d, L.D_TGAIN] * tension + drives[d, L.D_TOFFSET]


def measured_tensions(line: Line, drives: np.ndarray, tension: np.ndarray) -> np.ndarray:
    """Span tensions (records x spans) [N] as the loadcells show them (without their noise):
    gain T + offset on each calibrated loadcell span, the true tension elsewhere."""
    out = np.array(tension, dtype=float, copy=True)
    for d in range(len(line.drives)):
        k = int(drives[d, L.D_LOADCELL])
        if k >= 0:
            out[:, k] = drives[d, L.D_TGAIN] * tension[:, k] + drives[d, L.D_TOFFSET]
    return out


def measured_speeds(line: Line, drives: np.ndarray, speed: np.ndarray) -> np.ndarray:
    """Node speeds (records x nodes) [m/s] as the encoders show them (without their noise):
    scale x speed on each driven node, the true speed elsewhere."""
    out = np.array(speed, dtype=float, copy=True)
    for d, i in enumerate(line.drives):
        out[:, i] = drives[d, L.D_VSCALE] * speed[:, i]
    return out
