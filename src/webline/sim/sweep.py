"""``webline.sweep`` and ``webline.monte_carlo``: many runs of one line, batched.

Each case is the line with some values replaced (``Line.replace`` paths); its plan, RK4
sub-steps and initial state are built once in Python, then all cases of one structure run
in the batched kernel (``webline.sim.batch``) on every core. The result is an
``xarray.Dataset`` over ``case`` with the parameters as coordinates [SI] and the metrics of
``webline.sim.metrics`` per case, plus the verdict status of each case.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from webline.line import Line, load_line
from webline.sim import batch as B
from webline.sim import kernel
from webline.sim.batch import BatchOutput, run_batch
from webline.sim.distributions import draw
from webline.sim.failure import kernel_failure
from webline.sim.metrics import METRICS
from webline.sim.plan import Plan, compile_plan, equilibrium_plan_state
from webline.sim.simulate import MAX_RECORDS, choose_substeps
from webline.sim.stability import stability_findings
from webline.spec.paths import split_path
from webline.spec.ranges import argument
from webline.verdict import Finding, Level, Verdict


def spec_value(line: Line, path: str) -> object:
    """The value at ``path`` in ``line``'s validated spec (SI numbers for quantities)."""
    node: Any = line.spec.model_dump(exclude_none=True)
    for part in split_path(path):
        if isinstance(node, list):
            if isinstance(part, str) and not part.lstrip("-").isdigit():
                node = next(item for item in node if item.get("name") == part)
            else:
                node = node[int(part)]
        else:
            node = node[str(part)]
    return node


def _coordinate(values: list[object]) -> np.ndarray:
    try:
        return np.array([float(v) for v in values])  # type: ignore[arg-type]
    except (TypeError, ValueError):
        return np.array([str(v) for v in values])


def run_cases(line: Line | str | Path, cases: Sequence[Mapping[str, object]], *,
              duration: float | str | None = None, scenario: str | None = None,
              record: float | str | None = None, workers: int | None = None,
              ) -> Any:
    """Simulate ``line`` once per mapping of changes in ``cases`` for ``duration`` [s]
    (default: the scenario's, else 10 s); the Dataset of ``sweep``. ``record`` [s]: keep the
    span tensions at that interval (``tension`` over case, time, span). ``workers``: threads
    (default: every core)."""
    base = load_line(line)
    if scenario is not None:
        base = base.with_scenario(scenario)
        if duration is None:
            duration = base.spec.scenarios[scenario].duration
    duration = 10.0 if duration is None else argument(duration, "time", "duration",
                                                      within="scenario.duration")
    record_s = None if record is None else argument(record, "time", "record", within=None)
    plans, states, n_ticks, substeps, every = [], [], [], [], []
    for changes in cases:
        plan = compile_plan(base.replace(dict(changes)) if changes else base)
        x, istate = equilibrium_plan_state(plan)
        plans.append(plan)
        states.append((x, istate, kernel.initial_slip(plan, x)))
        ticks = max(1, round(duration / plan.dt))
        n_ticks.append(ticks)
        substeps.append(choose_substeps(plan))
        every.append(max(1, math.ceil((ticks + 1) / MAX_RECORDS)))  # as simulate records
    trace_every = 0
    n_trace = 0
    if record_s is not None:
        # a multiple of the record interval, so every trace point is a record
        step = max(every)
        trace_every = step * max(1, round(record_s / (plans[0].dt * step)))
        n_trace = max(n_ticks) // trace_every + 1
    # cases of one structure and table shapes run in one batch
    groups: dict[tuple[object, ...], list[int]] = {}
    for c, plan in enumerate(plans):
        key = (*(a.tobytes() for a in plan.structure()), plan.wound_ripple.shape,
               plan.speed_ripple.shape, plan.prof_off.shape)
        groups.setdefault(key, []).append(c)
    outputs: list[tuple[list[int], BatchOutput]] = []
    for idx in groups.values():
        out = run_batch([plans[c] for c in idx], [states[c] for c in idx],
                        np.array([n_ticks[c] for c in idx]), np.array([substeps[c] for c in idx]),
                        np.array([every[c] for c in idx]), trace_every, n_trace, workers)
        outputs.append((idx, out))
    return _dataset(plans, cases, outputs, duration, trace_every, n_trace, substeps)


def case_status(plan: Plan, out: BatchOutput, c: int) -> tuple[str, float]:
    """(verdict status, failure time [s] or NaN) of case ``c`` of a batch, built from the
    same findings as ``Result.verdict``: failure, events (by their first time), stability."""
    line = plan.line
    findings: list[Finding] = []
    failure = kernel_failure(plan, int(out.status[c]), float(out.t_fail[c]), int(out.where[c]),
                             out.x[c])
    if failure is not None:
        level: Level = "interrupted" if failure.kind == "interrupted" else "failed"
        findings.append(Finding(level, failure.kind, failure.where, failure.message,
                                failure.time))
    lay = out.layout
    firsts = out.acc[c, lay.event_base + lay.n_events:lay.event_base + 2 * lay.n_events]
    for kind, (start, count) in lay.event_slices().items():
        for j in range(count):
            first = firsts[start + j]
            if math.isfinite(first):
                findings.append(Finding("warning", kind, str(j), kind, float(first)))
    findings += stability_findings(line, plan=plan)
    return Verdict.of(findings).status, float(out.t_fail[c])


def _metric_arrays(out: BatchOutput) -> dict[str, np.ndarray]:
    """Metrics (``METRICS``) per case of a batch from its accumulators."""
    lay, acc = out.layout, out.acc
    s = lay.n_spans

    def block(b: int) -> np.ndarray:
        return acc[:, b * s:(b + 1) * s]

    n_rec = acc[:, -1:]
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


def _dataset(plans: list[Plan], cases: Sequence[Mapping[str, object]],
             outputs: list[tuple[list[int], BatchOutput]], duration: float, trace_every: int,
             n_trace: int, substeps: list[int]) -> Any:
    import xarray as xr

    line = plans[0].line
    n_c = len(plans)
    dims = {"span": line.n_spans, "drive": len(line.drives), "node": line.n_nodes}
    data = {name: np.full((n_c, dims[dim]), math.nan) for name, (dim, _, _) in METRICS.items()}
    status = np.empty(n_c, dtype=object)
    t_fail = np.full(n_c, math.nan)
    traces = np.full((n_c, n_trace, line.n_spans), math.nan) if n_trace else None
    loadcell = np.zeros(line.n_spans, dtype=bool)
    for zone in line.zones:
        loadcell[zone.loadcell] = True
    for idx, out in outputs:
        arrays = _metric_arrays(out)
        for name in METRICS:
            data[name][idx] = arrays[name]
        for j, c in enumerate(idx):
            status[c], t_fail[c] = case_status(plans[c], out, j)
        if traces is not None:
            traces[idx] = out.traces
    for name in ("tension_rms_error", "tension_peak_error", "settling_time"):
        data[name][:, ~loadcell] = math.nan
    names = {"span": [line.span_name(k) for k in range(line.n_spans)],
             "drive": [line.node_name(i) for i in line.drives],
             "node": [line.node_name(i) for i in range(line.n_nodes)]}
    variables = {name: xr.Variable(("case", dim), data[name],
                                   attrs={"units": units, "long_name": text})
                 for name, (dim, units, text) in METRICS.items()}
    variables["status"] = xr.Variable(("case",), status.astype(str),
                                      attrs={"long_name": "verdict status of the run"})
    variables["failure_time"] = xr.Variable(("case",), t_fail, attrs={
        "units": "s", "long_name": "time the run stopped early (NaN: it ran to the end)"})
    variables["substeps"] = xr.Variable(("case",), np.array(substeps), attrs={
        "long_name": "RK4 sub-steps per controller period"})
    coords: dict[str, Any] = {"case": np.arange(n_c), **names}
    paths = list(dict.fromkeys(p for case in cases for p in case))
    for path in paths:
        coords[path] = ("case", _coordinate([spec_value(p.line, path) for p in plans]),
                        {"units": "SI", "long_name": f"line parameter {path}"})
    if traces is not None:
        dt = plans[0].dt
        coords["time"] = ("time", np.arange(n_trace) * trace_every * dt, {"units": "s"})
        variables["tension"] = xr.Variable(("case", "time", "span"), traces,
                                           attrs={"units": "N", "long_name": "span tension"})
    ds = xr.Dataset(variables, coords=coords)
    ds.attrs.update({"line": line.name, "duration": duration, "parameters": list(paths)})
    return ds


def sweep(line: Line | str | Path, values: Mapping[str, Sequence[object]], *,
          duration: float | str | None = None, scenario: str | None = None,
          record: float | str | None = None, mode: str = "grid",
          workers: int | None = None) -> Any:
    """Simulate ``line`` over parameter values: ``{path: [v1, v2, ...]}`` (paths as in
    ``Line.replace``, values with units as a line file takes them). ``mode`` "grid" runs every
    combination (the last path varies fastest), "zip" the i-th value of every path together.
    Returns the Dataset of ``run_cases``; its attribute ``mode`` and, for a grid, ``shape``."""
    paths = list(values)
    columns = [list(values[p]) for p in paths]
    if mode == "grid":
        combos = list(itertools.product(*columns))
    elif mode == "zip":
        if len({len(c) for c in columns}) > 1:
            counts = ", ".join(f"{p}: {len(c)}" for p, c in zip(paths, columns, strict=True))
            raise ValueError(f"mode='zip' needs as many values for every path, got {counts}")
        combos = list(zip(*columns, strict=True))
    else:
        raise ValueError(f"mode must be 'grid' or 'zip', got {mode!r}")
    cases = [dict(zip(paths, combo, strict=True)) for combo in combos]
    ds = run_cases(line, cases, duration=duration, scenario=scenario, record=record,
                   workers=workers)
    ds.attrs["mode"] = mode
    if mode == "grid":
        ds.attrs["shape"] = [len(c) for c in columns]
    return ds


def monte_carlo(line: Line | str | Path, distributions: Mapping[str, Any], n: int, *,
                seed: int, duration: float | str | None = None, scenario: str | None = None,
                record: float | str | None = None, workers: int | None = None) -> Any:
    """``n`` runs of ``line`` with parameters drawn from ``distributions`` ({path: ``"normal(9
    kN, 5 %)"``, ``"uniform(0.1, 0.3)"``, ``"lognormal(9 kN, 5 %)"`` or a scipy.stats frozen
    distribution in SI}), all drawn up front from ``numpy.random.default_rng(seed)`` so the
    result does not depend on ``workers``. Returns the Dataset of ``run_cases``."""
    samples = draw(distributions, n, seed)
    cases = [{p: float(samples[p][c]) for p in samples} for c in range(n)]
    ds = run_cases(line, cases, duration=duration, scenario=scenario, record=record,
                   workers=workers)
    ds.attrs.update({"mode": "monte_carlo", "seed": seed})
    return ds
