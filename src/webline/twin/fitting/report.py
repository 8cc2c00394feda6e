"""HTML reports of a replay and of a fit, built from ``webline.report``'s page pieces: the
data and what loading did to it, the metrics, the fitted values with their intervals, the
correlations, the overlays and the residuals."""

from __future__ import annotations

import io
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from webline.files import atomic_write_bytes, atomic_write_text
from webline.report.text.html import Image, Section, Text, render
from webline.report.text.tables import Table, make_table
from webline.twin.traces.figures import overlay_figure, residual_figure
from webline.version import __version__

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from webline.twin.fitting.fit import FitResult
    from webline.twin.traces.measurements import Measurements
    from webline.twin.traces.replay import Replay

#: a replayed signal whose NRMSE exceeds this is named in the status line as poorly matched
POOR_NRMSE = 0.1


def _which(names: list[str]) -> str:
    """What a figure shows of ``names``: all, or how many (the tables list every signal)."""
    from webline.twin.traces.figures import MAX_PANELS

    if len(names) <= MAX_PANELS:
        return ""
    return (f" ({MAX_PANELS} of the {len(names)} signals, tensions and torques first; the "
            "tables list them all)")


def _png(fig: Figure) -> bytes:
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png", dpi=90)
    return buffer.getvalue()


def _g(value: float) -> str:
    return f"{value:.4g}" if np.isfinite(value) else "—"


def _data_section(data: Measurements) -> Section:
    return Section("Data", [Text(data.report(), pre=True)])


def metrics_table(frame: Any, key: str, title: str) -> Table:
    """The metrics DataFrame (``twin.traces.metrics.COLUMNS``) as a report table."""
    rows = [(r.signal, r.unit, str(r.points), _g(r.rms), _g(r.max_abs), _g(r.nrmse),
             _g(r.bias), _g(r.r2)) for r in frame.itertuples()]
    return make_table(key, title, ("signal", "unit", "points", "RMS", "max |error|", "NRMSE",
                                   "bias", "R²"), rows)


def _status(frame: Any) -> tuple[str, str]:
    """(status text, class) computed from the metrics: the worst NRMSE and how many signals
    exceed ``POOR_NRMSE``."""
    nrmse = frame["nrmse"].to_numpy(dtype=float)
    finite = nrmse[np.isfinite(nrmse)]
    if not len(finite):
        return "no signal could be compared", "warning"
    poor = int((finite > POOR_NRMSE).sum())
    worst = frame.loc[frame["nrmse"].idxmax()]
    text = (f"{len(finite)} signals compared; largest NRMSE {worst['nrmse']:.3g} "
            f"({worst['signal']}); {poor} above {POOR_NRMSE:g}")
    return text, "warning" if poor else "ok"


def write_replay_report(replay: Replay, out: Path) -> Path:
    """``out/report.html``, ``out/metrics.csv`` and ``out/replay.png``; the report's path."""
    out.mkdir(parents=True, exist_ok=True)
    figure = _png(replay.plot())
    atomic_write_bytes(out / "replay.png", figure)
    atomic_write_text(out / "metrics.csv", replay.metrics.to_csv(index=False))
    status, css = _status(replay.metrics)
    if replay.run.failure:
        status, css = f"the simulation failed: {replay.run.failure}", "failed"
    sections = [
        _data_section(replay.data),
        Section("Replay", [Text("Driven by: " + "; ".join(replay.notes)),
                           metrics_table(replay.metrics, "metrics",
                                         "Simulated against measured (SI)"),
                           Image("replay", "measured (grey) and simulated (blue)"
                                 + _which(replay.data.names), figure)]),
    ]
    html = render(f"webline replay: {replay.line.name}", str(replay.data.source), status, css,
                  sections, f"webline {__version__}", headline="replay")
    return atomic_write_text(out / "report.html", html)


def fit_figure_names(records: int) -> tuple[str, ...]:
    """The figure files of a fit's report: ``fit.png`` and ``residuals.png`` for one record,
    ``fit-K.png`` and ``residuals-K.png`` for record K (from 1) of several."""
    if records == 1:
        return ("fit.png", "residuals.png")
    return tuple(f"{kind}-{k}.png" for k in range(1, records + 1) for kind in ("fit", "residuals"))


def _record_sections(result: FitResult, out: Path) -> tuple[list[Section], list[Section]]:
    """Per record: (its data and weights; its overlays, metrics and residuals), the figures
    written into ``out``."""
    from webline.twin.traces.metrics import signal_metrics
    from webline.twin.traces.signals import si_unit

    several = len(result.records) > 1
    files = fit_figure_names(len(result.records))
    data, traces = [], []
    for k, record in enumerate(result.records):
        names = list(record.signals)
        measured = record.record.measured_signals()
        tag = f" ({record.label})" if several else ""
        key = f"-{k + 1}" if several else ""
        overlay = _png(overlay_figure(record.time, measured, record.after.values, names,
                                      f"fit{tag}: measured, before and after",
                                      record.before.values))
        residuals = _png(residual_figure(record.time, record.residuals(), record.noise,
                                         f"residuals{tag} after the fit (simulated - measured)"))
        atomic_write_bytes(out / files[2 * k], overlay)
        atomic_write_bytes(out / files[2 * k + 1], residuals)
        units = {n: si_unit(n) for n in names}
        before = signal_metrics(record.before.values, measured, units)
        after = signal_metrics(record.after.values, measured, units)
        weights = make_table(f"weights{key}", f"Noise level each signal{tag} was weighted by "
                             "(SI)", ("signal", "noise σ"),
                             [(n, _g(record.noise[n])) for n in names])
        head = [Text(f"Residuals {record.residual_scale:.3g} x the noise"
                     + (f"; scenario {record.record.scenario}" if record.record.scenario
                        else "") + "; driven by: " + "; ".join(record.record.notes))]
        data.append(Section(f"Data{tag}", [Text(record.data.report(), pre=True), *head,
                                           weights]))
        traces.append(Section(f"Traces{tag}", [
            Image(f"fit{key}", "measured (grey), the line's values (dashed), fitted (blue)"
                  + _which(names), overlay),
            metrics_table(before, f"before{key}", "Before the fit"),
            metrics_table(after, f"after{key}", "After the fit"),
            Image(f"residuals{key}", "simulated - measured after the fit, with the ±2σ band "
                  "of each signal's noise level" + _which(names), residuals)]))
    return data, traces


def write_fit_report(result: FitResult, out: Path) -> Path:
    """``out/report.html`` (per record: its data, weights, overlays before and after,
    metrics and residuals; the fitted values and intervals, correlations and model checks)
    and its figures as PNG (``fit_figure_names``); the report's path."""
    out.mkdir(parents=True, exist_ok=True)
    data, traces = _record_sections(result, out)
    rows = []
    for i, p in enumerate(result.parameters):
        ok = bool(result.identifiable[i])
        rows.append((result.labels[i], p.unit, _g(p.start), _g(result.value[i]) if ok else "—",
                     _g(result.stderr[i]) if ok else "—", _g(result.ci95[i, 0]),
                     _g(result.ci95[i, 1]),
                     "yes" if ok else "no: " + result.identifiability.reasons[i]))
    title = ("Fitted parameters" if result.verdict.good else
             f"Values of a {result.verdict.status.upper()} fit, not to be trusted")
    values = make_table("parameters", f"{title} (SI; an interval of a parameter that is not "
                        "identifiable is its bounds, one at a bound is one-sided; PATH@RECORD "
                        "is fitted to that record alone)",
                        ("parameter", "unit", "line", "fitted", "stderr", "95 % low",
                         "95 % high", "identifiable"), rows)
    short = [f"p{i + 1}" for i in range(len(result.parameters))]
    correlation = make_table("correlation", "Correlation of the estimates (" + ", ".join(
        f"{s} = {label}" for s, label in zip(short, result.labels, strict=True)) + ")",
        ("", *short), [(s, *(f"{c:+.3f}" for c in row))
                       for s, row in zip(short, result.correlation, strict=True)])
    unidentified = [result.labels[i] for i in range(len(result.parameters))
                    if not result.identifiable[i]]
    points = sum(r.record.points for r in result.records)
    status = (f"{len(result.parameters) - len(unidentified)} of {len(result.parameters)} "
              f"parameters identified; {result.simulations} simulations, cost "
              f"{result.cost:.4g} over {points} points"
              + (f" of {len(result.records)} records" if len(result.records) > 1 else "")
              + f"; {'converged' if result.converged else 'not converged: ' + result.message}"
              + (f"; not identifiable from this data: {', '.join(unidentified)}"
                 if unidentified else ""))
    verdict = result.verdict
    each = "".join(f", {r.label} {r.residual_scale:.3g}" for r in result.records
                   if len(result.records) > 1)
    status = (f"{verdict.status.upper()} FIT" + (": " + "; ".join(verdict.reasons)
                                                  if verdict.reasons else "")
              + (" (docs/commissioning.md: when the fit is poor)" if not verdict.good else "")
              + f". Residuals {result.residual_scale:.3g} x the noise{each}; " + status
              + (f"; {result.global_stage.summary()}" if result.global_stage else ""))
    css = {"good": "warning" if unidentified else "ok", "poor": "warning"}.get(
        verdict.status, "failed")
    checks = make_table("checks", "Model checks: residuals per signal, largest first (RMS in "
                        "noise levels; white residuals have p well above 0.001 and a "
                        "correlation time near one sample)",
                        ("signal", "RMS", "correlation time [s]", "whiteness p",
                         "worst 0.5 s from [s]", "RMS there"),
                        [(c.signal, _g(c.rms), _g(c.correlation_time), f"{c.p_white:.2g}",
                          _g(c.window[0]), _g(c.window_rms)) for c in result.checks.signals])
    findings = [Text("Model checks: " + "; ".join(result.checks.findings))] if \
        result.checks.findings else []
    sections = [*data, Section("Fit", [values, correlation]), *traces,
                Section("Model checks", [*findings, checks])]
    html = render(f"webline fit: {result.line.name}", result.sources, status, css,
                  sections, f"webline {__version__}", headline="fit")
    return atomic_write_text(out / "report.html", html)
