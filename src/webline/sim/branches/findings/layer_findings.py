"""What a branched run's records make of its bonded laminates (docs/branching.md, (B2)):
a layer in compression, where, when, for how long and how far below zero."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from webline.sim.branches.laminates import layer_rows, layer_stretch, mirrored_tension
from webline.spec.branched.check import kind_of
from webline.verdict import Finding

if TYPE_CHECKING:
    from webline.sim.branches.plan import BranchPlan


def layer_strains(plan: BranchPlan, w: int, states: np.ndarray) -> list[tuple[int, np.ndarray]]:
    """(raw web, own strain [-] per record x span of web ``w``) of each bonded layer of
    ``w``'s spans (empty: ``w`` is one raw web)."""
    line = plan.line
    spans = line.web_spans(w)
    rows = [layer_rows(plan, k) for k in spans]
    if not rows[0]:
        return []
    out = []
    for j, (_, r) in enumerate(rows[0]):
        ea = line.materials[r].ea
        out.append(
            (
                r,
                np.stack(
                    [layer_stretch(plan, rows[i][j][0], states) / ea for i in range(len(spans))],
                    axis=1,
                ),
            )
        )
    return out


def episode(plan: BranchPlan, time: np.ndarray, mask: np.ndarray,
            spans: list[int]) -> tuple[float, float, list[str]]:
    """(first record's time [s], the records' time summed [s], the spans' names) where
    ``mask`` (records x a web's ``spans``) holds: what a finding over records says."""
    step = np.diff(time, append=time[-1])
    rows = np.any(mask, axis=1)
    names = [plan.line.spans[spans[j]].name for j in np.nonzero(mask.any(axis=0))[0]]
    return float(time[np.argmax(rows)]), float(step[rows].sum()), names


def compressed_findings(plan: BranchPlan, time: np.ndarray, states: np.ndarray) -> list[Finding]:
    """A ``warning`` ``layer_compressed`` per bonded layer whose own strain went below zero
    in a laminate's (or its lanes') spans: the layer (its raw web), the spans, the first
    record in compression [s], the records' time in compression summed [s], and its lowest
    tension [N] (its law mirrored: docs/nonlinear-web.md, "Bonded layers") with its time. A
    bonded layer in compression is held straight by the others, as a whole laminate under
    tension, but it wrinkles where the bond or the web lets it and curls the laminate off
    the line."""
    line = plan.line
    if len(time) == 0:
        return []
    out: list[Finding] = []
    for w, web in enumerate(line.spec.webs):
        spans = line.web_spans(w)
        for r, strain in layer_strains(plan, w, states):
            below = strain < 0.0
            if not below.any():
                continue
            first, duration, names = episode(plan, time, below, spans)
            at = np.unravel_index(int(np.argmin(strain)), strain.shape)
            low = float(mirrored_tension(line, r, np.array([strain[at] * line.materials[r].ea]))[0])
            raw = line.spec.webs[r].name
            out.append(
                Finding(
                    "warning",
                    "layer_compressed",
                    raw,
                    f"web {raw} (a layer of {kind_of(web)} {web.name}) in compression in "
                    f"{', '.join(names)} from t = {first:.4g} s, {duration:.4g} s in all, down to "
                    f"{low:.4g} N at t = {float(time[at[0]]):.4g} s (wrinkle and curl risk)",
                    first,
                    {
                        "first_s": first,
                        "duration_s": duration,
                        "min_tension_N": low,
                        "min_strain": float(strain[at]),
                        "min_s": float(time[at[0]]),
                        "spans": names,
                    },
                )
            )
    return out
