"""What a branched line's loadcell shows its drive's tension loop (``spec.sensors``;
``layout`` O_SENSORS, SF_TGAIN, SF_TOFFSET), as the chain's ``sensor_loop.loadcell_reading``."""

from __future__ import annotations

import numpy as np

from webline.sim.branches.loop import layout as B
from webline.sim.elements.signals import jit


@jit
def loadcell_reading(k: int, tension: float, offsets: np.ndarray, sf: np.ndarray) -> float:
    """The tension [N] span ``k``'s loadcell shows when the web carries ``tension`` [N]:
    gain T + offset where a loadcell is calibrated (the flag folds away on a line without)."""
    if offsets[B.O_SENSORS]:
        return sf[k, B.SF_TGAIN] * tension + sf[k, B.SF_TOFFSET]
    return tension
