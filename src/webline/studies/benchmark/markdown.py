"""The benchmark's report (``benchmark.md``): ranking, its rule, every case's scores, each
metric's definition, the cases and the settings, and the stamp (versions, set hash)."""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING, Protocol

from webline.studies.benchmark.contenders import BUILTIN_NOTES
from webline.studies.benchmark.records import RANK_RULE, CaseRun
from webline.studies.benchmark.scores import METRICS, ROBUSTNESS_METRICS, RUN_METRICS
from webline.studies.benchmark.standard_set import Case

if TYPE_CHECKING:
    import pandas as pd


class Outcome(Protocol):
    """What the report reads of a ``result.BenchmarkResult``."""

    @property
    def version(self) -> str: ...

    @property
    def set_hash(self) -> str: ...

    @property
    def webline_version(self) -> str: ...

    @property
    def quick(self) -> bool: ...

    @property
    def cases(self) -> Sequence[Case]: ...

    @property
    def contenders(self) -> Sequence[str]: ...

    @property
    def runs(self) -> Sequence[CaseRun]: ...

    @property
    def seconds(self) -> float: ...

    @property
    def ranking(self) -> pd.DataFrame: ...


def number(value: float) -> str:
    """4 significant digits; "inf", "nan" as such."""
    return f"{value:.4g}" if math.isfinite(value) else str(value)


def _row(cells: list[str]) -> str:
    return "| " + " | ".join(c.replace("|", "\\|") for c in cells) + " |"


def _table(header: list[str], rows: list[list[str]]) -> list[str]:
    return [_row(header), _row(["---"] * len(header)), *(_row(r) for r in rows), ""]


def report(result: Outcome) -> str:
    """The Markdown report of ``result``."""
    out = ["# webline benchmark of controllers", "",
           f"Benchmark set **v{result.version}** (hash `{result.set_hash}`), webline "
           f"{result.webline_version}; {'the --quick subset' if result.quick else 'the full set'}"
           f": {len(result.cases)} cases x {len(result.contenders)} contenders, "
           f"{result.seconds:.1f} s of wall time. Cite numbers with the set version and hash.",
           "", "## Ranking", ""]
    ranking = result.ranking
    out += _table(["place", "contender", "mean rank", "pairs", "cases run", "failed", "n/a"],
                  [[str(r.place), r.contender, number(r.mean_rank), str(r.pairs),
                    str(r.cases), str(r.failed), str(r[6])]
                   for r in ranking.itertuples(index=False)])
    out += [f"Rule: {RANK_RULE}", "", "## Scores per case", ""]
    monte_carlo = {c.name for c in result.cases if c.monte_carlo}
    for case in result.cases:
        metrics = ROBUSTNESS_METRICS if case.name in monte_carlo else RUN_METRICS
        out += [f"### {case.name}", "", f"{case.what}.", ""]
        rows = []
        for r in (r for r in result.runs if r.case == case.name):
            cells = [number(r.scores[m.name]) if m.name in r.scores else "–" for m in metrics]
            rows.append([r.contender, r.status, *cells])
        out += _table(["contender", "status", *(f"{m.name} [{m.unit}]" for m in metrics)],
                      rows)
        notes = [f"- {r.contender} ({r.status}): {r.note}" for r in result.runs
                 if r.case == case.name and r.note]
        out += [*notes, ""] if notes else []
    out += ["## Metrics", "", "Lower is better for every metric; * marks those ranked.", ""]
    out += _table(["metric", "unit", "definition"],
                  [[m.name + (" *" if m.ranked else ""), m.unit, m.definition]
                   for m in METRICS.values()])
    out += ["## Cases", ""]
    out += _table(["case", "line", "scenario", "duration [s]", "onset [s]", "values set",
                   "Monte Carlo"],
                  [[c.name, c.line, c.scenario or "–", number(c.duration), number(c.onset),
                    "; ".join(f"{k} = {v}" for k, v in c.set.items()) or "–",
                    (f"{c.samples} samples, seed {c.seed}: " + "; ".join(
                        f"{k} ~ {v}" for k, v in c.uncertain.items())) if c.monte_carlo
                    else "–"] for c in result.cases])
    out += ["## Contenders and settings", "",
            "Every contender runs each case on the same line: its sample rate, measurement "
            "noise, torque limits and lags, integration step and records as the case's line "
            "and values give them; only the controllers differ. A user's controller commands "
            "every drive.", ""]
    out += [f"- **{name}**: {BUILTIN_NOTES.get(name, 'user controller')}"
            for name in result.contenders]
    return "\n".join(out) + "\n"
