"""An xarray Dataset of signals over time (a branched line's run, ``sim.branches.result``) to
the chain's results files, by the chain's rules (``result_files``): NetCDF-4 compressed and
chunked along time, float signals as the precision asked (time stays float64), or CSV with
one column per signal and element and its unit in the header; each written atomically."""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal

import numpy as np

from webline.errors import ArgumentError
from webline.files import atomic_write
from webline.sim.results.result_files import COMPLEVEL, TIME_CHUNK, Precision

if TYPE_CHECKING:
    import xarray as xr

Format = Literal["netcdf", "csv"]


def write_dataset(ds: xr.Dataset, path: str | Path, fmt: Format = "netcdf",
                  precision: Precision = "float64",
                  groups: Mapping[str, xr.Dataset] | None = None) -> Path:
    """Write ``ds`` (dimension ``time`` first in every signal, ``units`` in each signal's
    attributes) to ``path`` as ``fmt``: 'netcdf' (float signals as ``precision``) or 'csv'
    (9 significant digits, whatever ``precision``). ``groups``: more datasets, each in its
    NetCDF group by name (``a/b`` nests; not in a CSV). Returns the path."""
    if precision not in ("float64", "float32"):
        raise ArgumentError(f"precision: must be 'float64' or 'float32', got {precision!r}")
    if fmt == "csv":
        return write_dataset_csv(ds, path)
    if fmt != "netcdf":
        raise ArgumentError(f"format: must be 'netcdf' or 'csv', got {fmt!r}")
    n_time = ds.sizes.get("time", 0)
    encoding: dict[str, dict[str, object]] = {}
    for name, var in ds.data_vars.items():
        rule: dict[str, object] = {}
        if precision == "float32" and var.dtype.kind == "f":
            rule["dtype"] = "float32"
        if var.size:  # (HDF5 chunks a zero-length signal not at all)
            rule.update(compression="gzip", compression_opts=COMPLEVEL, shuffle=True,
                        chunksizes=(min(n_time, TIME_CHUNK), *var.shape[1:]))
        encoding[str(name)] = rule

    def write(tmp: Path) -> None:
        ds.to_netcdf(tmp, engine="h5netcdf", encoding=encoding)
        for name, group in (groups or {}).items():
            group.to_netcdf(tmp, mode="a", group=name, engine="h5netcdf")

    return atomic_write(Path(path), write)


def dataset_columns(ds: xr.Dataset) -> list[tuple[str, str, np.ndarray]]:
    """Each signal of ``ds`` as columns over time: (``name`` or ``name[element]``, its unit,
    its values), in the order of the signals and their elements (as
    ``result_files.signal_columns``)."""
    columns = []
    for name, var in ds.data_vars.items():
        unit = str(var.attrs.get("units", ""))
        if var.dims == ("time",):
            columns.append((str(name), unit, var.values))
            continue
        values = var.values.reshape(var.shape[0], -1)
        elements = [str(e) for e in ds[var.dims[1]].values] if var.ndim == 2 else \
            [str(j) for j in range(values.shape[1])]
        columns += [(f"{name}[{element}]", unit, values[:, j])
                    for j, element in enumerate(elements)]
    return columns


def dataset_frame(ds: xr.Dataset) -> Any:
    """``dataset_columns(ds)`` as a ``pandas.DataFrame`` indexed by ``time`` [s], the unit of
    each column in ``.attrs["units"]`` (as ``result_files.signal_frame``)."""
    import pandas as pd

    columns = dataset_columns(ds)
    frame = pd.DataFrame({name: values for name, _, values in columns},
                         index=pd.Index(ds["time"].values, name="time"))
    frame.attrs["units"] = {name: unit for name, unit, _ in columns}
    return frame


def write_dataset_csv(ds: xr.Dataset, path: str | Path) -> Path:
    """One column per signal and element of ``ds`` (``tension[film_zone] [N]`` ...), time
    [s] first, 9 significant digits."""
    columns = dataset_columns(ds)
    headers = ["time [s]", *(f"{name} [{unit}]" for name, unit, _ in columns)]
    table = np.column_stack([ds["time"].values, *(c for _, _, c in columns)])
    return atomic_write(Path(path), lambda tmp: np.savetxt(
        tmp, table, delimiter=",", header=",".join(headers), comments="", fmt="%.9g"))
