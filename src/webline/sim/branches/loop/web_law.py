"""Web laws in a branched line's compiled loop (docs/branching.md, "Web laws"): the tension
T = F(s) + τ ds/dt a span's rollers and loadcells feel, and the stretch a web carries into a
span where it starts at an unwind or a lamination nip.

A span's state is its stretch s = EA ε (EA its web's reference stiffness: a laminate's the
sum of its layers', a lane's its share of its base web's), which mass conservation moves
(B1). Its law is a sum of terms over the raw webs it is made of, T = Σ c F_w(a s) (a raw
web: a = c = 1; a layer i of a laminate: a = EA_i / EA_L, c = 1, plus its own offset state,
``loop.laminate``; a lane of share φ: a = 1 / φ, c = φ), ``F_w`` the raw web's law in its
own stretch (``physics.web_law``). Tables: ``layout`` S_LAW0, S_NLAW, SF_TAU, LI_*, LF_*.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from webline.physics import web_law
from webline.sim.branches.loop import layout as B
from webline.sim.branches.loop.laminate import bonded_tension
from webline.sim.elements.signals import jit

_law_tension: Any = jit(web_law.law_tension)
_law_slope: Any = jit(web_law.law_slope)
_law_stretch: Any = jit(web_law.law_stretch)

#: the inverse's relative tolerance on the tension [-] (a few rounding errors of a sum)
INVERSE_RTOL = 1e-15
#: most iterations of the inverse's safeguarded Newton (bisection halves 1e300 in ~1000)
INVERSE_ITERATIONS = 200


@jit
def law_tension(k: int, s: float, si: np.ndarray, lawi: np.ndarray, lawf: np.ndarray,
                laws: np.ndarray) -> float:
    """Elastic tension [N] of span ``k`` at stretch ``s`` [N]: Σ c F_w(a s) over its terms;
    max(s, 0) for a span without terms (a linear web)."""
    first, count = si[k, B.S_LAW0], si[k, B.S_NLAW]
    if count == 0:
        return s if s > 0.0 else 0.0
    total = 0.0
    for t in range(first, first + count):
        total += lawf[t, B.LF_FACTOR] * _law_tension(lawf[t, B.LF_SCALE] * s,
                                                     laws[lawi[t, B.LI_START]:])
    return total


@jit
def law_slope(k: int, s: float, si: np.ndarray, lawi: np.ndarray, lawf: np.ndarray,
              laws: np.ndarray) -> float:
    """Tangent dT/ds [-] of span ``k``'s law at stretch ``s`` [N]: Σ c a F_w'(a s)."""
    first, count = si[k, B.S_LAW0], si[k, B.S_NLAW]
    if count == 0:
        return 1.0 if s > 0.0 else 0.0
    total = 0.0
    for t in range(first, first + count):
        a = lawf[t, B.LF_SCALE]
        total += lawf[t, B.LF_FACTOR] * a * _law_slope(a * s, laws[lawi[t, B.LI_START]:])
    return total


@jit
def law_stretch(k: int, tension: float, si: np.ndarray, lawi: np.ndarray, lawf: np.ndarray,
                laws: np.ndarray) -> float:
    """Stretch [N] at which span ``k``'s law carries ``tension`` [N] (its inverse; a tension
    <= 0 is returned as it is). One term: the raw law's inverse; several (a laminate): a
    Newton iteration kept inside a bracket, the sum of increasing laws being increasing."""
    first, count = si[k, B.S_LAW0], si[k, B.S_NLAW]
    if count == 0 or tension <= 0.0:
        return tension
    if count == 1:
        return _law_stretch(tension / lawf[first, B.LF_FACTOR],
                            laws[lawi[first, B.LI_START]:]) / lawf[first, B.LF_SCALE]
    low, high = 0.0, tension
    while law_tension(k, high, si, lawi, lawf, laws) < tension:
        low, high = high, 2.0 * high
    s = 0.5 * (low + high)
    for _ in range(INVERSE_ITERATIONS):
        error = law_tension(k, s, si, lawi, lawf, laws) - tension
        if abs(error) <= INVERSE_RTOL * tension:
            break
        if error > 0.0:
            high = s
        else:
            low = s
        slope = law_slope(k, s, si, lawi, lawf, laws)
        step = s - error / slope if slope > 0.0 else 0.5 * (low + high)
        s = step if low < step < high else 0.5 * (low + high)
        if high - low <= INVERSE_RTOL * high:
            break
    return s


@jit
def law_tensions(x: np.ndarray, elastic: np.ndarray, si: np.ndarray, lawi: np.ndarray,
                 lawf: np.ndarray, laws: np.ndarray) -> None:
    """Every span's elastic tension F(s) [N] into ``elastic`` (a laminate's: its bonded
    layers' at their own stretches, ``loop.laminate``)."""
    for k in range(si.shape[0]):
        if si[k, B.S_NLAW] > 1:
            elastic[k] = bonded_tension(k, x, si, lawi, lawf, laws)
        else:
            elastic[k] = law_tension(k, x[k], si, lawi, lawf, laws)


@jit
def felt(k: int, x: np.ndarray, dx: np.ndarray, elastic: np.ndarray, sf: np.ndarray) -> float:
    """Tension [N] the rollers feel in span ``k`` once its stretch rate ``dx[k]`` is known:
    F(s) + τ ds/dt on a Kelvin-Voigt span (docs/winder.md V1), 0 where slack or where the
    damper would push (V3)."""
    tau = sf[k, B.SF_TAU]
    if tau == 0.0 or x[k] <= 0.0:
        return elastic[k]
    total = elastic[k] + tau * dx[k]
    return total if total > 0.0 else 0.0


def felt_start(n_s: int, n_n: int, has_law: bool, has_kv: bool) -> int:
    """Where in ``plant.rhs``'s scratch ``work`` the felt tensions [N] of its spans start:
    the clipped stretches (linear elastic line), the law's tensions, or the Kelvin-Voigt
    felt ones."""
    if has_kv:
        return 5 * n_s + 2 * n_n
    if has_law:
        return 4 * n_s + 2 * n_n
    return 0


felt_start_jit: Any = jit(felt_start)


def felt_view(work: np.ndarray, n_s: int, n_n: int, has_law: bool, has_kv: bool) -> np.ndarray:
    """The felt tensions [N] ``plant.rhs`` left in ``work`` (``felt_start``)."""
    start = felt_start(n_s, n_n, has_law, has_kv)
    return work[start:start + n_s]
