"""Results to files: NetCDF-4 (compressed, CF attributes) and CSV, each written atomically."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Literal

import numpy as np

from webline.errors import ArgumentError
from webline.files import atomic_write
from webline.sim.signal_attrs import SIGNAL_UNITS

if TYPE_CHECKING:
    import xarray as xr

#: records per chunk along time in the NetCDF file
TIME_CHUNK = 4096
#: zlib level: with the shuffle filter, level 1 writes 30 % faster than level 4 and the file
#: is 2-3 % larger (20 s of the HSWL, measured)
COMPLEVEL = 1
Precision = Literal["float64", "float32"]


def write_netcdf(ds: xr.Dataset, path: str | Path, precision: Precision = "float64") -> Path:
    """Write ``ds`` (``Result.to_xarray()``) to NetCDF-4 through h5netcdf: zlib (``COMPLEVEL``)
    with shuffle, chunks of ``TIME_CHUNK`` records; float signals as ``precision``."""
    if precision not in ("float64", "float32"):
        raise ArgumentError(f"precision: must be 'float64' or 'float32', got {precision!r}")
    encoding = {}
    for name, var in ds.data_vars.items():
        dtype = np.float32 if precision == "float32" and var.dtype.kind == "f" else var.dtype
        chunks = (min(ds.sizes["time"], TIME_CHUNK), *var.shape[1:])
        encoding[name] = {"zlib": True, "complevel": COMPLEVEL, "shuffle": True,
                          "chunksizes": chunks, "dtype": dtype}
    return atomic_write(path, lambda tmp: ds.to_netcdf(tmp, engine="h5netcdf",
                                                       encoding=encoding))


def write_csv(ds: xr.Dataset, path: str | Path) -> Path:
    """One column per named signal (``tension[span1] [N]`` ...) of ``ds``, time first."""
    columns, headers = [ds["time"].values], ["time [s]"]
    for name, var in ds.data_vars.items():
        if var.dims == ("time",):
            columns.append(var.values)
            headers.append(f"{name} [{SIGNAL_UNITS[str(name)]}]")
            continue
        for j, element in enumerate(ds[var.dims[1]].values):
            columns.append(var.values[:, j])
            headers.append(f"{name}[{element}] [{SIGNAL_UNITS[str(name)]}]")
    table = np.column_stack(columns)
    return atomic_write(Path(path), lambda tmp: np.savetxt(
        tmp, table, delimiter=",", header=",".join(headers), comments="", fmt="%.9g"))
