"""The layer columns of a branched line's law terms (``layout`` LI_SPAN .. LF_STRENGTH) and
the layer states they number: a bonded laminate's per-layer offsets and lengths
(docs/branching.md, (B2); the loop's ``loop.laminate``, the records'
``laminates``)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from webline.sim.branches.loop import layout as B
from webline.sim.branches.web_laws import web_terms
from webline.spec.branched.check import kind_of

if TYPE_CHECKING:
    from webline.model.web_graph import BranchedLine


def _upstream(line: BranchedLine, k: int, si: np.ndarray) -> list[tuple[int, int]]:
    """Per term of span ``k``: (the span upstream whose stretch it carries in, that span's
    term number)."""
    span = line.spans[k]
    web = line.spec.webs[span.web]
    if span.k > 0:
        return [(k - 1, j) for j in range(len(web_terms(line, span.web)))]
    if kind_of(web) == "laminate":
        out = []
        for name in web.layers or []:
            w = line.web_index[name]
            out += [(line.web_spans(w)[-1], j) for j in range(len(web_terms(line, w)))]
        return out
    base = int(si[k, B.S_FROM])  # a lane of a laminate: its base web's last span
    return [(base, j) for j in range(len(web_terms(line, span.web)))]


def layer_columns(
    line: BranchedLine, si: np.ndarray, offsets: np.ndarray, lawi: np.ndarray, lawf: np.ndarray
) -> None:
    """Fill the layer columns of the law terms (``layout`` LI_SPAN .. LF_STRENGTH) and give
    every term of a span of several raw webs its offset state, and every such web's terms
    their length in and out, at the end of the state (``offsets`` O_LAYER, O_LAYER_END, O_N
    grow)."""
    offsets[B.O_LAYER] = offsets[B.O_LAYER_END] = offsets[B.O_N]
    state = int(offsets[B.O_N])
    for span in line.spans:
        k = span.index
        first, count = int(si[k, B.S_LAW0]), int(si[k, B.S_NLAW])
        for j, (r, _, _) in enumerate(web_terms(line, span.web)[:count]):
            lawi[first + j, B.LI_SPAN] = k
            lawf[first + j, B.LF_EA] = line.materials[r].ea
        if count > 1:  # bonded layers: one offset each
            for j in range(count):
                lawi[first + j, B.LI_STATE] = state
                state += 1
    for span in line.spans:  # where each term's stretch comes from (its states now known)
        k = span.index
        first, count = int(si[k, B.S_LAW0]), int(si[k, B.S_NLAW])
        if count < 2:
            continue
        for j, (up, m) in enumerate(_upstream(line, k, si)):
            lawi[first + j, B.LI_UP] = up
            terms = web_terms(line, line.spans[up].web)
            lawf[first + j, B.LF_UPSCALE] = terms[m][1]
            if si[up, B.S_NLAW] > 1:
                lawi[first + j, B.LI_UPSTATE] = lawi[si[up, B.S_LAW0] + m, B.LI_STATE]
    for w in range(len(line.spec.webs)):  # each layer's length in and out of its web
        spans = line.web_spans(w)
        count = int(si[spans[0], B.S_NLAW])
        if count < 2:
            continue
        for j in range(count):
            lawi[si[spans[0], B.S_LAW0] + j, B.LI_LIN] = state
            lawi[si[spans[-1], B.S_LAW0] + j, B.LI_LOUT] = state + 1
            state += 2
    offsets[B.O_LAYER_END] = offsets[B.O_N] = state
