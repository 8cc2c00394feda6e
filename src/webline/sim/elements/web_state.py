"""The web's state between right-hand sides and the records' layout: the unwind's wound-in
tension at an instant, the stick/slip state of every traction roller held over a tick, and
the columns of a record row (``webline.sim.core.kernel.run``)."""

from __future__ import annotations

from typing import Any

import numpy as np

from webline.physics import slip, span, web_law
from webline.sim.elements import layout as L
from webline.sim.elements.envelope import node_arm
from webline.sim.elements.signals import jit, sines

_tension: Any = jit(span.tension)
_law_tension: Any = jit(web_law.law_tension)
_slip_state: Any = jit(slip.slip_state)


@jit
def wound_in(t: float, web: np.ndarray, wound_ripple: np.ndarray) -> float:
    """Wound-in tension of the unwind [N] at time ``t`` [s]: nominal plus ripple."""
    if wound_ripple.shape[0] == 0:
        return web[L.W_T0]
    return web[L.W_T0] + sines(wound_ripple, t)


@jit
def update_slip(x: np.ndarray, slipping: np.ndarray, ns: np.ndarray, offsets: np.ndarray,
                nodes: np.ndarray, web: np.ndarray) -> None:
    """Stick/slip state of every traction roller for the next tick (held over its stages, so
    the fixed step never chatters): ``physics.slip.slip_state`` on the sampled tensions."""
    for i in range(1, ns.shape[0] - 1):
        if ns[i, L.NS_TRACTION] == 0:
            continue
        surface = node_arm(i, x, ns, offsets, nodes) * x[offsets[L.O_OMEGA] + i]
        t_a, t_b = _tension(x[i - 1]), _tension(x[i])
        if offsets[L.O_LAW]:
            t_a, t_b = _law_tension(t_a, web[L.W_COLS:]), _law_tension(t_b, web[L.W_COLS:])
        slipping[i] = _slip_state(t_a, t_b, nodes[i, L.N_WRAP],
                                  nodes[i, L.N_MU], nodes[i, L.N_MUK], web[L.W_RHOA] * surface
                                  * surface, slipping[i], nodes[i, L.N_NIPS], nodes[i, L.N_NIPK])


def record_width(n_x: int, n_d: int, n_n: int) -> int:
    """Columns of a record row (``kernel.run``) for ``n_x`` states, ``n_d`` drives and
    ``n_n`` nodes."""
    return slip_column(n_x, n_d) + n_n + 3 * n_d


def slip_column(n_x: int, n_d: int) -> int:
    """First stick/slip column of a record row (``kernel.run``): after the time, the ``n_x``
    states and six columns per drive (commands, references, trims, u_eq, friction
    estimates, controller radii)."""
    return 1 + n_x + 6 * n_d


#: ``slip_column`` for compiled callers (``sim.sweeps.batch``)
compiled_slip_column: Any = jit(slip_column)
