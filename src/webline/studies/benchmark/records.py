"""One contender's outcome on one case (``CaseRun``) and the ranking rule over them."""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

from webline.studies.benchmark.scores import ROBUSTNESS_METRICS, RUN_METRICS
from webline.studies.benchmark.standard_set import Case

if TYPE_CHECKING:
    import pandas as pd

RANK_RULE = (
    "In every case the contenders that ran it are ranked on each ranked metric (lower is "
    "better; values equal to 9 significant digits share the mean of their places, as "
    "round-off must not order two controllers that compute the same; a contender whose run "
    "failed, or whose value is not a number, takes the last places). A contender's score is "
    "the mean of its ranks over every (case, metric) pair it was ranked in; cases where it "
    "is n/a are left out (the column 'pairs' says how many pairs each score averages). The "
    "lowest mean rank comes first.")


@dataclass(frozen=True)
class CaseRun:
    """One contender on one case: ``status`` "ok", "warning" or "unstable" (the run's
    verdict), "failed" or "n/a"; ``note`` the verdict's line or the reason; ``scores``
    metric -> value (empty when failed or n/a); ``seconds`` of wall time."""

    case: str
    contender: str
    status: str
    note: str
    scores: dict[str, float]
    seconds: float

    @property
    def scored(self) -> bool:
        """Whether it ran to the end and has scores (its verdict may still warn)."""
        return self.status not in ("failed", "n/a")


def case_ranks(runs: Sequence[CaseRun], cases: Sequence[Case]) -> pd.DataFrame:
    """The rank of every contender in every (case, ranked metric) pair (``RANK_RULE``):
    columns ``case``, ``metric``, ``contender``, ``rank``."""
    import pandas as pd

    rows = []
    monte_carlo = {c.name for c in cases if c.monte_carlo}
    for case in dict.fromkeys(r.case for r in runs):
        ran = [r for r in runs if r.case == case and r.status != "n/a"]
        metrics = ROBUSTNESS_METRICS if case in monte_carlo else RUN_METRICS
        for metric in (m.name for m in metrics if m.ranked):
            values = pd.Series([_rounded(r.scores.get(metric, math.nan)) if r.scored
                                else math.nan for r in ran], dtype=float)
            ranks = values.rank(method="average", na_option="bottom")
            rows += [(case, metric, r.contender, float(k))
                     for r, k in zip(ran, ranks, strict=True)]
    return pd.DataFrame(rows, columns=["case", "metric", "contender", "rank"])


def _rounded(value: float) -> float:
    """``value`` to 9 significant digits (the ranking's ties); inf and NaN as they are."""
    return float(f"{value:.9g}") if math.isfinite(value) else value


def ranking_table(runs: Sequence[CaseRun], cases: Sequence[Case],
                  contenders: Sequence[str]) -> pd.DataFrame:
    """Per contender, best first (``RANK_RULE``): ``place``, ``contender``, ``mean_rank``,
    ``pairs`` (ranks averaged), ``cases`` run, ``failed`` and ``n/a`` cases."""
    import pandas as pd

    ranks = case_ranks(runs, cases)
    rows = []
    for name in contenders:
        mine = ranks[ranks.contender == name]["rank"]
        own = [r for r in runs if r.contender == name]
        rows.append((name, float(mine.mean()) if len(mine) else math.nan, len(mine),
                     sum(r.status != "n/a" for r in own),
                     sum(r.status == "failed" for r in own),
                     sum(r.status == "n/a" for r in own)))
    table = pd.DataFrame(rows, columns=["contender", "mean_rank", "pairs", "cases", "failed",
                                        "n/a"])
    table = table.sort_values("mean_rank", kind="stable", na_position="last")
    table.insert(0, "place", table["mean_rank"].rank(method="min").astype("Int64"))
    return table.reset_index(drop=True)
