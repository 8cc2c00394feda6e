"""The global stage of a fit: a Latin hypercube (``scipy.stats.qmc``) of ``SCREEN`` points per
start screened by their cost (one simulation each, run as one batch), then local fits from
the line's own values and the best screened points, so that a fit started in the wrong
valley of its cost (a torque lag that ends on its lower bound while the truth is 2.5 times
the line file's) is not reported as the answer; and how many starts reached the best cost,
which says how sure the global stage is that it found the lowest valley."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

#: screened points of the Latin hypercube per local start
SCREEN = 4
#: a start "reached the best cost" when its cost is within this share of the best, or within
#: ``chi2_slack`` of it (below)
RELATIVE = 0.01
#: likelihood-ratio quantile: costs (½Σr², r in noise levels) that differ by less than
#: ½ χ²₀.₉₅(n) are statistically the same valley for n parameters
LEVEL = 0.95


@dataclass(frozen=True)
class GlobalStage:
    """Outcome of the global stage: the starts (scaled parameters, the line's values first),
    the cost each local fit reached (½Σr² of the coarse stage's residuals), the best point,
    how many starts reached the best cost and the simulations it took."""

    starts: np.ndarray
    costs: np.ndarray
    best: np.ndarray
    reached: int
    simulations: int

    @property
    def count(self) -> int:
        """Number of starts (the line's values included)."""
        return len(self.costs)

    def summary(self) -> str:
        """One line: '3 of 9 starts reached the best cost'."""
        return f"{self.reached} of {self.count} starts reached the best cost"


def latin_starts(
    x0: np.ndarray, count: int, cost: Callable[[np.ndarray], np.ndarray], seed: int = 0
) -> np.ndarray:
    """``count`` starts [scaled to the bounds, 0..1] for parameters ``x0``: ``x0`` (the line's
    values) first, then the ``count - 1`` lowest by ``cost`` (rows -> costs) of
    ``SCREEN * (count - 1)`` points of a Latin hypercube (each parameter's range cut into as
    many strata, one point in each, so every part of every range is tried)."""
    from scipy.stats import qmc

    x0 = np.asarray(x0, dtype=float)
    if count <= 1:
        return x0[None, :]
    sample = qmc.LatinHypercube(d=len(x0), seed=seed).random(SCREEN * (count - 1))
    costs = np.asarray(cost(sample), dtype=float)
    order = np.argsort(np.where(np.isfinite(costs), costs, np.inf), kind="stable")
    return np.vstack([x0, sample[order[: count - 1]]])


def chi2_slack(n: int) -> float:
    """½ χ²_LEVEL(n): cost differences below this are within the noise for n parameters."""
    from scipy.stats import chi2

    return 0.5 * float(chi2.ppf(LEVEL, max(1, n)))


def reached_best(costs: np.ndarray, n: int) -> int:
    """How many of ``costs`` lie within ``max(RELATIVE * best, chi2_slack(n))`` of the best."""
    finite = costs[np.isfinite(costs)]
    if not len(finite):
        return 0
    best = float(finite.min())
    return int(np.sum(finite <= best + max(RELATIVE * best, chi2_slack(n))))


def global_stage(
    starts: np.ndarray,
    local: Callable[[np.ndarray], tuple[np.ndarray, float]],
    simulations: Callable[[], int],
) -> GlobalStage:
    """Run ``local(start) -> (end point, cost)`` from every row of ``starts`` (one after
    another: each local fit already runs its Jacobian's cases as one batch) and keep the
    best; ``simulations()`` counts the simulations run so far."""
    before = simulations()
    ends, costs = [], []
    for start in starts:
        end, cost = local(start)
        ends.append(end)
        costs.append(cost if np.isfinite(cost) else np.inf)
    costs_a = np.array(costs)
    best = ends[int(np.argmin(costs_a))]
    return GlobalStage(
        starts,
        costs_a,
        np.asarray(best),
        reached_best(costs_a, starts.shape[1]),
        simulations() - before,
    )
