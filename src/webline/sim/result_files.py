"""Results to files: NetCDF-4 (compressed, CF attributes) and CSV, each written atomically."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Literal

import numpy as np

from webline.errors import ArgumentError
from webline.files import atomic_write, atomic_write_bytes
from webline.sim.signal_attrs import SIGNAL_UNITS

if TYPE_CHECKING:
    from webline.sim.result_dataset import ResultVariables

#: records per chunk along time in the NetCDF file
TIME_CHUNK = 4096
#: zlib level: with the shuffle filter, level 1 writes 30 % faster than level 4 and the file
#: is 2-3 % larger (20 s of the HSWL, measured)
COMPLEVEL = 1
Precision = Literal["float64", "float32"]


def write_netcdf(variables: ResultVariables, path: str | Path,
                 precision: Precision = "float64") -> Path:
    """Write ``variables`` (``result_dataset.result_variables``) to NetCDF-4 with h5netcdf
    directly (xarray, pandas and their import are not needed to write): zlib (``COMPLEVEL``)
    with shuffle, chunks of ``TIME_CHUNK`` records, float signals as ``precision``; names as
    variable-length UTF-8 strings. ``xarray.open_dataset`` reads it back as
    ``Result.to_xarray()``."""
    if precision not in ("float64", "float32"):
        raise ArgumentError(f"precision: must be 'float64' or 'float32', got {precision!r}")

    import io

    import h5netcdf
    import h5py

    # built in memory and written in one plain write: HDF5 crashes (a segfault) closing a file
    # whose write failed on a full disk, where a plain write raises OSError and
    # ``atomic_write`` leaves nothing behind
    buffer = io.BytesIO()
    with h5netcdf.File(buffer, "w") as f:
        for dim, (_, values, _) in variables.coords.items():
            f.dimensions[dim] = len(values)
        for name, (dims, values, attrs) in variables.coords.items():
            if values.dtype == object:
                var = f.create_variable(name, dims, dtype=h5py.string_dtype(),
                                        data=values.astype(str).astype(object))
            else:
                var = f.create_variable(name, dims, data=values)
            var.attrs.update(attrs)
        n_time = len(variables.coords["time"][1])
        for name, (dims, values, attrs) in variables.data.items():
            dtype = np.float32 if precision == "float32" and values.dtype.kind == "f" \
                else values.dtype
            chunks = (min(n_time, TIME_CHUNK), *values.shape[1:]) if n_time else None
            var = f.create_variable(name, dims, dtype=dtype, data=values.astype(dtype),
                                    chunks=chunks, compression="gzip",
                                    compression_opts=COMPLEVEL, shuffle=True)
            var.attrs.update(attrs)
        f.attrs.update(variables.attrs)
    return atomic_write_bytes(Path(path), buffer.getbuffer())


def write_csv(variables: ResultVariables, path: str | Path) -> Path:
    """One column per named signal (``tension[span1] [N]`` ...) of ``variables``, time
    first."""
    columns, headers = [variables.coords["time"][1]], ["time [s]"]
    for name, (dims, values, _) in variables.data.items():
        if dims == ("time",):
            columns.append(values)
            headers.append(f"{name} [{SIGNAL_UNITS[name]}]")
            continue
        for j, element in enumerate(variables.coords[dims[1]][1]):
            columns.append(values[:, j])
            headers.append(f"{name}[{element}] [{SIGNAL_UNITS[name]}]")
    table = np.column_stack(columns)
    return atomic_write(Path(path), lambda tmp: np.savetxt(
        tmp, table, delimiter=",", header=",".join(headers), comments="", fmt="%.9g"))
