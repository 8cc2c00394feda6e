"""Calibrated loadcells on a branched line (``spec.sensors``; docs/branching.md, "Sensors"):
the span table's gain and offset columns the drives' tension loops read, as the chain's
``sim.elements.sensor_loop`` fills its drive table."""

from __future__ import annotations

import numpy as np

from webline.errors import LineFileError
from webline.model.web_graph import BranchedLine
from webline.sim.branches.loop import layout as B
from webline.spec.sensors import LoadcellSensor


def sensor_columns(line: BranchedLine, offsets: np.ndarray, sf: np.ndarray, di: np.ndarray,
                   cells: list[tuple[int, int, int, int]]) -> None:
    """Each span's loadcell gain and offset (1, 0 where ideal) into ``sf``; ``O_SENSORS`` 1
    where one is other than ideal. ``LineFileError`` where no tension loop reads the
    loadcell (a dancer's, an observer's or an open-loop winder's zone): its calibration
    would not act, and the operating point would hold the wrong tension."""
    sf[:, B.SF_TGAIN], sf[:, B.SF_TOFFSET] = 1.0, 0.0
    spans = {span.name: span.index for span in line.spans}
    for s, sensor in enumerate(line.spec.sensors):
        if not isinstance(sensor, LoadcellSensor):  # (check_branched refuses encoders)
            continue
        k = spans[sensor.span]
        reader = _reader(line, k, di, cells)
        if reader:
            raise LineFileError(line.source, f"sensors[{s}].span",
                                f"{reader} controls span {sensor.span!r}, not its loadcell: "
                                "its calibration would not act")
        sf[k, B.SF_TGAIN], sf[k, B.SF_TOFFSET] = sensor.gain, sensor.offset
    offsets[B.O_SENSORS] = int(np.any(sf[:, B.SF_TGAIN] != 1.0)
                               or np.any(sf[:, B.SF_TOFFSET] != 0.0))


def _reader(line: BranchedLine, k: int, di: np.ndarray,
            cells: list[tuple[int, int, int, int]]) -> str:
    """'' where a drive's tension loop reads span ``k``'s loadcell, else what holds it."""
    for d in range(di.shape[0]):
        first, count = di[d, B.DI_CELLS], di[d, B.DI_NCELLS]
        if not any(cell[0] == k for cell in cells[first:first + count]):
            continue
        name = repr(line.spec.rollers[di[d, B.DI_NODE]].name)
        if any(cell[2] >= 0 for cell in cells[first:first + count]):
            return f"the dancer of {name}"
        if getattr(getattr(line.spec.rollers[di[d, B.DI_NODE]], "controller", None),
                   "tension_feedback", "") == "observer":
            return f"the tension observer of {name}"
        if di[d, B.DI_WINDER] == B.WINDER_OPEN:
            return f"the open-loop winder {name}"
        return ""
    return "no drive"
