"""Reading a measurement file (CSV, Parquet, NetCDF) into raw named columns with the units
their headers give; no resampling, no checks against a line (``measurements`` does those)."""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from webline.errors import WeblineError

#: "name [unit]": a header with its unit in brackets after a space (webline's own CSV);
#: "tension[span]" (no space) is a name with an element, not a unit
_HEADER = re.compile(r"^(?P<name>.*\S)\s+\[(?P<unit>[^\[\]]*)\]$")


class MeasurementError(WeblineError):
    """A measurement file cannot be used: the message is one line naming the file, the column
    and the problem (exit status 2 in the CLI)."""

    exit_code = 2

    def __init__(self, file: str, column: str, problem: str) -> None:
        self.file, self.column, self.problem = file, column, problem
        super().__init__(f"{file}: {column}: {problem}" if column else f"{file}: {problem}")


@dataclass(frozen=True)
class RawColumn:
    """One column as read: the header's name, its unit as written (None: no unit given) and
    its values (NaN where the file has none)."""

    header: str
    name: str
    unit: str | None
    values: np.ndarray


def split_header(header: str) -> tuple[str, str | None]:
    """(name, unit or None) of a column header ``"tension[process_span] [N]"``."""
    match = _HEADER.match(header.strip())
    if match is None:
        return header.strip(), None
    return match["name"], match["unit"].strip()


def read_columns(path: Path) -> list[RawColumn]:
    """Every column of the file at ``path``, by its suffix: .csv/.txt, .parquet/.pq,
    .nc/.netcdf. Raises ``MeasurementError`` for a missing, unreadable or empty file."""
    label = str(path)
    if not path.is_file():
        raise MeasurementError(label, "", "no such file")
    suffix = path.suffix.lower()
    if suffix in (".nc", ".netcdf", ".nc4"):
        columns = _netcdf(path)
    elif suffix in (".parquet", ".pq"):
        columns = _frame_columns(_parquet(path))
    elif suffix in (".csv", ".txt", ".tsv"):
        columns = _frame_columns(_csv(path))
    else:
        raise MeasurementError(label, "", f"unknown file type {path.suffix!r}: expected .csv, "
                               ".parquet or .nc")
    if not columns or all(len(c.values) == 0 for c in columns):
        raise MeasurementError(label, "", "the file holds no data (empty)")
    return columns


def _csv(path: Path) -> object:
    import pandas as pd

    try:
        return pd.read_csv(path, sep=None if path.suffix.lower() == ".txt" else
                           ("\t" if path.suffix.lower() == ".tsv" else ","),
                           engine="python" if path.suffix.lower() == ".txt" else "c")
    except pd.errors.EmptyDataError:
        raise MeasurementError(str(path), "", "the file holds no data (empty)") from None
    except (pd.errors.ParserError, UnicodeDecodeError, ValueError) as exc:
        raise MeasurementError(str(path), "", f"not a readable CSV table: "
                               f"{' '.join(str(exc).split())[:120]}") from None


def _parquet(path: Path) -> object:
    from webline.extras import require

    require("pyarrow")  # pandas reads Parquet through it: an optional extra
    import pandas as pd

    try:
        return pd.read_parquet(path)
    except Exception as exc:  # pyarrow raises its own types for a damaged file
        raise MeasurementError(str(path), "", f"not a readable Parquet file: "
                               f"{' '.join(str(exc).split())[:120]}") from None


def _frame_columns(frame: object) -> list[RawColumn]:
    import pandas as pd

    assert isinstance(frame, pd.DataFrame)
    out = []
    for header in frame.columns:
        name, unit = split_header(str(header))
        values = pd.to_numeric(frame[header], errors="coerce").to_numpy(dtype=float)
        out.append(RawColumn(str(header), name, unit, values))
    return out


def _netcdf(path: Path) -> list[RawColumn]:
    """Variables over time (a run's own results.nc: ``tension`` over (time, span) gives
    ``tension[SPAN]`` per span), units from each variable's ``units`` attribute."""
    import xarray as xr

    try:
        ds = xr.open_dataset(path, engine="h5netcdf", decode_times=False,
                             decode_timedelta=False)
    except Exception as exc:  # h5py/xarray raise many types for a damaged file
        raise MeasurementError(str(path), "", f"not a readable NetCDF file: "
                               f"{' '.join(str(exc).split())[:120]}") from None
    with ds:
        if "time" not in ds.variables:
            raise MeasurementError(str(path), "time", "no time variable in the file")
        time = ds["time"]
        out = [RawColumn("time", "time", time.attrs.get("units"),
                         np.asarray(time.values, dtype=float))]
        for name, var in ds.data_vars.items():
            if not var.dims or var.dims[0] != "time" or len(var.dims) > 2:
                continue
            unit = var.attrs.get("units")
            if len(var.dims) == 1:
                out.append(RawColumn(str(name), str(name), unit,
                                     np.asarray(var.values, dtype=float)))
                continue
            dim = var.dims[1]
            for j, element in enumerate(np.asarray(ds[dim].values).astype(str)):
                label = f"{name}[{element}]"
                out.append(RawColumn(label, label, unit,
                                     np.asarray(var.values[:, j], dtype=float)))
    return out
