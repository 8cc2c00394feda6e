"""Sensors on a branched line (``spec.sensors``; docs/branching.md, "Sensors"), as the chain's
``sim.elements.sensor_loop`` fills its drive table: the span table's loadcell gain and offset
columns the drives' tension loops read, each drive's encoder scale and the delays of its
zone's loadcells and of its encoder in whole controller samples (what a plan holds of them:
``sensor_views``)."""

from __future__ import annotations

import numpy as np

from webline.errors import LineFileError
from webline.model.web_graph import BranchedLine
from webline.sim.branches.loop import layout as B
from webline.sim.elements.sensor_loop import delay_samples
from webline.spec.sensors import LoadcellSensor


def sensor_columns(line: BranchedLine, offsets: np.ndarray, sf: np.ndarray, di: np.ndarray,
                   df: np.ndarray, cells: list[tuple[int, int, int, int]], dt: float) -> None:
    """Each span's loadcell gain and offset (1, 0 where ideal) into ``sf``, each drive's
    encoder scale and the delays [controller periods ``dt`` s] of its loadcells and encoder
    into ``df``; ``O_SENSORS`` 1 where one is other than ideal. ``LineFileError`` where no
    tension loop reads the loadcell (a dancer's, an observer's or an open-loop winder's
    zone: its calibration would not act, and the operating point would hold the wrong
    tension), where one zone's loadcells have different delays (the loop delays their sum)
    and beyond ``MAX_DELAY`` samples."""
    sf[:, B.SF_TGAIN], sf[:, B.SF_TOFFSET] = 1.0, 0.0
    df[:, B.D_VSCALE], df[:, B.D_TDELAY], df[:, B.D_VDELAY] = 1.0, 0.0, 0.0
    spans = {span.name: span.index for span in line.spans}
    delayed_by: dict[int, str] = {}  # drive -> the sensor that set its loadcells' delay
    for s, sensor in enumerate(line.spec.sensors):
        samples = delay_samples(line.source, f"sensors[{s}].delay", sensor.delay, dt)
        if not isinstance(sensor, LoadcellSensor):
            d = line.drives.index(line.node_index[sensor.roller])
            df[d, B.D_VSCALE], df[d, B.D_VDELAY] = sensor.scale, samples
            continue
        k = spans[sensor.span]
        reader, d = _reader(line, k, di, cells)
        if reader:
            raise LineFileError(line.source, f"sensors[{s}].span",
                                f"{reader} controls span {sensor.span!r}, not its loadcell: "
                                "its calibration would not act")
        sf[k, B.SF_TGAIN], sf[k, B.SF_TOFFSET] = sensor.gain, sensor.offset
        if d in delayed_by and df[d, B.D_TDELAY] != samples:
            raise LineFileError(line.source, f"sensors[{s}].delay",
                                f"the zone of {line.spec.rollers[di[d, B.DI_NODE]].name!r} "
                                f"sums this loadcell with {delayed_by[d]!r}, whose delay "
                                "differs: give its loadcells one delay")
        delayed_by[d] = sensor.name
        df[d, B.D_TDELAY] = samples
    offsets[B.O_SENSORS] = int(np.any(sf[:, B.SF_TGAIN] != 1.0)
                               or np.any(sf[:, B.SF_TOFFSET] != 0.0)
                               or np.any(df[:, B.D_VSCALE] != 1.0)
                               or np.any(df[:, B.D_TDELAY:B.D_VDELAY + 1] != 0.0))


def _reader(line: BranchedLine, k: int, di: np.ndarray,
            cells: list[tuple[int, int, int, int]]) -> tuple[str, int]:
    """('', drive) where a drive's tension loop reads span ``k``'s loadcell, else (what holds
    it, -1)."""
    for d in range(di.shape[0]):
        first, count = di[d, B.DI_CELLS], di[d, B.DI_NCELLS]
        if not any(cell[0] == k for cell in cells[first:first + count]):
            continue
        name = repr(line.spec.rollers[di[d, B.DI_NODE]].name)
        if any(cell[2] >= 0 for cell in cells[first:first + count]):
            return f"the dancer of {name}", -1
        if getattr(getattr(line.spec.rollers[di[d, B.DI_NODE]], "controller", None),
                   "tension_feedback", "") == "observer":
            return f"the tension observer of {name}", -1
        if di[d, B.DI_WINDER] == B.WINDER_OPEN:
            return f"the open-loop winder {name}", -1
        return "", d
    return "no drive", -1
