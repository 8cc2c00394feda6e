"""The HTML report of a named study (``webline study NAME``): its findings, its runs' verdict,
its table and its figures on one self-contained page, beside the files it already writes
(figures, ``table.csv``, ``summary.txt``)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path

from webline.report.html import Image, Section, Text, render
from webline.report.tables import Table, make_table
from webline.report.verdict_text import STATUS_CLASS
from webline.verdict import Verdict

#: rows of the study's table the page shows, at most (table.csv holds every row)
ROWS_SHOWN = 200


def _cell(value: object) -> str:
    return f"{value:.6g}" if isinstance(value, float) else str(value)


def study_table(rows: Sequence[Mapping[str, object]]) -> Table | None:
    """The study's rows as a table (columns in the order the keys first appear), the first
    ``ROWS_SHOWN``; None when there are none."""
    if not rows:
        return None
    columns: list[str] = []
    for row in rows:
        columns += [key for key in row if key not in columns]
    shown = rows[:ROWS_SHOWN]
    title = ("Table (also in table.csv)" if len(rows) == len(shown) else
             f"The first {len(shown)} of {len(rows)} rows (every row is in table.csv)")
    return make_table("study-table", title, columns,
                      [[_cell(row.get(c, "")) for c in columns] for row in shown])


def study_html(name: str, description: str, summary: str,
               rows: Sequence[Mapping[str, object]], figures: Sequence[Path],
               verdict: Verdict | None, version: str) -> str:
    """The whole page of study ``name``: ``summary`` (its findings, as summary.txt) under
    ``verdict``'s headline where the study keeps its runs' verdicts, its table, and every PNG
    of ``figures`` inlined, captioned by its file name."""
    images = [Image(p.stem, p.name, p.read_bytes()) for p in figures
              if p.suffix == ".png" and p.exists()]
    table = study_table(rows)
    sections = [Section("Findings", [Text(summary, pre=True)])]
    if table is not None:
        sections.append(Section("Table", [table]))
    sections.append(Section("Figures", images or [Text("This study draws no figure.")]))
    status = "ok" if verdict is None else verdict.status
    return render(f"webline study: {name}", description,
                  "" if verdict is None else "The verdict of the study's runs combined.",
                  STATUS_CLASS.get(status, "ok"), sections, f"webline {version}",
                  headline=(verdict.headline if verdict is not None else
                            f"{len(images)} figures, {len(rows)} table rows"))
