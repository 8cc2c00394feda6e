"""A grid sweep's Dataset with its parameters as dimensions, and back to one row per case.

``webline.sweep(mode="grid")`` runs its cases in one flat list (``case``, the last path
varying fastest, as ``itertools.product``); the user gets them on the grid: one dimension per
swept path, named by the path, with the path's values as its coordinate (numbers in SI, or
labels for tables, strings and booleans), and the case number kept as a coordinate over the
grid (``case``). The reshape is by position, so repeated values in a path's list stay
separate cells. ``as_cases`` undoes it (the report and the CLI's tables read cases in a row).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np

#: the flat dimension of a study's cases
CASE = "case"


def as_grid(ds: Any, paths: Sequence[str], shape: Sequence[int]) -> Any:
    """``ds`` (one row per case, ``len(case) == prod(shape)``) with ``case`` replaced by one
    dimension per path of ``paths`` (sizes ``shape``), each with that path's values as its
    coordinate; ``case`` becomes a coordinate over the grid (the case numbers)."""
    import xarray as xr

    paths, shape = list(paths), [int(n) for n in shape]
    if ds.sizes.get(CASE) != math.prod(shape) or len(paths) != len(shape):
        raise ValueError(f"cannot lay {ds.sizes.get(CASE)} cases on a grid of {shape}")
    variables = {name: _reshaped(var, paths, shape)
                 for name, var in ds.variables.items()
                 if CASE in var.dims and name not in (CASE, *paths)}
    coords: dict[str, Any] = {name: var for name, var in ds.coords.items()
                              if CASE not in var.dims}
    for axis, path in enumerate(paths):
        column = ds[path].values.reshape(shape)
        index = [0] * len(shape)
        index[axis] = slice(None)  # type: ignore[call-overload]
        coords[path] = xr.Variable((path,), column[tuple(index)], ds[path].attrs)
    coords[CASE] = xr.Variable(tuple(paths), ds[CASE].values.reshape(shape),
                               {"long_name": "case number (the order the cases ran in)"})
    data_vars = {name: var for name, var in variables.items() if name not in ds.coords}
    coords |= {name: var for name, var in variables.items() if name in ds.coords}
    plain = {name: var for name, var in ds.data_vars.items() if CASE not in var.dims}
    out = xr.Dataset(data_vars | plain, coords=coords, attrs=dict(ds.attrs))
    return out[[*ds.data_vars]]  # the variables in their original order


def _reshaped(var: Any, paths: list[str], shape: list[int]) -> Any:
    import xarray as xr

    axis = var.dims.index(CASE)
    values = np.moveaxis(var.values, axis, 0)
    dims = (*paths, *(d for d in var.dims if d != CASE))
    return xr.Variable(dims, values.reshape((*shape, *values.shape[1:])), var.attrs)


def as_cases(ds: Any) -> Any:
    """A study's Dataset with one row per case along ``case`` (``as_grid`` undone; a Dataset
    already over ``case`` is returned as it is)."""
    import xarray as xr

    if CASE in ds.dims:
        return ds
    paths = list(ds.attrs.get("parameters", []))
    if not paths or any(p not in ds.dims for p in paths):
        raise ValueError("not a study's Dataset: no case dimension and no parameter grid")
    shape = [ds.sizes[p] for p in paths]
    n = math.prod(shape)
    variables: dict[str, Any] = {}
    for name, var in ds.variables.items():
        if name in paths or name == CASE:
            continue
        if var.dims[:len(paths)] == tuple(paths):
            rest = var.dims[len(paths):]
            variables[name] = xr.Variable((CASE, *rest), var.values.reshape((n, *var.shape[
                len(paths):])), var.attrs)
        elif not set(paths) & set(var.dims):
            variables[name] = var
    coords: dict[str, Any] = {name: var for name, var in variables.items() if name in ds.coords}
    coords[CASE] = (CASE, ds[CASE].values.reshape(n) if CASE in ds.coords else np.arange(n))
    grids = np.meshgrid(*(ds[p].values for p in paths), indexing="ij")
    for path, grid in zip(paths, grids, strict=True):
        coords[path] = xr.Variable((CASE,), grid.reshape(n), ds[path].attrs)
    data_vars = {name: var for name, var in variables.items() if name not in ds.coords}
    return xr.Dataset(data_vars, coords=coords, attrs=dict(ds.attrs))
