"""Results files as CF tools read them (issue 23, item 6): time recognised as time, a
``long_name`` on every variable (coordinates too) and units on every number that has one; the
README's stated file size is what is written."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import xarray as xr

import webline

ROOT = Path(__file__).resolve().parents[2]


def test_every_variable_has_long_name_and_units(tmp_path) -> None:
    """Every variable of results.nc, coordinates included, has a ``long_name``; every number
    has ``units`` (flags have ``flag_meanings`` instead, names are text); time is
    ``standard_name = "time"``, ``axis = "T"`` in seconds."""
    path = webline.simulate("converter", "0.1 s").to_netcdf(tmp_path / "results.nc")
    with xr.open_dataset(path, decode_times=False) as ds:
        for name, var in ds.variables.items():
            assert var.attrs.get("long_name"), name
            if var.dtype.kind in "fiu":
                assert "units" in var.attrs or "flag_meanings" in var.attrs, name
        assert ds.time.attrs == {"units": "s", "long_name": "simulated time",
                                 "standard_name": "time", "axis": "T"}
        assert ds.attrs["Conventions"].startswith("CF-")


def test_readme_states_the_size_written(tmp_path) -> None:
    """The README's sizes of 20 s of the HSWL (float64 and float32) are those written, within
    10 % (zlib's output moves by a few per cent between library versions)."""
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    found = re.search(r"`webline run hswl -d 20`: `results.nc` ([\d.]+) MB \(([\d.]+) MB with "
                      r"`--precision float32`\)", " ".join(readme.split()))
    assert found, "the README's size sentence moved"
    result = webline.simulate("hswl", "20 s")
    for stated, precision in zip(map(float, found.groups()), ("float64", "float32"),
                                 strict=True):
        size = result.to_netcdf(tmp_path / f"{precision}.nc", precision).stat().st_size
        np.testing.assert_allclose(size / 1e6, stated, rtol=0.10, err_msg=precision)
