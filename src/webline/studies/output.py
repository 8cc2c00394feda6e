"""Shared output helpers of the studies: figures with matplotlib's Agg backend (``save``),
``table.csv`` and ``summary.txt`` in the study's folder (``finish``)."""

from __future__ import annotations

import csv
from pathlib import Path
from typing import Any

from webline.studies.result import StudyResult


def pyplot() -> Any:
    """matplotlib.pyplot on the non-interactive Agg backend."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def save(fig: Any, path: Path) -> Path:
    """Write ``fig`` as PNG at ``path`` and close it."""
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    pyplot().close(fig)
    return path


def finish(name: str, out_dir: Path, figures: list[Path], rows: list[dict[str, object]],
           summary: str) -> StudyResult:
    """Write ``table.csv`` and ``summary.txt`` under ``out_dir``; return the StudyResult."""
    if rows:
        fields: list[str] = []
        for row in rows:
            fields += [key for key in row if key not in fields]
        with (out_dir / "table.csv").open("w", newline="", encoding="utf-8") as f:
            writer = csv.DictWriter(f, fieldnames=fields)
            writer.writeheader()
            writer.writerows(rows)
    (out_dir / "summary.txt").write_text(summary + "\n", encoding="utf-8")
    return StudyResult(name, tuple(figures), rows, summary)
