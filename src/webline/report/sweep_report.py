"""The report of a sweep or Monte Carlo study (``webline.sweep``): summary tables, the table
of cases (their parameters, status and worst metric), metric versus parameter plots, a heat
map for a 2-D grid, histograms and verdict probabilities. Every quantity is shown in the
``Display``'s units (``webline sweep --units``; the results file stays SI)."""

from __future__ import annotations

import io
import math
from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from webline.report.text.display import Display, number_text
from webline.report.text.html import Image, Section, Text, render
from webline.report.text.tables import Table, make_table
from webline.sim.results.metrics import METRICS
from webline.sim.sweeps.branch_study import FINAL_ERROR
from webline.sim.sweeps.distributions import proportion_interval
from webline.sim.sweeps.study_grid import as_cases
from webline.units import SI_UNITS
from webline.verdict import RANK

#: the metric the plots show, per loadcell span
MAIN_METRIC = "tension_rms_error"


def _png(fig: Any) -> bytes:
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png", dpi=110, bbox_inches="tight")
    plt.close(fig)
    return buffer.getvalue()


def loadcell_spans(ds: Any) -> list[str]:
    """Spans with a tension reference (their RMS error is a number)."""
    ds = as_cases(ds)  # a grid laid flat: one row per case
    values = ds[MAIN_METRIC].values
    return [str(s) for j, s in enumerate(ds.span.values) if np.isfinite(values[:, j]).any()]


def status_table(ds: Any) -> Table:
    """Cases and share of cases per verdict status, worst first; for Monte Carlo the exact
    95 % interval of each share as a probability (``distributions.proportion_interval``)."""
    ds = as_cases(ds)  # a grid laid flat: one row per case
    status = ds.status.values.astype(str)
    n = len(status)
    sampled = ds.attrs.get("mode") == "monte_carlo"
    rows = []
    groups = [(name, status == name) for name in sorted(set(status), key=lambda s: -RANK[s])]
    if sampled:  # what a robustness question asks, also when no case failed
        groups.append(("unstable or failed", np.isin(status, ("unstable", "failed"))))
    for name, members in groups:
        k = int(np.sum(members))
        row = [name, str(k), f"{k / n:.1%}"]
        if sampled:
            low, high = proportion_interval(k, n)
            row.append(f"{low:.1%} to {high:.1%}")
        rows.append(tuple(row))
    columns = ("status", "cases", "share", *(("probability, 95 % interval",) if sampled else ()))
    return make_table("sweep-status", f"Verdicts of {n} cases", columns, rows)


#: cases named in the table of cases that were not ok, at most
WORST_SHOWN = 10


def worst_cases_table(ds: Any) -> Table | None:
    """The cases that were not ok, worst status first (then in case order), at most
    ``WORST_SHOWN``: each case's number, status and verdict headline (what its run says);
    None when every case was ok or the study has no headlines."""
    ds = as_cases(ds)  # a grid laid flat: one row per case
    if "headline" not in ds:
        return None
    status = ds.status.values.astype(str)
    bad = sorted((c for c in range(len(status)) if status[c] != "ok"),
                 key=lambda c: (-RANK[status[c]], c))
    if not bad:
        return None
    shown = bad[:WORST_SHOWN]
    rows = [(str(int(ds.case.values[c])), status[c], str(ds.headline.values[c])) for c in shown]
    title = (f"Cases that were not ok ({len(bad)})" if len(shown) == len(bad) else
             f"The {len(shown)} worst of {len(bad)} cases that were not ok")
    return make_table("sweep-worst", title, ("case", "status", "verdict"), rows)


#: the kind of quantity (``Display``) of each SI unit a study's numbers carry
KIND_OF_SI_UNIT = {unit: kind for kind, unit in SI_UNITS.items()
                   if unit and kind != "force_per_width"}


def shown(display: Display, values: np.ndarray, si_unit: str | None) -> tuple[np.ndarray, str]:
    """``values`` in SI ``si_unit`` as ``display`` shows them, and the unit it shows."""
    kind = KIND_OF_SI_UNIT.get(si_unit or "")
    if kind is None or not np.issubdtype(np.asarray(values).dtype, np.number):
        return values, si_unit or ""
    return display.array(values, kind), display.unit(kind)


def metric_table(ds: Any, display: Display | None = None) -> Table:
    """Min, median and max over the cases of each metric of each element where it is not
    NaN in every case, in ``display``'s units (default SI)."""
    ds = as_cases(ds)  # a grid laid flat: one row per case
    display = display or Display()
    rows = []
    shown_metrics = {**METRICS, **{k: v for k, v in FINAL_ERROR.items() if k in ds}}
    for name, (dim, si_unit, _) in shown_metrics.items():
        for j, element in enumerate(ds[dim].values):
            column, units = shown(display, ds[name].values[:, j], si_unit)
            finite = column[np.isfinite(column)]
            if finite.size == 0 or (name.endswith("_time") and not finite.any()):
                continue
            rows.append((f"{name} [{element}]", f"{finite.min():.4g}",
                         f"{np.median(finite):.4g}", f"{finite.max():.4g}", units))
    return make_table("sweep-metrics", "Metrics over the cases",
                      ("metric", "min", "median", "max", "unit"), rows)


#: most lines of one metric-versus-parameter plot (one per value of the other parameters)
MAX_GROUPS = 8


def axis_label(ds: Any, path: str) -> str:
    """``path [unit]`` of a parameter coordinate (its ``units`` attribute), or the path."""
    unit = ds[path].attrs.get("units")
    return f"{path} [{unit}]" if unit else path


def _unit(ds: Any) -> str:
    """The unit the main metric is in (SI, or the report's ``in_units``)."""
    return str(ds[MAIN_METRIC].attrs.get("units", "N"))


def in_units(ds: Any, display: Display) -> Any:
    """A flat copy of ``ds`` (``as_cases``) with every numeric variable and coordinate that
    carries an SI ``units`` attribute in ``display``'s units, its attribute changed to match."""
    ds = as_cases(ds).copy()
    for name in list(ds.variables):
        var = ds[name]
        values, unit = shown(display, var.values, var.attrs.get("units"))
        if unit != (var.attrs.get("units") or "") or values is not var.values:
            ds[name] = var.copy(data=values)
            ds[name].attrs["units"] = unit
    return ds


#: the cases the table of cases lists, at most (the results file holds every case)
CASES_SHOWN = 50


def cases_table(ds: Any) -> Table:
    """One row per case (the first ``CASES_SHOWN``): its number, the value of each swept
    parameter (in the units of ``ds``, see ``in_units``), its status and its largest RMS
    tension error over the loadcell spans."""
    ds = as_cases(ds)
    params = list(ds.attrs.get("parameters", []))
    spans = loadcell_spans(ds)
    worst = (ds[MAIN_METRIC].sel(span=spans).max("span").values if spans
             else np.full(ds.sizes["case"], math.nan))
    n = ds.sizes["case"]
    rows = []
    for c in range(min(n, CASES_SHOWN)):
        cells = [str(int(ds.case.values[c]))]
        cells += [_short(ds[p].values[c].item()) for p in params]
        cells += [str(ds.status.values[c]), number_text(float(worst[c]))]
        rows.append(cells)
    title = "Cases" if n <= CASES_SHOWN else (f"The first {CASES_SHOWN} of {n} cases (every "
                                              "case is in sweep.nc)")
    return make_table("sweep-cases", title,
                      ("case", *(axis_label(ds, p) for p in params), "status",
                       f"largest RMS tension error [{_unit(ds)}]"), rows)


def figures(ds: Any) -> list[Image]:
    """Heat map (grid of two numeric parameters), metric versus the first numeric parameter
    (a grid or zip: a line per loadcell span, or with other parameters a line per value of
    theirs), and histograms per loadcell span (Monte Carlo, or nothing numeric to plot
    against)."""
    ds = as_cases(ds)  # a grid laid flat: one row per case
    spans = loadcell_spans(ds)
    if not spans:
        return []
    metric = ds[MAIN_METRIC].sel(span=spans)
    params = list(ds.attrs.get("parameters", []))
    numeric = [p for p in params if np.issubdtype(ds[p].dtype, np.number)]
    mode = ds.attrs.get("mode")
    out: list[Image] = []
    if mode == "grid" and len(numeric) == 2 and len(params) == 2:
        out.append(_heat_map(ds, metric, params))
    elif mode in ("grid", "zip") and numeric:
        out.append(_against(ds, metric, spans, numeric[0],
                            [p for p in params if p != numeric[0]]))
    if mode == "monte_carlo" or not out:
        out.append(_histograms(metric, spans))
    return out


def _heat_map(ds: Any, metric: Any, params: list[str]) -> Image:
    shape = tuple(ds.attrs["shape"])
    worst = metric.max("span").values.reshape(shape)
    x = ds[params[1]].values.reshape(shape)[0]
    y = ds[params[0]].values.reshape(shape)[:, 0]
    fig, ax = plt.subplots(figsize=(6, 4.5))
    mesh = ax.pcolormesh(x, y, worst, shading="nearest")
    fig.colorbar(mesh, ax=ax, label=f"largest RMS tension error over spans [{_unit(ds)}]")
    ax.set_xlabel(axis_label(ds, params[1]))
    ax.set_ylabel(axis_label(ds, params[0]))
    return Image("sweep-heatmap", "Largest RMS tension error over the grid", _png(fig))


def _against(ds: Any, metric: Any, spans: list[str], x_path: str, others: list[str]) -> Image:
    """The metric against ``x_path``: per span, or with ``others`` the largest over the
    spans, one line per combination of the others' values (at most ``MAX_GROUPS``)."""
    x = ds[x_path].values
    fig, ax = plt.subplots(figsize=(7, 3.5))
    if not others:
        order = np.argsort(x, kind="stable")
        for span in spans:
            ax.plot(x[order], metric.sel(span=span).values[order], "o-", label=span)
        ylabel = f"RMS tension error [{_unit(ds)}]"
        caption = f"RMS tension error against {x_path}"
    else:
        worst = metric.max("span").values
        keys = list(zip(*(ds[p].values.tolist() for p in others), strict=True))
        groups = list(dict.fromkeys(keys))
        for key in groups[:MAX_GROUPS]:
            mask = np.array([k == key for k in keys])
            order = np.argsort(x[mask], kind="stable")
            label = ", ".join(f"{p} = {_short(v)}" for p, v in zip(others, key, strict=True))
            ax.plot(x[mask][order], worst[mask][order], "o-", label=label)
        ylabel = f"largest RMS tension error over spans [{_unit(ds)}]"
        shown = "" if len(groups) <= MAX_GROUPS else f" (the first {MAX_GROUPS} of {len(groups)})"
        caption = (f"Largest RMS tension error over the loadcell spans against {x_path}, a line "
                   f"per value of {', '.join(others)}{shown}")
    ax.set_xlabel(axis_label(ds, x_path))
    ax.set_ylabel(ylabel)
    ax.legend(fontsize="small")
    return Image("sweep-metric", caption, _png(fig))


def _short(value: object, limit: int = 40) -> str:
    text = f"{value:.4g}" if isinstance(value, float) else str(value)
    return text if len(text) <= limit else text[:limit - 1] + "…"


def _histograms(metric: Any, spans: list[str]) -> Image:
    """One histogram per loadcell span, each on its own axis (their errors may differ by
    orders of magnitude)."""
    fig, axes = plt.subplots(len(spans), 1, figsize=(7, 1.9 * len(spans) + 0.6), squeeze=False)
    for ax, span in zip(axes[:, 0], spans, strict=True):
        values = metric.sel(span=span).values
        ax.hist(values[np.isfinite(values)], bins=30)
        ax.set_ylabel("cases")
        ax.set_title(span, fontsize="medium", loc="left")
    axes[-1, 0].set_xlabel(f"RMS tension error [{metric.attrs.get('units', 'N')}]")
    fig.tight_layout()
    return Image("sweep-hist", "Distribution of the RMS tension error per loadcell span",
                 _png(fig))


def sweep_html(ds: Any, display: Display | None = None) -> str:
    """The whole sweep report page, every quantity in ``display``'s units (default SI)."""
    display = display or Display()
    ds = in_units(ds, display)  # a grid laid flat: one row per case
    status = ds.status.values.astype(str)
    worst = max(status, key=lambda s: RANK[s]) if len(status) else "ok"
    failed = float(np.mean(np.isin(status, ("unstable", "failed"))))
    headline = (f"{len(status)} cases of line {ds.attrs.get('line')}: "
                f"{failed:.1%} unstable or failed, worst verdict {worst}")
    params = ", ".join(ds.attrs.get("parameters", [])) or "none"
    worst_cases = worst_cases_table(ds)
    verdicts = (status_table(ds),) + ((worst_cases,) if worst_cases is not None else ())
    sections = [Section("Verdicts", verdicts),
                Section("Cases", (cases_table(ds),)),
                Section("Metrics", (metric_table(ds),)),
                Section("Figures", tuple(figures(ds)) or (Text("No loadcell span to plot."),))]
    css = {"ok": "ok", "warning": "warning"}.get(worst, "failed")
    duration = float(ds.attrs.get("duration", math.nan))
    return render(f"webline sweep: {ds.attrs.get('line')}",
                  f"{ds.attrs.get('mode')} over {params}; {duration:.4g} s per case",
                  "", css, sections, f"webline sweep report · units: {display.system}",
                  headline=headline)
