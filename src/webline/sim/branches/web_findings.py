"""What a branched run's verdict says about its web laws (docs/branching.md, "Web laws"):
strain beyond a web's yield, per web and lane (the chain's ``sim.results.yield_findings``,
N4), and the stop at a web's strength."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from webline.sim.branches.loop import layout as B
from webline.sim.branches.web_laws import raw_law, raw_material, web_tension, web_terms
from webline.spec.branched.check import kind_of
from webline.spec.web_law import stretch_at
from webline.verdict import Finding

if TYPE_CHECKING:
    from webline.sim.branches.plan import BranchPlan


def yield_findings(plan: BranchPlan, time: np.ndarray, states: np.ndarray) -> list[Finding]:
    """A ``warning`` ``yield`` for each web or lane, and each layer of a laminate, whose
    strain exceeded its raw web's ``yield_strain`` in the records (``time`` [s], ``states``):
    where (the web or lane; in a laminate, the layer), its spans beyond yield, the first
    record beyond it [s], the records' time beyond it summed [s] and the peak strain [-]
    with its time. A layer's strain in a laminate is the laminate's (its layers share it)."""
    line = plan.line
    if len(time) == 0:
        return []
    step = np.diff(time, append=time[-1])
    out: list[Finding] = []
    for w, web in enumerate(line.spec.webs):
        spans = line.web_spans(w)
        for r, a, _ in web_terms(line, w):
            law = raw_material(line, r).stress_strain
            if law is None or law.yield_strain is None:
                continue
            limit = law.yield_strain
            strain = a * states[:, spans] / line.materials[r].ea  # ε of raw web r's material
            beyond = strain > limit
            if not beyond.any():
                continue
            rows = np.any(beyond, axis=1)
            first = float(time[np.argmax(rows)])
            duration = float(step[rows].sum())
            at = np.unravel_index(int(np.argmax(strain)), strain.shape)
            peak, peak_s = float(strain[at]), float(time[at[0]])
            names = [line.spans[spans[j]].name for j in np.nonzero(beyond.any(axis=0))[0]]
            laminate = kind_of(web) == "laminate"
            where = line.spec.webs[r].name if laminate else web.name
            label = (f"web {where} (a layer of laminate {web.name})" if laminate
                     else f"{kind_of(web)} {web.name}")
            out.append(Finding(
                "warning", "yield", where,
                f"{label} strained beyond its yield ({100 * limit:.3g} %) in "
                f"{', '.join(names)} from t = {first:.4g} s, {duration:.4g} s in all, peak "
                f"{100 * peak:.3g} % at t = {peak_s:.4g} s", first,
                {"yield_strain": limit, "first_s": first, "duration_s": duration,
                 "peak_strain": peak, "peak_s": peak_s, "spans": names}))
    return out


def strength_failure(plan: BranchPlan, x: np.ndarray, t_fail: float) -> str:
    """Why a run stopped at a web's strength (``layout.STATUS_STRENGTH``), from its last
    state ``x``: the span, its web or lane, and the raw web (a laminate's layer) whose
    ``strength`` its tension reached."""
    line = plan.line
    k = int(np.argmax(x[:len(line.spans)] - plan.sf[:, B.SF_STRENGTH]))
    span = line.spans[k]
    web = line.spec.webs[span.web]
    terms = web_terms(line, span.web)
    limits = [np.inf if raw_material(line, r).strength is None else
              stretch_at(raw_law(line, r), raw_material(line, r).strength) / a
              for r, a, _ in terms]
    j = int(np.argmin(limits))  # the weakest raw web sets the span's limit (SF_STRENGTH)
    r = terms[j][0]
    raw = line.spec.webs[r].name
    whose = (f"web {raw} (a layer of laminate {web.name})" if kind_of(web) == "laminate"
             else f"{kind_of(web)} {web.name}")
    breaking = float(web_tension(line, span.web, np.array([limits[j]]))[0])
    return (f"{whose} broke: span {span.name} reached {breaking:.4g} N, the strain at which "
            f"web {raw} reaches its strength ({raw_material(line, r).strength:.4g} N), at "
            f"t = {t_fail:.4g} s")
