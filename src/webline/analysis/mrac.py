"""Theorem 6.3.1 for webline's MRAC: condition (6.69) and the reference model's K_m (6.67).

The MRAC's reference models are the section closed loops of its design, A_mi = A_i - b_i k_iᵀ
(6.63; ``webline.sim.drives.mrac``). (6.69) δs(A_mi) > √N ξ_i is (6.54) with Ā_i = A_mi once the
proof's coupling terms are corrected (E-6.8: ξ_i from the couplings A_ji *out of* section i,
N the count of the sum over j ≠ i, E-6.12), so it is evaluated by
``webline.analysis.certificate.certificate`` with those matrices. The whole reference model
(6.67) is A_m - B K_mᵀ with A_m the A_mi joined by the known interconnections A_ij; the thesis
takes K_m = 0 when A_m is Hurwitz and places its poles otherwise.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.signal

from webline.analysis.certificate import Certificate, NRule, Scaling, certificate
from webline.control.gains import section_designs
from webline.control.sections import section_models
from webline.line import Line
from webline.model.operating_point import operating_point


@dataclass(frozen=True)
class MRACCondition:
    """(6.69) per section (``certificate``), the eigenvalues of the interconnected reference
    model A_m (6.67 with K_m = 0) [1/s] and K_m (zero when A_m is Hurwitz; else by pole
    placement, rows k_mi, input i = section i)."""

    certificate: Certificate
    reference_eigenvalues: np.ndarray
    k_m: np.ndarray

    @property
    def reference_hurwitz(self) -> bool:
        return bool(self.reference_eigenvalues.real.max() < 0.0)

    def summary(self) -> str:
        """One sentence per fact, computed from the numbers."""
        c = self.certificate
        worst = min(c.sections, key=lambda s: s.ratio)
        verdict = "holds" if c.holds else "fails"
        lines = [f"(6.69) {verdict} in {c.scaling} coordinates (N rule {c.n_rule}): worst "
                 f"section {worst.name}, δs/(√N ξ) = {worst.ratio:.3g} (> 1 needed).",
                 f"Interconnected reference model A_m: largest real part "
                 f"{self.reference_eigenvalues.real.max():.4g} 1/s, so K_m "
                 + ("= 0 (6.67)." if self.reference_hurwitz else "is placed (6.67).")]
        return "\n".join(lines)


def mrac_condition(line: Line, *, scaling: Scaling = "optimize",
                   n_rule: NRule = "thesis") -> MRACCondition:
    """Condition (6.69) and the reference model (6.67) of ``line``'s MRAC design at its
    operating point (``scaling``, ``n_rule``: as ``certificate``). Use
    ``webline.control.lumped.without_idlers`` for a line with idle rollers, as the section
    models of Ch. 6 have none."""
    op = operating_point(line)
    models = section_models(line, op)
    closed = [d.closed for d in section_designs(line, op)]
    cert = certificate(line, closed, scaling=scaling, n_rule=n_rule, plant=False)
    sizes = [m.a.shape[0] for m in models]
    starts = np.concatenate(([0], np.cumsum(sizes)))
    a_m = np.zeros((starts[-1], starts[-1]))
    b = np.zeros((starts[-1], len(models)))
    for s, (m, a_bar) in enumerate(zip(models, closed, strict=True)):
        block = slice(starts[s], starts[s + 1])
        a_m[block, block] = a_bar
        b[block, s] = m.b[:, 0]
        for j, coupling in m.coupling.items():
            a_m[block, starts[j]:starts[j + 1]] = coupling
    eigs = np.linalg.eigvals(a_m)
    k_m = np.zeros((len(models), starts[-1]))
    if eigs.real.max() >= 0.0:  # reflect the unstable poles (pole placement, 6.67)
        target = np.where(eigs.real >= 0.0, -np.abs(eigs.real) - 1.0 + 1j * eigs.imag, eigs)
        k_m = scipy.signal.place_poles(a_m, b, target).gain_matrix
    return MRACCondition(cert, eigs, k_m)
