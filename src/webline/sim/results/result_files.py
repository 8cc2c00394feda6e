"""Results to files: NetCDF-4 (compressed, CF attributes) and CSV, each written atomically."""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Literal

import numpy as np

from webline.errors import ArgumentError
from webline.files import atomic_write, atomic_write_bytes
from webline.sim.results.signal_attrs import SIGNAL_UNITS

if TYPE_CHECKING:
    from webline.sim.results.result_dataset import ResultVariables

#: records per chunk along time in the NetCDF file
TIME_CHUNK = 4096
#: zlib level: with the shuffle filter, level 1 writes 30 % faster than level 4 and the file
#: is 2-3 % larger (20 s of the HSWL, measured)
COMPLEVEL = 1
Precision = Literal["float64", "float32"]


#: a NetCDF group's variables: name -> (dimensions, values, attributes)
GroupVariables = Mapping[str, tuple[tuple[str, ...], np.ndarray, Mapping[str, object]]]


def write_netcdf(variables: ResultVariables, path: str | Path,
                 precision: Precision = "float64",
                 groups: Mapping[str, GroupVariables] | None = None) -> Path:
    """Write ``variables`` (``result_dataset.result_variables``) to NetCDF-4 with h5netcdf
    directly (xarray, pandas and their import are not needed to write): zlib (``COMPLEVEL``)
    with shuffle, chunks of ``TIME_CHUNK`` records, float signals as ``precision``; names as
    variable-length UTF-8 strings. ``xarray.open_dataset`` reads it back as
    ``Result.to_xarray()``. ``groups``: more variables in named groups, each with its own
    dimensions (the wound roll per layer: ``xarray.open_dataset(path, group="wound_roll")``)."""
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
        for group_name, group_vars in (groups or {}).items():
            g = f.create_group(group_name)
            for name, (g_dims, g_values, g_attrs) in group_vars.items():
                for dim, size in zip(g_dims, g_values.shape, strict=True):
                    if dim not in g.dimensions:
                        g.dimensions[dim] = size
                var = g.create_variable(name, g_dims, data=g_values)
                var.attrs.update(dict(g_attrs))
    return atomic_write_bytes(Path(path), buffer.getbuffer())


def signal_columns(variables: ResultVariables) -> list[tuple[str, str, np.ndarray]]:
    """Each signal of ``variables`` as columns over time: (``name`` or ``name[element]``, its
    unit, its values), in the order of the variables and their elements; the table of the CSV
    and of ``Result.to_dataframe``."""
    columns = []
    for name, (dims, values, _) in variables.data.items():
        if dims == ("time",):
            columns.append((name, SIGNAL_UNITS[name], values))
            continue
        for j, element in enumerate(variables.coords[dims[1]][1]):
            columns.append((f"{name}[{element}]", SIGNAL_UNITS[name], values[:, j]))
    return columns


def signal_frame(variables: ResultVariables):
    """``signal_columns(variables)`` as a ``pandas.DataFrame`` indexed by ``time`` [s], the
    unit of each column in ``.attrs["units"]``."""
    import pandas as pd

    columns = signal_columns(variables)
    frame = pd.DataFrame({name: values for name, _, values in columns},
                         index=pd.Index(variables.coords["time"][1], name="time"))
    frame.attrs["units"] = {name: unit for name, unit, _ in columns}
    return frame


def write_csv(variables: ResultVariables, path: str | Path) -> Path:
    """One column per named signal (``tension[span1] [N]`` ...) of ``variables``, time
    first."""
    columns = signal_columns(variables)
    headers = ["time [s]", *(f"{name} [{unit}]" for name, unit, _ in columns)]
    table = np.column_stack([variables.coords["time"][1], *(c for _, _, c in columns)])
    return atomic_write(Path(path), lambda tmp: np.savetxt(
        tmp, table, delimiter=",", header=",".join(headers), comments="", fmt="%.9g"))
