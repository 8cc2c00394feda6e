"""The files of one ``webline run``: everything written into its output folder, the manifest
finished (see ``webline.report.outputs``)."""

from __future__ import annotations

from pathlib import Path

from webline.errors import WeblineError
from webline.files import write_failure
from webline.report.early import Reporter, ReportJob
from webline.report.outputs import OutputFolder, ReportFiles
from webline.report.results_file import Format, results_name, write_results
from webline.report.text.display import System
from webline.sim.results.result import Precision, Result


def write_run(result: Result, folder: OutputFolder, fmt: Format = "netcdf",
              precision: Precision = "float64", units: System = "si",
              scenario: str | None = None, svg: bool = False,
              reporter: Reporter | None = None) -> tuple[ReportFiles, Path]:
    """Write results, figures (SVG too with ``svg``), summary and report into ``folder``
    (each file atomically and in its manifest), then finish the manifest: files of the
    previous run not rewritten are removed. Returns the report's files and the results file.
    A ``reporter`` (``report.early``, its caller closes it) writes the report meanwhile; if
    it fails, it is written here."""
    try:
        results_file = folder.claim(results_name(fmt))  # before the reporter copies the folder
        result.verdict  # noqa: B018  judged once: the copy receives it cached with the result
        handed = reporter is not None and reporter.submit(ReportJob(
            result, folder, units, scenario, results_file, svg))
        write_results(result, folder.path, fmt, precision=precision, folder=folder)
        files = reporter.collect(folder) if handed and reporter is not None else None
        if files is None:
            from webline.report.writer import write_report

            files = write_report(result, folder.path, units=units, scenario=scenario,
                                 results_file=results_file, folder=folder, svg=svg)
        folder.finish()
    except OSError as exc:  # a full disk: one line naming the file, the files written whole
        raise WeblineError(f"cannot write the run's files: {write_failure(exc)}") from None
    return files, results_file
