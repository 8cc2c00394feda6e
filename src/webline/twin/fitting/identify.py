"""Which fitted parameters the data identify: a parameter is named "not identifiable from
this data" when its 95 % interval is wider than its bounds, when it takes part in a
near-zero singular direction of the (column-normalised) Jacobian, or when it correlates
with another beyond ``MAX_CORRELATION`` and its interval is not narrow (wider than
``NARROW`` of its bounds): the standard errors already carry the correlation, so two
parameters a joint fit pins to 0.02 % each (EA and a span length, correlated +0.996 through
their ratio) are both identified."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

#: |correlation| beyond which two parameters are not separated by the data
MAX_CORRELATION = 0.95
#: an interval narrower than this share of its bounds is an identified value whatever its
#: correlation with another
NARROW = 0.1
#: a singular value of the column-normalised Jacobian below this share of the largest is a
#: direction the data do not see
SINGULAR_RATIO = 1e-3
#: a parameter takes part in a singular direction where its component exceeds this
PARTICIPATION = 0.3


@dataclass(frozen=True)
class Identifiability:
    """Per parameter: identifiable or not, and why not ("" if identifiable)."""

    identifiable: np.ndarray
    reasons: tuple[str, ...]


def identifiability(jac: np.ndarray, ci95: np.ndarray, low: np.ndarray, high: np.ndarray,
                    correlation: np.ndarray, names: list[str]) -> Identifiability:
    """The verdict for each column of ``jac`` (residuals over scaled parameters ``names``,
    bounds ``low``, ``high`` and intervals ``ci95`` in SI)."""
    n = jac.shape[1]
    why: list[list[str]] = [[] for _ in range(n)]
    norms = np.linalg.norm(jac, axis=0)
    dead = norms <= 1e-12 * max(float(norms.max()), 1e-300)
    for i in np.flatnonzero(dead).tolist():
        why[i].append("the data do not depend on it")
    alive = np.flatnonzero(~dead)
    if len(alive):
        _, sv, vt = np.linalg.svd(jac[:, alive] / norms[alive], full_matrices=False)
        for k in np.flatnonzero(sv < SINGULAR_RATIO * sv[0]).tolist():
            for j in np.flatnonzero(np.abs(vt[k]) > PARTICIPATION).tolist():
                why[alive[j]].append(f"a near-zero singular direction "
                                     f"({sv[k] / sv[0]:.1e} of the largest)")
    for i in range(n):
        if ci95[i, 1] - ci95[i, 0] > high[i] - low[i]:
            why[i].append("its 95 % interval is wider than its bounds")
        narrow = ci95[i, 1] - ci95[i, 0] < NARROW * (high[i] - low[i])
        for j in range(n):
            if j != i and abs(correlation[i, j]) > MAX_CORRELATION and not narrow:
                why[i].append(f"correlation {correlation[i, j]:+.3f} with {names[j]}")
    reasons = tuple("; ".join(dict.fromkeys(w)) for w in why)
    return Identifiability(np.array([not r for r in reasons]), reasons)
