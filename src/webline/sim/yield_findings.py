"""Strain beyond the web's yield (docs/nonlinear-web.md, N4): where, when, how long and how
far, as a verdict finding of the run (``sim.findings.run_verdict`` takes it)."""

from __future__ import annotations

import numpy as np

from webline.line import Line
from webline.physics.web_law import law_tension
from webline.spec.web_law import stretch_at
from webline.verdict import Finding


def yield_findings(line: Line, time: np.ndarray, stretch: np.ndarray) -> list[Finding]:
    """A ``warning`` ``yield`` for each span whose strain ε = s/EA exceeded the law's
    ``yield_strain`` in the run's records (``time`` [s], ``stretch`` [N], records x spans):
    the first record beyond it [s], the records' time beyond it summed [s], and the peak
    strain [-] with its time. None for a law without a yield strain."""
    law = line.spec.web.stress_strain
    if law is None or law.yield_strain is None or len(time) == 0:
        return []
    ea, limit = line.ea, law.yield_strain
    step = np.diff(time, append=time[-1])
    out: list[Finding] = []
    for k in range(stretch.shape[1]):
        strain = stretch[:, k] / ea
        beyond = strain > limit
        if not beyond.any():
            continue
        first = float(time[np.argmax(beyond)])
        duration = float(step[beyond].sum())
        peak_at = int(np.argmax(strain))
        peak = float(strain[peak_at])
        span = line.span_name(k)
        out.append(Finding(
            "warning", "yield", span,
            f"{span} strained beyond the web's yield ({100 * limit:.3g} %) from t = {first:.4g} s, "
            f"{duration:.4g} s in all, peak {100 * peak:.3g} % at t = {float(time[peak_at]):.4g} s",
            first, {"yield_strain": limit, "first_s": first, "duration_s": duration,
                    "peak_strain": peak, "peak_s": float(time[peak_at])}))
    return out


def case_yield_findings(line: Line, tension_max: np.ndarray) -> list[Finding]:
    """The ``yield`` findings of a study case, whose accumulators keep each span's largest
    felt tension [N] (``tension_max``) but no strains: a span yielded where that tension
    exceeds the law's at the yield strain, its peak strain F⁻¹(T_max)/EA. When and how long
    are its run's to say (``yield_findings``). A Kelvin-Voigt damper adds to the felt tension,
    so lines with one are left out (their cases carry no yield finding)."""
    law = line.spec.web.stress_strain
    if law is None or law.yield_strain is None or any(
            s.retardation for s in line.spec.spans):
        return []
    ea, limit = line.ea, law.yield_strain
    at_yield = law_tension(ea * limit, line.law)
    out: list[Finding] = []
    for k, tension in enumerate(tension_max):
        if not tension > at_yield:
            continue
        peak = stretch_at(line.law, float(tension)) / ea
        span = line.span_name(k)
        out.append(Finding(
            "warning", "yield", span,
            f"{span} strained beyond the web's yield ({100 * limit:.3g} %), peak "
            f"{100 * peak:.3g} % (when and how long: its run)", None,
            {"yield_strain": limit, "peak_strain": peak}))
    return out
