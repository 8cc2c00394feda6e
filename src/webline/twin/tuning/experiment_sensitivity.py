"""Which parameters a planned experiment (on any line, single-path or branched) can identify,
checked before it is run: the
sensitivities of the signals it logs to each requested parameter, from simulations of the
planned test with each parameter moved by ``STEP`` of its value (of its bounds' width where
it is 0; finite differences of the full nonlinear line, on the ticks of the logging rate the
plan states).

Each sensitivity column is d(signal)/d(p/scale) over the signal's sensor noise (the scale
the value, or the bounds' width for a value of 0)
(``twin.traces.synthetic.NOISE``), so the columns together are the Jacobian a fit of the
test's record would see at the truth. With white noise the least-squares covariance of the
scaled parameters is (SᵀS)⁻¹: a 95 % interval per parameter, and the correlations. The verdict is
the fit's own (``twin.fitting.identify``): a parameter the signals do not depend on, one in a
near-zero singular direction of the column-normalised S, one whose interval is wider than its
bounds or which correlates with another beyond 0.95 cannot be identified by this test. The
intervals are those of sensor noise alone (the best case: a model error or correlated noise
only widens them), so a parameter called identifiable here may still be fitted loosely, but
one called not identifiable will not be fitted from this test.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from webline.errors import ArgumentError
from webline.line import Line
from webline.model.web_graph import BranchedLine
from webline.sim.simulate import simulate
from webline.twin.fitting.free import FreeParameter, parse_free
from webline.twin.fitting.identify import identifiability
from webline.twin.traces.runs import common_substeps
from webline.twin.traces.signals import simulated
from webline.twin.traces.synthetic import NOISE, logged_signals
from webline.twin.tuning.experiment import ExperimentPlan

#: each parameter is moved by this share of its value for its sensitivity
STEP = 0.01
#: bounds of a requested parameter given without them: its value divided and multiplied by
DEFAULT_FACTOR = 2.0


@dataclass(frozen=True)
class Sensitivity:
    """The check of a plan: per parameter its path, value [SI], the 95 % interval's half
    width [SI] (sensor noise alone), whether the test identifies it and why not; the
    condition number of the column-normalised sensitivity matrix."""

    paths: tuple[str, ...]
    value: np.ndarray
    half_width: np.ndarray
    identifiable: np.ndarray
    reasons: tuple[str, ...]
    condition: float

    def lines(self) -> list[str]:
        """The check in words, one line per parameter."""
        out = []
        for i, path in enumerate(self.paths):
            verdict = ("identifiable" if self.identifiable[i]
                       else f"NOT identifiable by this test: {self.reasons[i]}")
            share = (f" = {100 * self.half_width[i] / abs(self.value[i]):.2g} %"
                     if self.value[i] else "")
            out.append(f"{path} = {self.value[i]:.4g}: ±{self.half_width[i]:.2g}{share} "
                       f"(95 %, sensor noise alone); {verdict}")
        return out

    def as_dict(self) -> dict[str, object]:
        return {"condition_number": self.condition, "parameters": [
            {"path": p, "value": float(self.value[i]),
             "half_width_95": float(self.half_width[i]),
             "identifiable": bool(self.identifiable[i]), "why_not": self.reasons[i]}
            for i, p in enumerate(self.paths)]}


def requested(line: Line | BranchedLine, identify: Sequence[str]) -> list[FreeParameter]:
    """The parameters of ``identify``: ``PATH`` (bounds the value / and x ``DEFAULT_FACTOR``)
    or ``PATH=LOW..HIGH UNIT`` as ``fit --free`` takes them, ``*`` wildcards expanded."""
    from webline.twin.fitting.free import expand, lookup

    data = line.spec.model_dump(exclude_none=True)
    out: list[FreeParameter] = []
    for item in identify:
        path, _, bounds = (part.strip() for part in item.partition("="))
        if bounds:
            out += parse_free(line, {path: bounds})
            continue
        found = expand(data, path)
        if not found:
            raise ArgumentError(f"identify {path}: matches no value of line {line.name!r}")
        for one in found:
            value = lookup(data, one)  # SI, as the line file's schema holds it
            if value is None:
                raise ArgumentError(f"identify {one}: matches no value of line {line.name!r}")
            if not isinstance(value, int | float) or value <= 0:
                raise ArgumentError(f"identify {one}: no positive number there in line "
                                    f"{line.name!r}; give bounds as PATH=LOW..HIGH")
            out.append(FreeParameter(one, value / DEFAULT_FACTOR, value * DEFAULT_FACTOR, "",
                                     float(value)))
    if len({p.path for p in out}) < len(out):
        raise ArgumentError("identify: a parameter is named twice")
    return out


def _logged(line: Line | BranchedLine, duration: float, rate: float, substeps: int
            ) -> np.ndarray:
    """The logged signals of ``line`` run for ``duration`` [s] at ``rate`` [Hz], each over
    its sensor noise, end to end."""
    result = simulate(line, duration, record_interval=1.0 / rate, substeps=substeps,
                      raise_on_failure=False)
    if result.failure is not None:
        raise ArgumentError(f"identify: the planned test fails on {line.name}: "
                            f"{result.message}")
    chosen = [s for s in logged_signals(line) if s.kind in NOISE]
    values = simulated(result, chosen)
    return np.concatenate([values[s.name] / NOISE[s.kind] for s in chosen])


def check_plan(plan: ExperimentPlan, identify: Sequence[str]) -> Sensitivity:
    """Which of ``identify`` (``requested``'s forms) ``plan`` can identify (module
    docstring): n + 1 simulations of the planned test."""
    line = plan.line
    params = requested(line, identify)
    values = np.array([p.start for p in params])
    scale = np.array([abs(p.start) or p.high - p.low for p in params])
    # a step up, or down where up would leave the bounds
    steps = np.array([STEP if p.start + STEP * sc <= p.high else -STEP
                      for p, sc in zip(params, scale, strict=True)])
    cases = [{p.path: p.start + h * sc} for p, h, sc in zip(params, steps, scale, strict=True)]
    substeps = common_substeps(line, cases)
    base = _logged(line, plan.duration, plan.logging_rate, substeps)
    s = np.column_stack([(_logged(line.replace(case), plan.duration, plan.logging_rate,
                                  substeps) - base) / h for case, h in zip(cases, steps,
                                                                            strict=True)])
    names = [p.path for p in params]
    cov = np.linalg.pinv(s.T @ s)
    sd = np.sqrt(np.clip(np.diag(cov), 0.0, None))
    half = 1.96 * sd * scale  # [SI]
    ci95 = np.column_stack([values - half, values + half])
    unit = np.where(sd > 0, sd, 1.0)
    correlation = np.clip(cov / np.outer(unit, unit), -1.0, 1.0)
    low, high = np.array([p.low for p in params]), np.array([p.high for p in params])
    verdict = identifiability(s, ci95, low, high, correlation, names)
    norms = np.linalg.norm(s, axis=0)
    sv = np.linalg.svd(s / np.where(norms > 0, norms, 1.0), compute_uv=False)
    condition = float(sv[0] / sv[-1]) if sv[-1] > 0 else float("inf")
    return Sensitivity(tuple(names), values, half, verdict.identifiable, verdict.reasons,
                       condition)
