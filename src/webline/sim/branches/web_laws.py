"""Web laws on a branched line (docs/branching.md, "Web laws"): each raw web's
``stress_strain`` law, ``strength`` and its spans' Kelvin-Voigt dampers as the compiled loop's
tables (``sim.branches.loop.web_law``); what a run's records and verdict make of them is
``sim.branches.findings.web_findings``'s.

A span's law is a sum of terms over the raw webs it is made of, T(s) = Σ c F_w(a s)
(``web_terms``); a web whose raw webs are all linear has none (T = max(s, 0), as before).
"""

from __future__ import annotations

import numpy as np

from webline.model.web_graph import BranchedLine
from webline.physics.web_law import law_slope, law_tension
from webline.sim.branches.loop import layout as B
from webline.spec.branched.check import kind_of
from webline.spec.schema import WebSpec
from webline.spec.web_law import stretch_at
from webline.spec.web_law_checks import law_array

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
    Every table is empty on a line of linear elastic webs without laminates; a laminate's
    spans always have terms (its layers' columns: ``laminates.layer_columns``)."""
    raw = [w for w, web in enumerate(line.spec.webs) if kind_of(web) == "web"]
    laws = {w: raw_law(line, w) for w in raw}
    starts: dict[int, int] = {}
    flat: list[np.ndarray] = []
    for w in raw:
        starts[w] = int(sum(len(a) for a in flat))
        flat.append(laws[w])
    rows_i: list[tuple[int, int]] = []
    rows_f: list[tuple[float, float, float]] = []
    kv = []
    for span in line.spans:
        k = span.index
        terms = web_terms(line, span.web)
        strengths = [_strength_stretch(line, laws[r], r) for r, _, _ in terms]
        # (bonded layers: each its own strength at its own stretch, ``loop.laminate``)
        sf[k, B.SF_STRENGTH] = (min(u / a for u, (_, a, _) in zip(strengths, terms, strict=True))
                                if len(terms) == 1 else np.inf)
        if len(terms) > 1 or any(laws[r].size > 1 for r, _, _ in terms):  # layers, or a law
            si[k, B.S_LAW0], si[k, B.S_NLAW] = len(rows_i), len(terms)
            rows_i += [(r, starts[r]) for r, _, _ in terms]
            rows_f += [(a, c, u) for (_, a, c), u in zip(terms, strengths, strict=True)]
        spec = line.spec.webs[span.web].spans[span.k]
        if spec.model == "kelvin-voigt":
            sf[k, B.SF_TAU] = spec.retardation or 0.0
            kv.append(k)
    any_law = bool(rows_i)
    lawi = np.full((len(rows_i), B.LI_COLS), -1, dtype=np.int64)  # (layer columns: -1, 0)
    lawf = np.zeros((len(rows_f), B.LF_COLS))
    if rows_i:
        lawi[:, :2] = rows_i
        lawf[:, :2] = [row[:2] for row in rows_f]
        lawf[:, B.LF_STRENGTH] = [row[2] for row in rows_f]
    return (lawi, lawf,
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
