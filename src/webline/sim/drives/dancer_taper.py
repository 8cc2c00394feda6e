"""Taper through a dancer (docs/winder.md W1): in dancer position control the tension is the
dancer's load / 2, so a drive's taper acts on the load (the loading pressure follows the
diameter, as winder drives set it), not on a reference the position loop never reads."""

from __future__ import annotations

import numpy as np

from webline.sim.drives.controllers import taper_at
from webline.sim.elements import layout as L
from webline.sim.elements.signals import jit


@jit
def load_factor(i: int, istate: np.ndarray, ds: np.ndarray, drives: np.ndarray,
                prof_t: np.ndarray, prof_v: np.ndarray, prof_off: np.ndarray) -> float:
    """Factor [-] on the load of the dancer on node ``i``: the taper factor of the drive that
    runs it in position control at the diameter that drive's controller knows (its
    calculated radius), 1 otherwise."""
    factor = 1.0
    for d in range(ds.shape[0]):
        if ds[d, L.DS_DANCER] == i and ds[d, L.DS_DUSE] == L.DANCER_POSITION and (
                drives[d, L.D_TAPER] > 0.0):
            factor *= taper_at(d, istate[d, L.I_RADIUS], drives, prof_t, prof_v, prof_off)
    return factor

