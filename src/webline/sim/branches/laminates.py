"""Bonded laminates on a branched line (docs/branching.md, (B2)): what a run's records
make of the layer states of the compiled loop (``loop.laminate``; their tables:
``laminate_tables``): each layer's stretch, tension and unstrained length per laminate span.

Layers gripped at a nip move together from there on but keep the strain each was bonded
with: a laminate span's state is its stretch s = EA_L ε_L (ε_L the EA-weighted mean of its
layers' strains, whose mass balance is the span equation 6.8 of the laminate) and, per layer
(raw web r, term (r, a, c) of ``web_laws.web_terms``), the offset o of its own stretch
u = a s + o = EA_r ε_r, advected with the web as the strain is: L do/dt = v_a o_in - v_b o.
At the nip the laminate's stretch in is the sum of its layers' (Σ EA_i ε_i) and each offset
takes the rest of its layer's stretch, so every layer's unstrained length passes the nip
unchanged; the layer's tension is its own law at u, the laminate's their sum.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from webline.sim.branches.loop import layout as B
from webline.sim.branches.web_laws import raw_law, web_terms

if TYPE_CHECKING:
    from webline.model.web_graph import BranchedLine
    from webline.sim.branches.plan import BranchPlan


def layer_rows(plan: BranchPlan, k: int) -> list[tuple[int, int]]:
    """(law-term row, raw web) of each bonded layer of span ``k`` (empty: one raw web)."""
    first, count = int(plan.si[k, B.S_LAW0]), int(plan.si[k, B.S_NLAW])
    if count < 2:
        return []
    return [(t, int(plan.lawi[t, B.LI_WEB])) for t in range(first, first + count)]


def layer_terms(plan: BranchPlan, layer: int, k: int) -> range:
    """Law-term rows of layer web ``layer`` (a raw web, or a laminate's or lane's raw webs)
    in laminate span ``k``: a block of the span's terms, in layer order."""
    line = plan.line
    first = int(plan.si[k, B.S_LAW0])
    for name in line.spec.webs[line.spans[k].web].layers or []:
        count = len(web_terms(line, line.web_index[name]))
        if line.web_index[name] == layer:
            return range(first, first + count)
        first += count
    raise ValueError(f"web {layer} is no layer of span {k}'s laminate")


def layer_strain(plan: BranchPlan, layer: int, k: int, states: np.ndarray) -> np.ndarray:
    """Strain [-] of layer web ``layer`` in laminate span ``k`` at each record of ``states``:
    its own, Σ u / EA_layer over its raw webs (a raw layer's u / EA; a laminate as a layer:
    its EA-weighted mean)."""
    ea = plan.line.materials[layer].ea
    return (
        sum(
            (layer_stretch(plan, t, states) for t in layer_terms(plan, layer, k)),
            np.zeros(len(states)),
        )
        / ea
    )


def layer_stretch(plan: BranchPlan, t: int, states: np.ndarray) -> np.ndarray:
    """Own stretch u = a s + o [N] = EA_r ε_r of law term ``t``'s layer at each record of
    ``states`` (records x states)."""
    k = int(plan.lawi[t, B.LI_SPAN])
    return plan.lawf[t, B.LF_SCALE] * states[:, k] + states[:, plan.lawi[t, B.LI_STATE]]


def mirrored_tension(line: BranchedLine, r: int, u: np.ndarray) -> np.ndarray:
    """Tension [N] raw web ``r``'s law gives a bonded layer at its stretch ``u`` [N]: the law
    mirrored in compression, F(u) = -F(-u) (docs/nonlinear-web.md, "Bonded layers")."""
    from webline.physics.web_law import law_tension

    law = raw_law(line, r)
    return np.array([np.sign(v) * law_tension(abs(v), law) for v in np.ravel(u)]).reshape(
        np.shape(u)
    )


def layer_names(plan: BranchPlan) -> list[tuple[str, int, int]]:
    """('laminate web/raw web', law-term row in its first span, row in its last) of every
    layer of every web of several raw webs."""
    line = plan.line
    out = []
    for w, web in enumerate(line.spec.webs):
        spans = line.web_spans(w)
        rows_first, rows_last = layer_rows(plan, spans[0]), layer_rows(plan, spans[-1])
        out += [
            (f"{web.name}/{line.spec.webs[r].name}", t, u)
            for (t, r), (u, _) in zip(rows_first, rows_last, strict=True)
        ]
    return out


def layer_lengths(
    plan: BranchPlan, states: np.ndarray, lengths: np.ndarray
) -> tuple[list[str], np.ndarray, np.ndarray, np.ndarray]:
    """(names, in, out, stored) [m] of each layer's unstrained length per laminate web at
    each record: in at its first span, out at its last, stored in its spans
    Σ L EA_r/(EA_r + u), or Σ L (1 - u / EA_r) with first-order transport (errata E-6.6;
    ``lengths``: each span's length at each record)."""
    line = plan.line
    names, into, out, stored = [], [], [], []
    for name, t_first, t_last in layer_names(plan):
        w = line.spans[int(plan.lawi[t_first, B.LI_SPAN])].web
        names.append(name)
        into.append(states[:, plan.lawi[t_first, B.LI_LIN]])
        out.append(states[:, plan.lawi[t_last, B.LI_LOUT]])
        j = t_first - int(plan.si[line.web_spans(w)[0], B.S_LAW0])
        ea = plan.lawf[t_first, B.LF_EA]
        held = [layer_stretch(plan, int(plan.si[k, B.S_LAW0]) + j, states) / ea
                 for k in line.web_spans(w)]
        stored.append(
            sum(
                lengths[:, k] * (1.0 / (1.0 + e) if line.exact else 1.0 - e)
                for k, e in zip(line.web_spans(w), held, strict=True)
            )
        )
    n = len(states)
    return (
        names,
        np.array(into).T.reshape(n, len(names)),
        np.array(out).T.reshape(n, len(names)),
        np.array(stored).T.reshape(n, len(names)),
    )
