"""A run's signals as one file, SI throughout: NetCDF-4 or CSV (no figures: this module does
not import matplotlib, so ``webline run`` writes it while the report is drawn elsewhere)."""

from __future__ import annotations

from pathlib import Path
from typing import Literal

from webline.report.outputs import OutputFolder
from webline.sim.results.result import Precision, Result

Format = Literal["netcdf", "csv"]


def results_name(fmt: Format) -> str:
    """File name of the results in format ``fmt``."""
    return "results.csv" if fmt == "csv" else "results.nc"


def write_results(result: Result, out_dir: Path, fmt: Format = "netcdf", *,
                  precision: Precision = "float64", folder: OutputFolder | None = None) -> Path:
    """Write the run's signals (SI, units as attributes/headers) as ``results.nc`` (NetCDF-4,
    compressed, floats as ``precision``) or ``results.csv`` in ``out_dir``, atomically; with
    ``folder`` (the ``OutputFolder`` of ``out_dir``) the file joins its manifest. Returns the
    path."""
    name = results_name(fmt)
    path = folder.claim(name) if folder else out_dir / name
    if fmt == "csv":
        return result.to_csv(path)
    return result.to_netcdf(path, precision=precision)
