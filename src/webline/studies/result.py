"""What a named study returns."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from webline.verdict import Verdict


@dataclass(frozen=True)
class StudyResult:
    """A study's output: the figure files it wrote, one table (rows of plain values, units in
    the column names) and a short text of its findings; ``verdict``: the runs' verdicts
    combined, where the study keeps them (None where it does not)."""

    name: str
    figures: tuple[Path, ...]
    table: list[dict[str, object]] = field(default_factory=list)
    summary: str = ""
    verdict: Verdict | None = None
