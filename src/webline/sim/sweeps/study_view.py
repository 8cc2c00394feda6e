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

    def _case_dims(self) -> tuple[Any, ...] | None:
        """The dimensions that number the cases (``case``, or a grid's parameter paths): those
        of ``status``; None for a slice that lost it (xarray's own tables then)."""
        return tuple(self["status"].dims) if "status" in self.data_vars else None

    def metrics(self) -> Any:
        """A tidy table (pandas): one row per case, metric and element (span, drive or node;
        "" for a metric of the whole case) with columns: the case dimensions (``case`` or the
        grid's parameter paths), every parameter coordinate, ``metric``, ``element`` and
        ``value`` (SI). Text variables (``status``, ``headline``) are left to
        ``to_dataframe``."""
        import pandas as pd

        cases = self._case_dims()
        if cases is None:
            raise ValueError("metrics() needs a study's Dataset (its 'status' variable)")
        frame = self._case_table(cases)
        parts = []
        for name, da in self.data_vars.items():
            if da.dtype.kind not in "fiub":
                continue
            extra = [d for d in da.dims if d not in cases]
            if len(extra) > 1:  # no study metric has two element dimensions
                raise ValueError(f"metric {name!r} has dimensions {da.dims}")
            values = da.transpose(*cases, *extra).values.reshape(frame.shape[0], -1)
            elements = [str(e) for e in da[extra[0]].values] if extra else [""]
            for k, element in enumerate(elements):
                part = frame.copy()
                part["metric"], part["element"] = name, element
                part["value"] = values[:, k]
                parts.append(part)
        return pd.concat(parts, ignore_index=True)

    def to_dataframe(self, dim_order: Any = None) -> Any:
        """One row per case (pandas): the case dimensions as index, every parameter
        coordinate and every variable as columns, a per-element metric as one column per
        element (``tension_rms_error[span2]``): no cross product of spans, drives and nodes.
        With ``dim_order``, or for a slice without ``status``: xarray's own table."""
        cases = self._case_dims()
        if cases is None or dim_order is not None:
            return xr.Dataset.to_dataframe(self, dim_order=dim_order)
        frame = self._case_table(cases)
        for name, da in self.data_vars.items():
            extra = [d for d in da.dims if d not in cases]
            values = da.transpose(*cases, *extra).values.reshape(frame.shape[0], -1)
            if not extra:
                frame[name] = values[:, 0]
                continue
            for k, element in enumerate(da[extra[0]].values):
                frame[f"{name}[{element}]"] = values[:, k]
        return frame.set_index(list(cases))

    def _case_table(self, cases: tuple[Any, ...]) -> Any:
        """A table of one row per case: the case dimensions' values and every coordinate
        over the cases (the parameters of a Monte Carlo study, ``case`` of a grid)."""
        import pandas as pd

        index = pd.MultiIndex.from_product([self[d].values for d in cases], names=cases)
        frame = index.to_frame(index=False)
        for name, coord in self.coords.items():
            if name not in cases and coord.dims and set(coord.dims) <= set(cases):
                spread = coord.broadcast_like(self["status"]).transpose(*cases)
                frame[name] = spread.values.reshape(-1)
        return frame


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
