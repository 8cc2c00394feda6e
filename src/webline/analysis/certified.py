"""Decentralized state feedback designed so that the certificate of Theorem 6.2.1 holds.

Thesis Sec. 6.2 asks for closed-loop section matrices Ā_i, by pole placement or LQ (6.55-6.57),
such that (6.54) holds. webline keeps its LQ design with the bandwidth cap of
``webline.control.decentralized`` (a section model has no torque lag and no sampling, so its
fastest closed-loop pole stays below min(0.2 / lag, 2π f_s / 20)) and searches

* per section, the LQ weight of the tension error (``tension_weights``, dividing the default
  tension scale) and the fraction of the bandwidth cap used (``bandwidth_fractions``), and
* the coordinates (state units) in which the certificate is evaluated
  (``webline.analysis.scaling``): with the couplings (AE - T)/L of order 10³ N/m per m/s
  against r²/J of order 0.1 1/kg, no realisable bandwidth satisfies (6.54) in SI units.

for the largest worst-section ratio δs(Ā_i) / (√N_i ξ_i) (the certificate holds iff > 1). The
result is that best design, whether or not it certifies, with its certificate. The design can
be redone at any roll radii (``unwind_radius``, ``rewind_radius``), as the thesis's Ā_i are
recomputed as the rolls change.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from webline.analysis import scaling as sc
from webline.analysis.certificate import (
    Certificate,
    NRule,
    certificate,
    line_at_radii,
    section_counts,
    structure_of,
    thesis_units,
)
from webline.control.decentralized import SectionDesign
from webline.control.gains import section_designs
from webline.control.sections import section_models
from webline.line import Line
from webline.model.operating_point import operating_point

TENSION_WEIGHTS = tuple(float(w) for w in np.logspace(-2, 2, 9))
BANDWIDTH_FRACTIONS = (1.0, 0.5)


@dataclass(frozen=True)
class CertifiedDesign:
    """The best design found: per section its ``design`` (gains K_i, Ā_i), the
    ``tension_weight`` and ``bandwidth_fraction`` it was designed with, and the
    ``certificate`` (in the coordinates found by the search)."""

    designs: tuple[SectionDesign, ...]
    tension_weight: tuple[float, ...]
    bandwidth_fraction: tuple[float, ...]
    certificate: Certificate

    @property
    def gains(self) -> list[np.ndarray]:
        """K_i = (K_T [N·m/N], K_V [N·m·s/m]) per drive, for ``with_gains``."""
        return [d.gain for d in self.designs]

    @property
    def holds(self) -> bool:
        return self.certificate.holds

    def summary(self) -> str:
        c = self.certificate
        verdict = "holds" if c.holds else "does NOT hold"
        plant = ("n/a" if c.max_real_plant is None else
                 f"{c.max_real_plant:.4g} 1/s (sampled: |z| max {c.sampled_radius:.4g})")
        lines = [f"certificate {verdict} at {c.line_speed:.4g} m/s (N rule {c.n_rule}): worst "
                 f"δs/(√N ξ) = {c.worst_ratio:.3g} (needs > 1); interconnected section model "
                 f"max Re λ = {c.max_real:.4g} 1/s, full plant {plant}"]
        for s, w, f in zip(c.sections, self.tension_weight, self.bandwidth_fraction,
                           strict=True):
            lines.append(f"  {s.name}: δs = {s.delta:.4g}, ξ = {s.xi:.4g}, N = {s.n}, "
                         f"ratio = {s.ratio:.3g}, tension weight {w:.3g}, bandwidth x{f:.2g}")
        return "\n".join(lines)


def design_for_certificate(line: Line, *, unwind_radius: float | None = None,
                           rewind_radius: float | None = None, n_rule: NRule = "thesis",
                           tension_weights: Sequence[float] = TENSION_WEIGHTS,
                           bandwidth_fractions: Sequence[float] = BANDWIDTH_FRACTIONS,
                           plant: bool = True) -> CertifiedDesign:
    """Search LQ weights and certificate coordinates (module docstring) for the design that
    maximises the worst-section certificate ratio of ``line`` at the given roll radii [m]."""
    at = line_at_radii(line, unwind_radius, rewind_radius)
    op = operating_point(at)
    models = section_models(at, op)
    options = [(w, f) for f in bandwidth_fractions for w in tension_weights]
    table = [section_designs(at, op, tension_weight=w, bandwidth_fraction=f) for w, f in options]
    candidates = [[table[k][i] for k in range(len(options))] for i in range(len(models))]
    # a master section has no tension weight: its candidates differ by bandwidth only
    structure = structure_of(models, section_counts(models, n_rule))
    closed = [[d.closed for d in c] for c in candidates]
    full = structure.coupling.copy()
    for i, c in enumerate(candidates):
        full[structure.block(i), structure.block(i)] = c[0].closed
    starts = [np.ones(len(full)), thesis_units(models), sc.balanced_units(full)]
    units = sc.best_units(structure, closed, starts)
    _, choice = sc.log_margins(structure, units, closed)
    chosen = [candidates[i][k] for i, k in enumerate(choice)]
    cert = certificate(at, [d.closed for d in chosen], n_rule=n_rule, scaling=units,
                       plant=plant)
    return CertifiedDesign(tuple(chosen), tuple(options[k][0] for k in choice),
                           tuple(options[k][1] for k in choice), cert)
