"""Shared output helpers of the studies: figures with matplotlib's Agg backend (``save``),
``table.csv`` and ``summary.txt`` in the study's folder (``finish``). Every file is written
atomically (``webline.files.atomic_write``): a study stopped part-way leaves each file whole,
either new or as the previous run left it."""

from __future__ import annotations

import csv
from pathlib import Path
from typing import Any

from webline.files import atomic_write, atomic_write_text
from webline.studies.result import StudyResult


def pyplot() -> Any:
    """matplotlib.pyplot on the non-interactive Agg backend."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def write_figure(fig: Any, path: Path, dpi: float = 100) -> Path:
    """Write ``fig`` as PNG at ``path`` (atomically, at ``dpi``) and close it."""
    try:
        atomic_write(path, lambda tmp: fig.savefig(tmp, dpi=dpi))
    finally:
        pyplot().close(fig)
    return path


def save(fig: Any, path: Path) -> Path:
    """Lay out ``fig`` (tight), write it as PNG at ``path`` and close it."""
    fig.tight_layout()
    return write_figure(fig, path)


def write_table(rows: list[dict[str, object]], path: Path) -> Path:
    """Write ``rows`` as CSV at ``path`` (atomically): one column per key, in the order the
    keys first appear."""
    fields: list[str] = []
    for row in rows:
        fields += [key for key in row if key not in fields]

    def write(tmp: Path) -> None:
        with tmp.open("w", newline="", encoding="utf-8") as f:
            writer = csv.DictWriter(f, fieldnames=fields)
            writer.writeheader()
            writer.writerows(rows)

    return atomic_write(path, write)


def finish(name: str, out_dir: Path, figures: list[Path], rows: list[dict[str, object]],
           summary: str) -> StudyResult:
    """Write ``table.csv`` and ``summary.txt`` under ``out_dir``; return the StudyResult."""
    if rows:
        write_table(rows, out_dir / "table.csv")
    atomic_write_text(out_dir / "summary.txt", summary + "\n")
    return StudyResult(name, tuple(figures), rows, summary)
