"""Figures, tables and the self-contained HTML report of a run, in SI or imperial units.

The names below are imported on first use (PEP 562): a submodule without figures (tables,
the results file, the output folder) can be imported without loading matplotlib.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from webline.report.outputs import ReportFiles
    from webline.report.results_file import write_results
    from webline.report.text.display import Display
    from webline.report.writer import Analysis, analyse, write_report

__all__ = ["Analysis", "Display", "ReportFiles", "analyse", "write_report", "write_results"]

_HOME = {"Display": "webline.report.text.display", "ReportFiles": "webline.report.outputs",
         "write_results": "webline.report.results_file"}


def __getattr__(name: str) -> object:
    if name in __all__:
        return getattr(importlib.import_module(_HOME.get(name, "webline.report.writer")), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
