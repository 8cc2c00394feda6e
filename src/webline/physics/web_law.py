"""A web's stress-strain law in the span's own variable, the stretch s = EA·ε [N]
(docs/nonlinear-web.md).

The span state stays the stretch that mass conservation moves (thesis 6.8 in strain, scaled by
the reference stiffness EA of ``web.modulus``/``web.ea``); the tension the rollers feel is
T = F(s), F the law. A law is a float array (``compile`` in ``webline.line``):

- ``[LINEAR]``: T = s, today's elastic web;
- ``[TABLE, m, s_0 .. s_{m-1}, T_0 .. T_{m-1}]``: piecewise linear through m points
  (s_0 = T_0 = 0, both strictly increasing), the last segment's slope beyond the last point
  (a bilinear law with yield is the table of three points);
- ``[POWER, S_r, n]``: T = S_r (s / S_r)^n with S_r = EA ε_r, the secant stiffness at the
  reference strain ε_r being EA.

Every function is plain Python on floats and the array (no helper calls), so numba compiles
it into the kernel.
A slack span (s <= 0) carries nothing, as ``span.tension``.
"""

from __future__ import annotations

import numpy as np

from webline.spec.web_law import POWER, TABLE


def law_tension(stretch: float, law: np.ndarray) -> float:
    """Tension [N] of a span whose stretch is ``stretch`` [N] = EA·ε under ``law``."""
    if stretch <= 0.0:
        return 0.0
    kind = int(law[0])
    if kind == TABLE:
        m = int(law[1])
        j = 0  # the segment [s_j, s_j+1] holding the stretch (the last one beyond it)
        while j < m - 2 and stretch > law[3 + j]:
            j += 1
        s0, s1 = law[2 + j], law[3 + j]
        t0, t1 = law[2 + m + j], law[3 + m + j]
        return t0 + (t1 - t0) * (stretch - s0) / (s1 - s0)
    if kind == POWER:
        return law[1] * (stretch / law[1]) ** law[2]
    return stretch


def law_slope(stretch: float, law: np.ndarray) -> float:
    """Tangent dT/ds [-] of ``law`` at ``stretch`` [N]: the local modulus over the reference
    one, E_t(ε)/E (0 for a slack span)."""
    if stretch <= 0.0:
        return 0.0
    kind = int(law[0])
    if kind == TABLE:
        m = int(law[1])
        j = 0  # the segment [s_j, s_j+1] holding the stretch (the last one beyond it)
        while j < m - 2 and stretch > law[3 + j]:
            j += 1
        return (law[3 + m + j] - law[2 + m + j]) / (law[3 + j] - law[2 + j])
    if kind == POWER:
        return law[2] * (stretch / law[1]) ** (law[2] - 1.0)
    return 1.0


def law_stretch(tension: float, law: np.ndarray) -> float:
    """Stretch [N] = EA·ε at which ``law`` carries ``tension`` [N] (its inverse; a tension
    <= 0 is returned as it is, the stretch of a span that is just taut or slack)."""
    if tension <= 0.0:
        return tension
    kind = int(law[0])
    if kind == TABLE:
        m = int(law[1])
        j = 0
        while j < m - 2 and tension > law[2 + m + j + 1]:
            j += 1
        s0, s1 = law[2 + j], law[3 + j]
        t0, t1 = law[2 + m + j], law[3 + m + j]
        return s0 + (s1 - s0) * (tension - t0) / (t1 - t0)
    if kind == POWER:
        return law[1] * (tension / law[1]) ** (1.0 / law[2])
    return tension
