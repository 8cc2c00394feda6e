"""Taper through a dancer on a branched line (docs/branching.md, "Dancers"; the chain's
``sim.drives.dancer_taper``, docs/winder.md W1): in position control the tension is the
dancer's load over its strand gains, so a rewind's taper acts on the load (the loading
pressure follows the diameter), not on a reference the position loop never reads."""

from __future__ import annotations

import numpy as np

from webline.sim.branches.loop import layout as B
from webline.sim.branches.loop.control import taper_at
from webline.sim.elements.signals import jit


@jit
def taper_loads(held: np.ndarray, istate: np.ndarray, x: np.ndarray, offsets: np.ndarray,
                nodes: np.ndarray, di: np.ndarray, df: np.ndarray, cells: np.ndarray,
                prof_t: np.ndarray, prof_v: np.ndarray, prof_off: np.ndarray) -> None:
    """Multiply the held load [N] of each dancer a tapered drive holds in position control
    by that drive's taper factor f(D) (``control.taper_at``), D from the radius its
    controller knows: the calculated one with a diameter calculator, else the true one (a
    dancer read as tension sensor keeps its load: its drive's reference is tapered).
    The dancers' loads are the last entries of ``held``."""
    first_load = held.shape[0] - (offsets[B.O_DANCER_END] - offsets[B.O_DANCER]) // 2
    for d in range(di.shape[0]):
        if df[d, B.D_TAPER_KIND] == 0.0:
            continue
        i, j = di[d, B.DI_NODE], di[d, B.DI_ROLL]
        radius = x[offsets[B.O_RADIUS] + j] if j >= 0 else nodes[i, B.N_RADIUS]
        if df[d, B.D_DCALC] != B.DCALC_NONE:
            radius = istate[d, B.I_RADIUS]
        for c in range(di[d, B.DI_CELLS], di[d, B.DI_CELLS] + di[d, B.DI_NCELLS]):
            node = cells[c, B.CELL_DANCER]
            if node >= 0 and not cells[c, B.CELL_SENSOR]:  # (a sensor: the reference tapers)
                slot = first_load + (int(nodes[node, B.N_DSTATE]) - offsets[B.O_DANCER]) // 2
                held[slot] *= taper_at(d, radius, nodes[i, B.N_CORE], df, prof_t, prof_v,
                                       prof_off)
