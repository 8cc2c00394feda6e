"""The Dataset of a study (``webline.sim.sweeps.sweep``): per case, the metrics of
``webline.sim.results.metrics`` from the batch's accumulators, the verdict (status and headline)
built
by the function ``Result.verdict`` uses (``findings.run_verdict``), the parameter values as
coordinates (with their units) and, on request, the span tensions over time."""

from __future__ import annotations

import json
import math
from typing import Any

import numpy as np

from webline.line import Line
from webline.sim.core.plan import Plan
from webline.sim.results.events import EventSummary
from webline.sim.results.failure import kernel_failure
from webline.sim.results.findings import run_verdict
from webline.sim.results.metrics import METRICS
from webline.sim.results.yield_findings import case_yield_findings
from webline.sim.sweeps import batch_layout as B
from webline.sim.sweeps.batch import BatchOutput
from webline.sim.sweeps.batch_states import batch_after_stop, batch_state_findings
from webline.sim.sweeps.cases import case_value, path_unit
from webline.verdict import Verdict

#: the kinds of event in the order ``Result.events`` lists them, with their elements
_EVENT_ELEMENTS = (("slack", "span"), ("tension_limit", "span"), ("torque_limit", "drive"),
                   ("slip", "node"), ("backlash_open", "drive"))


def case_verdict(plan: Plan, out: BatchOutput, c: int) -> Verdict:
    """The verdict of case ``c`` of a batch, by ``findings.run_verdict`` as ``Result.verdict``
    gives it for the same run: its failure, its events (``EventSummary`` from the batch's
    accumulators), its web breaks (the monitor's state at the end and the driven rollers
    after the stop), its winder states (``batch_states``), strain beyond yield (from its
    largest tensions) and its stability."""
    line, lay = plan.line, out.layout
    failure = kernel_failure(plan, int(out.status[c]), float(out.t_fail[c]), int(out.where[c]),
                             out.x[c])
    n_ev, base = lay.n_events, lay.event_base
    row = out.acc[c]
    end = float(row[lay.end_column])
    names = {"span": line.span_name, "node": line.node_name,
             "drive": lambda d: line.node_name(line.drives[d])}
    slices = lay.event_slices()
    events = []
    for kind, element in _EVENT_ELEMENTS:
        start, count = slices[kind]
        for j in range(count):
            e = start + j
            if row[base + B.EV_COUNT * n_ev + e] > 0:
                events.append(EventSummary(
                    kind, names[element](j), int(row[base + B.EV_COUNT * n_ev + e]),
                    float(row[base + B.EV_FIRST * n_ev + e]),
                    float(row[base + B.EV_TOTAL * n_ev + e]),
                    float(row[base + B.EV_LONGEST * n_ev + e]), end))
    monitor = (float(out.monitor[c, 0]), int(out.monitor[c, 1]))
    n_s = line.n_spans
    # in the order Result.verdict lists them: the winder states, then strain beyond yield
    extra = batch_state_findings(plan, row, lay.state_base, int(row[lay.end_column + 1]), end)
    extra += case_yield_findings(line, row[B.A_TMAX * n_s:(B.A_TMAX + 1) * n_s])
    return run_verdict(plan, failure, events, end, monitor,
                       batch_after_stop(plan, row, lay.stop_base, monitor[0]), extra)


def batch_metrics(out: BatchOutput) -> dict[str, np.ndarray]:
    """Metrics (``METRICS``) per case of a batch from its accumulators."""
    lay, acc = out.layout, out.acc
    s = lay.n_spans

    def block(b: int) -> np.ndarray:
        return acc[:, b * s:(b + 1) * s]

    n_rec = acc[:, lay.end_column + 1:lay.end_column + 2]
    totals = acc[:, lay.event_base:lay.event_base + lay.n_events]
    sl = lay.event_slices()
    settle = np.where(block(B.A_LASTOUT) > 0, math.inf, block(B.A_SETTLE))
    metrics = {"tension_rms_error": np.sqrt(block(B.A_SUMSQ) / n_rec),
               "tension_peak_error": block(B.A_PEAK).copy(),
               "tension_min": block(B.A_TMIN).copy(), "tension_max": block(B.A_TMAX).copy(),
               "settling_time": settle,
               "slack_time": totals[:, sl["slack"][0]:sl["slack"][0] + s],
               "torque_limit_time": totals[:, sl["torque_limit"][0]:sl["torque_limit"][0]
                                           + lay.n_drives],
               "slip_time": totals[:, sl["slip"][0]:sl["slip"][0] + lay.n_nodes]}
    return metrics


class Collector:
    """Per-case metrics, statuses, coordinates and traces, filled block by block."""

    def __init__(self, line: Line, n_c: int, paths: list[str], n_trace: int) -> None:
        self.line, self.paths = line, paths
        dims = {"span": line.n_spans, "drive": len(line.drives), "node": line.n_nodes}
        self.data = {name: np.full((n_c, dims[dim]), math.nan)
                     for name, (dim, _, _) in METRICS.items()}
        self.status = np.empty(n_c, dtype=object)
        self.headline = np.empty(n_c, dtype=object)
        self.t_fail = np.full(n_c, math.nan)
        self.substeps = np.zeros(n_c, dtype=np.int64)
        self.values: dict[str, list[object]] = {p: [None] * n_c for p in paths}
        self.traces = np.full((n_c, n_trace, line.n_spans), math.nan) if n_trace else None

    def add(self, cases: list[int], plans: list[Plan], substeps: list[int],
            out: BatchOutput) -> None:
        arrays = batch_metrics(out)
        for name in METRICS:
            self.data[name][cases] = arrays[name]
        for j, (c, plan) in enumerate(zip(cases, plans, strict=True)):
            verdict = case_verdict(plan, out, j)
            self.status[c], self.headline[c] = verdict.status, verdict.headline
            self.t_fail[c] = float(out.t_fail[j])
            for path in self.paths:
                self.values[path][c] = case_value(plan.line, path)
        self.substeps[cases] = substeps
        if self.traces is not None:
            self.traces[cases] = out.traces

    def dataset(self, duration: float, trace_interval: float) -> Any:
        import xarray as xr

        line, data = self.line, self.data
        loadcell = np.zeros(line.n_spans, dtype=bool)
        for zone in line.zones:
            loadcell[zone.loadcell] = True
        for name in ("tension_rms_error", "tension_peak_error", "settling_time"):
            data[name][:, ~loadcell] = math.nan
        names = {"span": [line.span_name(k) for k in range(line.n_spans)],
                 "drive": [line.node_name(i) for i in line.drives],
                 "node": [line.node_name(i) for i in range(line.n_nodes)]}
        variables = {name: xr.Variable(("case", dim), data[name],
                                       attrs={"units": units, "long_name": text})
                     for name, (dim, units, text) in METRICS.items()}
        variables["status"] = xr.Variable(("case",), self.status.astype(str),
                                          attrs={"long_name": "verdict status of the run"})
        variables["headline"] = xr.Variable(("case",), self.headline.astype(str), attrs={
            "long_name": "verdict of the run: its status and first findings, in words"})
        variables["failure_time"] = xr.Variable(("case",), self.t_fail, attrs={
            "units": "s", "long_name": "time the run stopped early (NaN: it ran to the end)"})
        variables["substeps"] = xr.Variable(("case",), self.substeps, attrs={
            "long_name": "RK4 sub-steps per controller period"})
        coords: dict[str, Any] = {"case": np.arange(len(self.status)), **names}
        for path in self.paths:
            unit = path_unit(line, path)
            coords[path] = ("case", _coordinate(self.values[path]),
                            {"long_name": f"line parameter {path}"}
                            | ({} if unit is None else {"units": unit}))
        if self.traces is not None:
            coords["time"] = ("time", np.arange(self.traces.shape[1]) * trace_interval,
                              {"units": "s"})
            variables["tension"] = xr.Variable(("case", "time", "span"), self.traces,
                                               attrs={"units": "N", "long_name": "span tension"})
        ds = xr.Dataset(variables, coords=coords)
        ds.attrs.update({"line": line.name, "duration": duration, "parameters": self.paths})
        return ds


def _coordinate(values: list[object]) -> np.ndarray:
    """A path's values as a coordinate: numbers [SI], else their labels (``_label``: a table,
    a choice, a switch as a line file writes it, ``true``/``false`` for a boolean)."""
    if all(isinstance(v, int | float) and not isinstance(v, bool) for v in values):
        return np.array([float(v) for v in values])  # type: ignore[arg-type]
    return np.array([_label(v) for v in values])


def _label(value: object, nested: bool = False) -> str:
    """``value`` as a line file writes it: a table (a validated element of the spec, or a
    dict) inline with the keys it sets, ``{type = "state_feedback"}``, its quantities in SI."""
    dump = getattr(value, "model_dump", None)
    if dump is not None:
        value = dump(exclude_none=True, mode="json")
    if isinstance(value, dict):
        return "{" + ", ".join(f"{k} = {_label(v, True)}" for k, v in value.items()) + "}"
    if isinstance(value, list | tuple):
        return "[" + ", ".join(_label(v, True) for v in value) + "]"
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str) and nested:
        return json.dumps(value, ensure_ascii=False)
    return str(value)
