"""A fit's verdict: ``good`` (use it), ``poor`` (its values are the best this model finds, but
the model, the bounds or the optimiser left a sign that they are not the line's) or
``failed`` (no usable values), with the reasons in words; and the exit status of
``webline fit`` for each."""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

#: residuals larger than this many noise levels (RMS) mean the model misses something the
#: data show: white noise of the estimated levels gives 1 ± ~0.15 (the noise estimate from
#: second differences)
MISFIT = 1.5
#: exit status of ``webline fit`` by verdict (2 is bad input, 1 is not used by fit)
EXIT = {"good": 0, "poor": 4, "failed": 5}


@dataclass(frozen=True)
class Verdict:
    """``status`` ("good", "poor" or "failed") and why (empty for good)."""

    status: str
    reasons: tuple[str, ...]

    @property
    def good(self) -> bool:
        return self.status == "good"

    def line(self) -> str:
        """'verdict: poor (reason; reason)'."""
        why = f" ({'; '.join(self.reasons)})" if self.reasons else ""
        return f"verdict: {self.status}{why}"


def judge(
    *,
    residual_scale: float,
    converged: bool,
    message: str,
    failure: str,
    at_bound: Sequence[tuple[str, str]],
    reached: int | None = None,
    starts: int | None = None,
    lacks: Sequence[str] = (),
    records: Sequence[tuple[str, float]] = (),
) -> Verdict:
    """The verdict of a fit: ``failure`` (the fitted line's simulation failed: "" if not) or a
    residual scale that is not finite is ``failed``, as is a fit that neither converged nor
    reached the noise; a residual scale above ``MISFIT``, a value at a bound (``at_bound``:
    (path, "low"/"high") of the identifiable parameters) or no convergence is ``poor``.
    ``reached`` of ``starts`` starts found the best cost (said when only one did, as a
    caution, not a reason). ``lacks``: model checks that say the model lacks something
    (``twin.fitting.checks``: correlated residuals well above the noise over a window,
    which the residual scale over the whole record can hide) make it ``poor`` too.
    ``records``: (label, residual scale) of each record of a joint fit: a record above
    ``MISFIT`` makes it ``poor`` even where the joint scale is not (a short record the model
    misses can hide under a long one it matches)."""
    if failure or not math.isfinite(residual_scale):
        return Verdict(
            "failed",
            (f"the fitted line's simulation failed: {failure}" if failure else "no finite cost",),
        )
    reasons = []
    if residual_scale > MISFIT:
        reasons.append(
            f"residuals {residual_scale:.3g} x the noise (above {MISFIT:g}): the "
            "model misses something the data show"
        )
    if len(records) > 1:
        reasons.extend(
            f"{label}: residuals {scale:.3g} x the noise (above {MISFIT:g}): the model "
            "misses something this record shows"
            for label, scale in records
            if not math.isfinite(scale) or scale > MISFIT
        )
    for path, side in at_bound:
        reasons.append(
            f"{path} at its {'lower' if side == 'low' else 'upper'} bound: the "
            "bound is too tight, or the value stands in for something the model "
            "lacks"
        )
    reasons.extend(f"the model likely lacks something: {finding}" for finding in lacks)
    if not converged:
        reasons.append(f"not converged ({message})")
        if residual_scale > MISFIT:
            return Verdict("failed", tuple(reasons))
    if reasons and starts is not None and starts > 1 and reached == 1:
        reasons.append(f"only 1 of {starts} starts reached the best cost: try more --starts")
    return Verdict("poor" if reasons else "good", tuple(reasons))
