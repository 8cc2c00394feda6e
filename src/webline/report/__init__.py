"""Figures, tables and the self-contained HTML report of a run, in SI or imperial units."""

from webline.report.display import Display
from webline.report.writer import Analysis, ReportFiles, analyse, write_report, write_results

__all__ = ["Analysis", "Display", "ReportFiles", "analyse", "write_report", "write_results"]
