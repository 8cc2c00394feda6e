"""Shared output helpers of the studies: figures with matplotlib's Agg backend (``save``),
``table.csv`` and ``summary.txt`` in the study's folder (``finish``). Every file is written
atomically (``webline.files.atomic_write``): a study stopped part-way leaves each file whole,
either new or as the previous run left it.

Within ``recording(folder)`` (``webline study`` runs a study so) each file joins the output
folder's manifest (``webline.report.outputs``) before it is written, as a run's files do: a
rerun removes the files of the previous run it did not write again, and a folder webline did
not write is refused."""

from __future__ import annotations

import csv
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from contextvars import ContextVar
from pathlib import Path
from typing import Any

from webline.files import atomic_write, atomic_write_text
from webline.report.outputs import OutputFolder
from webline.studies.result import StudyResult

_FOLDER: ContextVar[OutputFolder | None] = ContextVar("study_folder", default=None)


@contextmanager
def recording(folder: OutputFolder) -> Iterator[OutputFolder]:
    """Within the block every file the studies write under ``folder`` joins its manifest;
    at a normal exit the manifest is finished (the previous run's files not written again
    are removed). An interrupted study leaves its manifest listing what it wrote."""
    token = _FOLDER.set(folder)
    try:
        yield folder
        folder.finish()
    finally:
        _FOLDER.reset(token)


def _claimed(path: Path) -> Path:
    """``path``, claimed in the recording folder's manifest if it lies in that folder."""
    folder = _FOLDER.get()
    if folder is not None:
        try:
            relative = path.resolve().relative_to(folder.path.resolve())
        except ValueError:
            return path  # written elsewhere (a caller's own path): not this folder's
        folder.claim(relative.as_posix())
    return path


def _write(path: Path, write: Callable[[Path], object]) -> Path:
    return atomic_write(_claimed(path), write)


def write_text(path: Path, text: str) -> Path:
    """Write ``text`` (UTF-8) at ``path`` atomically, in the manifest while recording."""
    return atomic_write_text(_claimed(path), text)


def pyplot() -> Any:
    """matplotlib.pyplot on the non-interactive Agg backend."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def write_figure(fig: Any, path: Path, dpi: float = 100) -> Path:
    """Write ``fig`` as PNG at ``path`` (atomically, at ``dpi``) and close it."""
    try:
        _write(path, lambda tmp: fig.savefig(tmp, dpi=dpi))
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

    return _write(path, write)


def finish(name: str, out_dir: Path, figures: list[Path], rows: list[dict[str, object]],
           summary: str) -> StudyResult:
    """Write ``table.csv`` and ``summary.txt`` under ``out_dir``; return the StudyResult."""
    if rows:
        write_table(rows, out_dir / "table.csv")
    write_text(out_dir / "summary.txt", summary + "\n")
    return StudyResult(name, tuple(figures), rows, summary)
