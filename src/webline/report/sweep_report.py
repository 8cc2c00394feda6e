"""The report of a sweep or Monte Carlo study (``webline.sweep``): summary tables, metric
versus parameter plots, a heat map for a 2-D grid, histograms and verdict probabilities."""

from __future__ import annotations

import io
import math
from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from webline.report.html import Image, Section, Text, render
from webline.report.tables import Table, make_table
from webline.sim.metrics import METRICS
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
    values = ds[MAIN_METRIC].values
    return [str(s) for j, s in enumerate(ds.span.values) if np.isfinite(values[:, j]).any()]


def status_table(ds: Any) -> Table:
    """Cases and share of cases per verdict status, worst first."""
    status = ds.status.values.astype(str)
    n = len(status)
    rows = [(s, str(int(np.sum(status == s))), f"{np.mean(status == s):.1%}")
            for s in sorted(set(status), key=lambda s: -RANK[s])]
    return make_table("sweep-status", f"Verdicts of {n} cases", ("status", "cases", "share"),
                      rows)


def metric_table(ds: Any) -> Table:
    """Min, median and max over the cases of each metric of each element where it is not
    NaN in every case."""
    rows = []
    for name, (dim, units, _) in METRICS.items():
        for j, element in enumerate(ds[dim].values):
            column = ds[name].values[:, j]
            finite = column[np.isfinite(column)]
            if finite.size == 0 or (name.endswith("_time") and not finite.any()):
                continue
            rows.append((f"{name} [{element}]", f"{finite.min():.4g}",
                         f"{np.median(finite):.4g}", f"{finite.max():.4g}", units))
    return make_table("sweep-metrics", "Metrics over the cases",
                      ("metric", "min", "median", "max", "unit"), rows)


def figures(ds: Any) -> list[Image]:
    """Metric versus parameter (1 parameter), heat map (2-D grid), histograms (Monte Carlo)."""
    spans = loadcell_spans(ds)
    params = list(ds.attrs.get("parameters", []))
    numeric = [p for p in params if np.issubdtype(ds[p].dtype, np.number)]
    out: list[Image] = []
    metric = ds[MAIN_METRIC].sel(span=spans) if spans else None
    if metric is None:
        return out
    mode = ds.attrs.get("mode")
    if mode == "monte_carlo" or len(numeric) != len(params) or len(params) > 2:
        fig, ax = plt.subplots(figsize=(7, 3.5))
        for span in spans:
            values = metric.sel(span=span).values
            ax.hist(values[np.isfinite(values)], bins=30, alpha=0.6, label=span)
        ax.set_xlabel("RMS tension error [N]")
        ax.set_ylabel("cases")
        ax.legend()
        out.append(Image("sweep-hist", "Distribution of the RMS tension error per loadcell span",
                         _png(fig)))
    if mode == "grid" and len(numeric) == 2 and len(params) == 2:
        shape = tuple(ds.attrs["shape"])
        worst = metric.max("span").values.reshape(shape)
        x = ds[params[1]].values.reshape(shape)[0]
        y = ds[params[0]].values.reshape(shape)[:, 0]
        fig, ax = plt.subplots(figsize=(6, 4.5))
        mesh = ax.pcolormesh(x, y, worst, shading="nearest")
        fig.colorbar(mesh, ax=ax, label="largest RMS tension error over spans [N]")
        ax.set_xlabel(params[1])
        ax.set_ylabel(params[0])
        out.append(Image("sweep-heatmap", "Largest RMS tension error over the grid", _png(fig)))
    elif mode in ("grid", "zip") and numeric:
        fig, ax = plt.subplots(figsize=(7, 3.5))
        x = ds[numeric[0]].values
        order = np.argsort(x, kind="stable")
        for span in spans:
            ax.plot(x[order], metric.sel(span=span).values[order], "o-", label=span)
        ax.set_xlabel(f"{numeric[0]} [SI]")
        ax.set_ylabel("RMS tension error [N]")
        ax.legend()
        out.append(Image("sweep-metric", f"RMS tension error against {numeric[0]}", _png(fig)))
    return out


def sweep_html(ds: Any) -> str:
    """The whole sweep report page."""
    status = ds.status.values.astype(str)
    worst = max(status, key=lambda s: RANK[s]) if len(status) else "ok"
    failed = float(np.mean(np.isin(status, ("unstable", "failed"))))
    headline = (f"{len(status)} cases of line {ds.attrs.get('line')}: "
                f"{failed:.1%} unstable or failed, worst verdict {worst}")
    params = ", ".join(ds.attrs.get("parameters", [])) or "none"
    sections = [Section("Verdicts", (status_table(ds),)),
                Section("Metrics", (metric_table(ds),)),
                Section("Figures", tuple(figures(ds)) or (Text("No loadcell span to plot."),))]
    css = {"ok": "ok", "warning": "warning"}.get(worst, "failed")
    duration = float(ds.attrs.get("duration", math.nan))
    return render(f"webline sweep: {ds.attrs.get('line')}",
                  f"{ds.attrs.get('mode')} over {params}; {duration:.4g} s per case",
                  "", css, sections, "webline sweep report", headline=headline)
