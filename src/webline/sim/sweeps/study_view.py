"""``StudyDataset``: what ``webline.sweep`` and ``webline.monte_carlo`` return, an
``xarray.Dataset`` in every respect but its plain repr, which says what the study is in a few
lines (xarray's own lists every variable and attribute: some thirty lines). Notebooks keep
xarray's collapsible HTML view."""

from __future__ import annotations

from collections import Counter
from typing import Any

import xarray as xr

from webline.verdict import RANK


class StudyDataset(xr.Dataset):
    """A study's Dataset (``webline.sim.sweeps.sweep``): every xarray method works as on any
    Dataset; ``repr`` is ``study_text`` and ``full_repr()`` xarray's own."""

    __slots__ = ()

    def __repr__(self) -> str:
        try:
            return study_text(self)
        except (KeyError, TypeError, ValueError, AttributeError):  # a slice without a study's
            return xr.Dataset.__repr__(self)  # attributes: xarray's own view

    def full_repr(self) -> str:
        """xarray's repr: every dimension, coordinate, variable and attribute."""
        return xr.Dataset.__repr__(self)


def as_study(ds: xr.Dataset) -> StudyDataset:
    """``ds``'s variables, coordinates and attributes as a ``StudyDataset`` (no copy of the
    data)."""
    return StudyDataset({k: v.variable for k, v in ds.data_vars.items()},
                        coords={k: v.variable for k, v in ds.coords.items()},
                        attrs=dict(ds.attrs))


def study_text(ds: Any) -> str:
    """A few lines: the study (mode, parameters with their sizes, line, cases, duration per
    case), the verdicts counted, the variables per element kind."""
    params = list(ds.attrs["parameters"])
    mode = ds.attrs["mode"]
    sizes = " × ".join(str(ds.sizes[p]) if p in ds.dims else "" for p in params)
    over = ", ".join(params) or "no parameter"
    kind = {"grid": f"grid {sizes} over {over}" if sizes.strip(" ×") else f"grid over {over}",
            "zip": f"zip over {over}",
            "monte_carlo": f"Monte Carlo over {over} (seed {ds.attrs.get('seed')})"}.get(
                mode, f"{mode} over {over}")
    status = ds.status.values.astype(str).ravel()
    counted = Counter(status.tolist())
    verdicts = ", ".join(f"{counted[s]} {s}" for s in sorted(counted, key=lambda s: -RANK[s]))
    per: dict[str, list[str]] = {}
    for name, var in ds.data_vars.items():
        element = next((d for d in var.dims if d in ("span", "drive", "node", "web")), "case")
        per.setdefault(element, []).append(str(name))
    lines = [f"<webline study: {kind} of line {ds.attrs['line']}: {status.size} cases of "
             f"{float(ds.attrs['duration']):.4g} s>",
             f"verdicts: {verdicts}",
             *(f"per {element}: {', '.join(names)}" for element, names in per.items()),
             "dims: " + ", ".join(f"{d} {n}" for d, n in ds.sizes.items())
             + "  (ds.full_repr() for xarray's view)"]
    return "\n".join(lines)
