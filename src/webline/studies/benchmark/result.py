"""A benchmark's result: the tidy table, the ranking by its stated rule, the files."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from webline.studies.benchmark.markdown import report
from webline.studies.benchmark.records import CaseRun, case_ranks, ranking_table
from webline.studies.benchmark.scores import METRICS
from webline.studies.benchmark.standard_set import Case

if TYPE_CHECKING:
    import pandas as pd

FILES = ("benchmark.csv", "runs.csv", "benchmark.md")


@dataclass(frozen=True)
class BenchmarkResult:
    """What ``webline.benchmark`` returns: the set's ``version`` and ``set_hash``, webline's
    version, whether the ``quick`` subset ran, its ``cases``, the ``contenders`` (names, in
    order), one ``CaseRun`` per case and contender and the wall time [s]."""

    version: str
    set_hash: str
    webline_version: str
    quick: bool
    cases: tuple[Case, ...]
    contenders: tuple[str, ...]
    runs: tuple[CaseRun, ...]
    seconds: float

    @property
    def stamp(self) -> dict[str, str]:
        """The columns every output carries: benchmark version, set hash, webline version."""
        return {"benchmark_version": self.version, "set_hash": self.set_hash,
                "webline_version": self.webline_version}

    @property
    def table(self) -> pd.DataFrame:
        """Tidy scores: one row per case, contender and metric (``case``, ``contender``,
        ``metric``, ``value``, ``unit`` and the stamp columns); failed and n/a runs have no
        rows here (``runs_table`` says why)."""
        import pandas as pd

        rows = [(r.case, r.contender, name, value, METRICS[name].unit)
                for r in self.runs for name, value in r.scores.items()]
        table = pd.DataFrame(rows, columns=["case", "contender", "metric", "value", "unit"])
        return table.assign(**self.stamp)

    @property
    def runs_table(self) -> pd.DataFrame:
        """One row per case and contender: ``status`` (ok, warning, unstable, failed, n/a),
        ``note`` (the verdict's line or why n/a), ``seconds`` and the stamp columns."""
        import pandas as pd

        table = pd.DataFrame([(r.case, r.contender, r.status, r.note, r.seconds)
                              for r in self.runs],
                             columns=["case", "contender", "status", "note", "seconds"])
        return table.assign(**self.stamp)

    def ranks(self) -> pd.DataFrame:
        """Every contender's rank in every (case, ranked metric) pair
        (``records.case_ranks``)."""
        return case_ranks(self.runs, self.cases)

    @property
    def ranking(self) -> pd.DataFrame:
        """Per contender, best first (``records.ranking_table``, ``records.RANK_RULE``)."""
        return ranking_table(self.runs, self.cases, self.contenders)

    def to_markdown(self) -> str:
        """The report: ranking, rule, per-case scores, metric definitions, cases, settings."""
        return report(self)

    def write(self, folder: Path,
              claim: Callable[[str], Path] | None = None) -> list[Path]:
        """``benchmark.csv`` (``table``), ``runs.csv`` (``runs_table``) and ``benchmark.md``
        (``to_markdown``) in ``folder``, each written whole (``webline.files``); ``claim``
        (an output folder's) gives each file's path by its name."""
        from webline.files import atomic_write_text

        paths = [claim(name) if claim else Path(folder) / name for name in FILES]
        atomic_write_text(paths[0], self.table.to_csv(index=False))
        atomic_write_text(paths[1], self.runs_table.to_csv(index=False))
        atomic_write_text(paths[2], self.to_markdown())
        return paths
