"""What a branched run's records and verdict make of its web laws (docs/branching.md, "Web
laws"): the tensions the rollers feel and each layer's, their rows in the linear model,
strain beyond a web's yield per web and lane (the chain's ``sim.results.yield_findings``,
N4), and the stop at a web's strength."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from webline.sim.branches.findings.layer_findings import episode, layer_strains
from webline.sim.branches.laminates import layer_stretch, layer_terms, mirrored_tension
from webline.sim.branches.loop import layout as B
from webline.sim.branches.loop.plant import rhs
from webline.sim.branches.loop.web_law import felt_view
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
    with its time. A layer's strain in a laminate is its own (bonded with its offset:
    ``sim.branches.laminates``)."""
    line = plan.line
    if len(time) == 0:
        return []
    out: list[Finding] = []
    for w, web in enumerate(line.spec.webs):
        spans = line.web_spans(w)
        bonded = layer_strains(plan, w, states)  # a laminate's layers: their own strains
        for j, (r, a, _) in enumerate(web_terms(line, w)):
            law = raw_material(line, r).stress_strain
            if law is None or law.yield_strain is None:
                continue
            limit = law.yield_strain
            strain = (bonded[j][1] if bonded  # ε of raw web r's material
                      else a * states[:, spans] / line.materials[r].ea)
            beyond = strain > limit
            if not beyond.any():
                continue
            first, duration, names = episode(plan, time, beyond, spans)
            at = np.unravel_index(int(np.argmax(strain)), strain.shape)
            peak, peak_s = float(strain[at]), float(time[at[0]])
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
    bonded = np.nonzero(plan.lawi[:, B.LI_STATE] >= 0)[0]
    over = [plan.lawf[t, B.LF_SCALE] * x[plan.lawi[t, B.LI_SPAN]] + x[plan.lawi[t, B.LI_STATE]]
            - plan.lawf[t, B.LF_STRENGTH] for t in bonded]
    if over and max(over) > 0.0:  # a bonded layer at its own strength
        t = int(bonded[int(np.argmax(over))])
        r = int(plan.lawi[t, B.LI_WEB])
        span = line.spans[int(plan.lawi[t, B.LI_SPAN])]
        web = line.spec.webs[span.web]
        raw = line.spec.webs[r].name
        return (f"web {raw} (a layer of {kind_of(web)} {web.name}) broke: in span "
                f"{span.name} it reached its strength ({raw_material(line, r).strength:.4g} N)"
                f" at t = {t_fail:.4g} s")
    k = int(np.argmax(x[:len(line.spans)] - plan.sf[:, B.SF_STRENGTH]))
    span = line.spans[k]
    web = line.spec.webs[span.web]
    terms = web_terms(line, span.web)
    strengths = [raw_material(line, r).strength for r, _, _ in terms]
    limits = [np.inf if s is None else stretch_at(raw_law(line, r), s) / a
              for s, (r, a, _) in zip(strengths, terms, strict=True)]
    j = int(np.argmin(limits))  # the weakest raw web sets the span's limit (SF_STRENGTH)
    r = terms[j][0]
    raw = line.spec.webs[r].name
    whose = (f"web {raw} (a layer of laminate {web.name})" if kind_of(web) == "laminate"
             else f"{kind_of(web)} {web.name}")
    breaking = float(web_tension(line, span.web, np.array([limits[j]]))[0])
    return (f"{whose} broke: span {span.name} reached {breaking:.4g} N, the strain at which "
            f"web {raw} reaches its strength ({strengths[j]:.4g} N), at "
            f"t = {t_fail:.4g} s")


def has_laws(plan: BranchPlan) -> bool:
    """Whether the line's spans feel anything other than their clipped stretch."""
    return plan.lawi.shape[0] > 0 or plan.kv.shape[0] > 0


def felt_records(plan: BranchPlan, time: np.ndarray, states: np.ndarray) -> np.ndarray:
    """Tension [N] the rollers feel in each span at each record (records x spans): the
    clipped stretch of a linear elastic line, else evaluated by the kernel's own
    right-hand side (F(s) + τ ds/dt, the held wound-in tensions at each record's time)."""
    n_s, n_n = len(plan.line.spans), plan.nodes.shape[0]
    if not has_laws(plan):
        return np.maximum(states[:, :n_s], 0.0)
    dx, work = np.zeros(plan.n_x), plan.scratch()
    cmd = np.zeros(plan.di.shape[0])
    out = np.empty((len(time), n_s))
    held = plan.held(0.0)
    for r, t in enumerate(time):
        if plan.kv.shape[0]:  # the first spans' rates see the wound-in tension
            held = plan.held(float(t))
        rhs(np.ascontiguousarray(states[r]), cmd, held, *plan.tables(), dx, work)
        out[r] = felt_view(work, n_s, n_n, plan.lawi.shape[0] > 0, plan.kv.shape[0] > 0)
    return out


def layer_tension(plan: BranchPlan, layer: int, k: int, states: np.ndarray,
                  felt: np.ndarray) -> np.ndarray:
    """Tension [N] layer web ``layer`` carries in laminate span ``k`` at its records
    (``states``: records x states, ``felt`` [N]: the span's): each of its raw webs' law
    (mirrored in compression) at its own stretch a s + o (``sim.branches.laminates``), plus
    its stiffness share of a damper's force."""
    line = plan.line
    own = layer_terms(plan, layer, k)
    out = np.zeros(len(states))
    elastic = np.zeros(len(states))
    for t in range(int(plan.si[k, B.S_LAW0]), int(plan.si[k, B.S_LAW0] + plan.si[k, B.S_NLAW])):
        r = int(plan.lawi[t, B.LI_WEB])
        carried = plan.lawf[t, B.LF_FACTOR] * mirrored_tension(
            line, r, layer_stretch(plan, t, states))
        elastic += carried
        if t in own:
            out += carried
    share = line.materials[layer].ea / plan.sf[k, B.SF_EA]
    return out + share * (felt - np.maximum(elastic, 0.0))


def felt_rows(plan: BranchPlan, x0: np.ndarray, keep: np.ndarray,
              steps: np.ndarray) -> np.ndarray:
    """Rows M [N per state unit] of the felt tensions δT = M δx over the kept states ``keep``
    at the state ``x0``, central differences of ``plant.rhs`` with ``steps`` (the plant's):
    F'(s) on the diagonal, plus τ times the span rows of A on a Kelvin-Voigt span. [I 0] on
    a linear elastic line, whose loadcells read the stretch itself."""
    n_s, n_n = len(plan.line.spans), plan.nodes.shape[0]
    if not has_laws(plan):
        return np.eye(n_s, len(keep))
    dx, work = np.zeros(plan.n_x), plan.scratch()
    cmd = np.zeros(plan.di.shape[0])  # (the span rates and tensions do not read it)

    def felt(x: np.ndarray) -> np.ndarray:
        rhs(x, cmd, plan.wound, *plan.tables(), dx, work)
        return felt_view(work, n_s, n_n, plan.lawi.shape[0] > 0, plan.kv.shape[0] > 0).copy()

    rows = np.empty((n_s, len(keep)))
    for col, (m, h) in enumerate(zip(keep, steps, strict=True)):
        x = x0.copy()
        x[m] += h
        up = felt(x)
        x[m] -= 2 * h
        rows[:, col] = (up - felt(x)) / (2 * h)
    return rows


def felt_wound_rows(plan: BranchPlan, x0: np.ndarray, webs: list[int]) -> np.ndarray:
    """Columns [N/N] of the felt tensions over the wound-in tensions of ``webs`` at the state
    ``x0``: τ times a first span's (B1) input on a Kelvin-Voigt span, zero elsewhere; central
    differences of 1 N (exact for a linear web, whose rates are affine in the input)."""
    n_s, n_n = len(plan.line.spans), plan.nodes.shape[0]
    dx, work = np.zeros(plan.n_x), plan.scratch()
    cmd = np.zeros(plan.di.shape[0])
    x = np.ascontiguousarray(x0)
    out = np.zeros((n_s, len(webs)))
    if not plan.kv.shape[0]:
        return out
    for col, w in enumerate(webs):
        felt = []
        for step in (1.0, -1.0):
            wound = plan.wound.copy()
            wound[w] += step
            rhs(x, cmd, wound, *plan.tables(), dx, work)
            felt.append(felt_view(work, n_s, n_n, False, True).copy())
        out[:, col] = (felt[0] - felt[1]) / 2.0
    return out
