"""Web laws on a branched line (docs/branching.md, "Web laws"): each raw web's
``stress_strain`` law, ``strength`` and its spans' Kelvin-Voigt dampers as the compiled loop's
tables (``sim.branches.loop.web_law``), and what a run's records and verdict make of them:
felt and layer tensions, the failure at a web's strength, strain beyond yield.

A span's law is a sum of terms over the raw webs it is made of, T(s) = Σ c F_w(a s)
(``web_terms``); a web whose raw webs are all linear has none (T = max(s, 0), as before).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from webline.model.web_graph import BranchedLine
from webline.physics.web_law import law_slope, law_tension
from webline.sim.branches.loop import layout as B
from webline.sim.branches.loop.plant import rhs
from webline.sim.branches.loop.web_law import felt_view
from webline.spec.branched.check import kind_of
from webline.spec.schema import WebSpec
from webline.spec.web_law import stretch_at
from webline.spec.web_law_checks import law_array
from webline.verdict import Finding

if TYPE_CHECKING:
    from webline.sim.branches.plan import BranchPlan

#: a term: (raw web, scale a on the span's stretch, factor c on its law's tension)
Term = tuple[int, float, float]


def raw_material(line: BranchedLine, w: int) -> WebSpec:
    """The ``web`` table of raw web ``w`` (its own, else the line's)."""
    web = line.spec.webs[w]
    material = web.web or line.spec.web
    assert material is not None and kind_of(web) == "web"
    return material


def web_terms(line: BranchedLine, w: int) -> list[Term]:
    """The terms of web ``w``'s law in its own stretch s = EA_w ε: a raw web (w, 1, 1); a
    laminate its layers' terms with a scaled by EA_i / EA_L (its layers share its strain); a
    lane its base web's with a / φ and c φ, φ = EA_lane / EA_base (its area share)."""
    web = line.spec.webs[w]
    ea = line.materials[w].ea
    if web.layers is not None:
        out = []
        for name in web.layers:
            i = line.web_index[name]
            share = line.materials[i].ea / ea
            out += [(r, a * share, c) for r, a, c in web_terms(line, i)]
        return out
    if web.slit_from is not None:
        base = line.web_index[web.slit_from]
        phi = ea / line.materials[base].ea
        return [(r, a / phi, c * phi) for r, a, c in web_terms(line, base)]
    return [(w, 1.0, 1.0)]


def raw_law(line: BranchedLine, w: int) -> np.ndarray:
    """Raw web ``w``'s law array in its stretch (``spec.web_law_checks.law_array``)."""
    return law_array(raw_material(line, w), line.materials[w].ea)


def law_tables(line: BranchedLine, si: np.ndarray,
               sf: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(lawi, lawf, laws, kv) of ``line`` (``layout`` LI_*, LF_*; the flat law arrays; the
    Kelvin-Voigt spans), filling the span tables' S_LAW0, S_NLAW, SF_TAU and SF_STRENGTH.
    Every table is empty on a line of linear elastic webs."""
    raw = [w for w, web in enumerate(line.spec.webs) if kind_of(web) == "web"]
    laws = {w: raw_law(line, w) for w in raw}
    starts, flat = {}, []
    for w in raw:
        starts[w] = sum(len(a) for a in flat)
        flat.append(laws[w])
    rows_i: list[tuple[int, int]] = []
    rows_f: list[tuple[float, float]] = []
    kv = []
    for span in line.spans:
        k = span.index
        terms = web_terms(line, span.web)
        sf[k, B.SF_STRENGTH] = min(_strength_stretch(line, laws[r], r) / a for r, a, _ in terms)
        if any(laws[r].size > 1 for r, _, _ in terms):  # some raw web is nonlinear
            si[k, B.S_LAW0], si[k, B.S_NLAW] = len(rows_i), len(terms)
            rows_i += [(r, starts[r]) for r, _, _ in terms]
            rows_f += [(a, c) for _, a, c in terms]
        spec = line.spec.webs[span.web].spans[span.k]
        if spec.model == "kelvin-voigt":
            sf[k, B.SF_TAU] = spec.retardation or 0.0
            kv.append(k)
    any_law = bool(rows_i)
    return (np.array(rows_i, dtype=np.int64).reshape(-1, B.LI_COLS),
            np.array(rows_f, dtype=float).reshape(-1, B.LF_COLS),
            np.concatenate(flat) if any_law else np.zeros(0),
            np.array(kv, dtype=np.int64))


def _strength_stretch(line: BranchedLine, law: np.ndarray, w: int) -> float:
    """Stretch [N] of raw web ``w`` at its ``strength`` (inf without one)."""
    strength = raw_material(line, w).strength
    return np.inf if strength is None else stretch_at(law, strength)


def web_tension(line: BranchedLine, w: int, stretch: np.ndarray) -> np.ndarray:
    """Elastic tension [N] of web ``w`` at ``stretch`` [N] (its own s = EA_w ε), from its
    terms: plain Python over ``physics.web_law``, for records and tests."""
    out = np.zeros_like(stretch, dtype=float)
    for r, a, c in web_terms(line, w):
        law = raw_law(line, r)
        out += c * np.array([law_tension(a * s, law) for s in np.ravel(stretch)]).reshape(
            np.shape(stretch))
    return out


def web_slope(line: BranchedLine, w: int, stretch: float) -> float:
    """Tangent dT/ds [-] of web ``w``'s law at ``stretch`` [N]: Σ c a F_r'(a s); times EA_w,
    the tangent stiffness dT/dε [N]."""
    return float(sum(c * a * law_slope(a * stretch, raw_law(line, r))
                     for r, a, c in web_terms(line, w)))


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


def layer_tension(plan: BranchPlan, layer: int, k: int, stretch: np.ndarray,
                  felt: np.ndarray) -> np.ndarray:
    """Tension [N] layer web ``layer`` carries in laminate span ``k`` at its records
    (``stretch``, ``felt`` [N]): its own law at the laminate's strain plus its stiffness
    share of a damper's force; (EA_i / EA_L) x T_L on a linear elastic line."""
    line = plan.line
    share = line.materials[layer].ea / plan.sf[k, B.SF_EA]
    if not has_laws(plan):
        return share * felt
    elastic = web_tension(line, line.spans[k].web, stretch)
    return web_tension(line, layer, share * stretch) + share * (felt - elastic)


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
