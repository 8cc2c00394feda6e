"""``webline.twin.fitting.fit``: a line's uncertain parameters fitted to measured traces,
one record or several at once, by weighted least squares, with standard errors, 95 %
intervals, correlations, a verdict on which parameters the data can identify and one on
the fit itself."""

from __future__ import annotations

import math
import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from webline.errors import ArgumentError
from webline.line import Line
from webline.model.lines import load_line
from webline.twin.fitting.checks import ModelChecks, merged_checks, model_checks
from webline.twin.fitting.free import FreeParameter
from webline.twin.fitting.identify import Identifiability, identifiability
from webline.twin.fitting.intervals import honest_covariance, intervals, profile_intervals
from webline.twin.fitting.records import (
    FitRecord,
    RecordFit,
    prepare_records,
    residual_scale,
    scenario_list,
)
from webline.twin.fitting.shared import coordinates
from webline.twin.fitting.starts import GlobalStage, global_stage, latin_starts
from webline.twin.fitting.verdict import Verdict, judge
from webline.twin.traces.measurements import Measurements
from webline.twin.traces.runs import Run, common_substeps, run_cases

if TYPE_CHECKING:
    from webline.model.web_graph import BranchedLine

#: forward-difference step of the Jacobian, as a share of each parameter's bounds
FD_STEP = 1e-3
#: starts of the global stage by default (the line's values and 7 Latin-hypercube points)
STARTS = 8
#: least-squares iterations each start of the global stage may take, at most
START_ITERATIONS = 8


def blocks(r: np.ndarray, window: int) -> np.ndarray:
    """Residuals (signals x points, NaN: not measured) as means over ``window`` points, times
    √(points averaged), so each stays of unit variance under white noise; flattened, NaN
    left out."""
    if window <= 1:
        flat = r.ravel()
        return flat[np.isfinite(flat)]
    n = r.shape[1] // window * window
    parts = r[:, :n].reshape(r.shape[0], -1, window)
    counts = np.isfinite(parts).sum(axis=2)
    with np.errstate(invalid="ignore", divide="ignore"):
        means = np.nansum(parts, axis=2) / counts * np.sqrt(counts)
    flat = means.ravel()
    return flat[np.isfinite(flat)]


@dataclass(frozen=True)
class FitResult:
    """A fit's outcome; values and intervals in SI (``FreeParameter.unit``).

    ``parameters`` the fitted coordinates: the shared ones, then each record's own
    (``owner``: the index of its record in ``records``, None where shared; ``labels``: the
    path, or ``PATH@RECORD``). Per coordinate: ``value`` (a parameter the data do not
    identify keeps the line's: ``raw_value`` holds the optimiser's number for it),
    ``stderr`` (``twin.fitting.intervals``: a batch-means sandwich over blocks of the
    residuals' correlation time, at least the noise-only error times the residual scale
    where it exceeds 1; ``stderr_noise`` the noise-only error (JᵀJ)⁻¹), ``ci95`` (value ±
    t₀.₉₇₅ · stderr with ``effective_points`` - n degrees of freedom: the blocks; one-sided
    at a bound; the bounds for a parameter the data do not identify: ``interval_kind`` says
    which, ``at_bound`` "low"/"high"/""); ``correlation`` (n × n); ``identifiability``
    (which parameters the data cannot separate, and why).

    Joint over every record: ``simulations`` run; ``cost`` (½Σr², r in noise levels);
    ``converged`` (scipy's test was met); ``residual_scale`` √(Σr²/(m - n)): about 1 where
    the residuals are the signals' noise, more where the model misses something;
    ``correlation_time`` [s] of the residuals (the longest record's); ``global_stage``
    (None for one start); ``verdict`` good / poor / failed with its reasons
    (``twin.fitting.verdict``: a record whose own residual scale is too large makes it
    poor); ``checks`` the residuals' whiteness and input correlation of every record
    (``twin.fitting.checks``, ``LABEL: `` before each signal where there are several).

    Per record (``records``, ``twin.fitting.records.RecordFit``): its data, residual scale,
    runs before and after, checks. ``fitted_line``: the line as given (no scenario) with the
    identified shared values (a per-record value belongs to its record, not to the line).
    ``data``, ``before``, ``after``, ``noise``, ``signals``, ``time`` and ``residuals()``
    are the first record's: the only one of a one-record fit."""

    line: Line | BranchedLine
    fitted_line: Line | BranchedLine
    records: tuple[RecordFit, ...]
    parameters: tuple[FreeParameter, ...]
    owner: tuple[int | None, ...]
    labels: tuple[str, ...]
    value: np.ndarray
    raw_value: np.ndarray
    stderr: np.ndarray
    ci95: np.ndarray
    correlation: np.ndarray
    identifiability: Identifiability
    simulations: int
    cost: float
    converged: bool
    message: str
    residual_scale: float
    seconds: float
    global_stage: GlobalStage | None
    verdict: Verdict
    interval_kind: tuple[str, ...]
    at_bound: tuple[str, ...]
    stderr_noise: np.ndarray
    effective_points: int
    correlation_time: float
    checks: ModelChecks

    @property
    def identifiable(self) -> np.ndarray:
        """Whether the data identify each parameter."""
        return self.identifiability.identifiable

    @property
    def data(self) -> Measurements:
        return self.records[0].data

    @property
    def before(self) -> Run:
        return self.records[0].before

    @property
    def after(self) -> Run:
        return self.records[0].after

    @property
    def noise(self) -> dict[str, float]:
        return self.records[0].noise

    @property
    def signals(self) -> tuple[str, ...]:
        return self.records[0].signals

    @property
    def time(self) -> np.ndarray:
        """The first record's compared points [s]."""
        return self.records[0].time

    def residuals(self) -> dict[str, np.ndarray]:
        """The first record's simulated with the fitted values minus measured [SI]."""
        return self.records[0].residuals()

    @property
    def sources(self) -> str:
        """The records' file names, joined by " + "."""
        return " + ".join(r.label for r in self.records)

    def table(self) -> Any:
        """One row per parameter: label (path, or PATH@RECORD), unit, line value, fitted
        value, stderr, ci95 low and high, identifiable, why not (SI), as a
        ``pandas.DataFrame``."""
        import pandas as pd

        return pd.DataFrame([{
            "parameter": self.labels[i], "unit": p.unit, "line value": p.start,
            "fitted": self.value[i], "stderr": self.stderr[i], "ci95 low": self.ci95[i, 0],
            "ci95 high": self.ci95[i, 1], "identifiable": bool(self.identifiable[i]),
            "why not": self.identifiability.reasons[i]}
            for i, p in enumerate(self.parameters)])

    def __repr__(self) -> str:
        rows = []
        for i, p in enumerate(self.parameters):
            if self.identifiable[i]:
                side = self.at_bound[i]
                mark = (f", one-sided: at its {'lower' if side == 'low' else 'upper'} bound"
                        if side else "")
                rows.append(f"  {self.labels[i]} = {self.value[i]:.4g} {p.unit} ± "
                            f"{self.stderr[i]:.2g} (95 %: {self.ci95[i, 0]:.4g} .. "
                            f"{self.ci95[i, 1]:.4g}{mark})")
            else:
                rows.append(f"  {self.labels[i]}: not identifiable from this data "
                            f"({self.identifiability.reasons[i]})")
        each = ("" if len(self.records) == 1 else "\n" + "\n".join(
            f"  record {r.label}: residuals {r.residual_scale:.3g} x the noise"
            for r in self.records))
        return (f"<webline Fit of {self.sources}: {len(self.parameters)} "
                f"parameters, {self.simulations} simulations, cost {self.cost:.4g}, residuals "
                f"{self.residual_scale:.3g} x the noise, "
                f"{'converged' if self.converged else 'not converged'}"
                + (f", {self.global_stage.summary()}" if self.global_stage else "")
                + ">" + each + "\n" + "\n".join(rows) + "\n" + self.verdict.line()
                + "".join(f"\nmodel check: {f}" for f in self.checks.findings))


def fit(line: Line | BranchedLine | str | Path,
        data: Measurements | str | Path | Sequence[Measurements | str | Path],
        free: Mapping[str, object], *, scenario: str | Sequence[str | None] | None = None,
        per_record: Sequence[str] = (), signals: Sequence[str] | None = None,
        max_simulations: int = 400, workers: int | None = 1, starts: int = STARTS,
        seed: int = 0, profile: bool = False) -> FitResult:
    """Fit the ``free`` parameters of ``line`` ({path: "LOW .. HIGH UNIT"}, paths as
    ``Line.replace`` takes them, ``*`` for every element: ``rollers.*.friction``) to the
    measured traces ``data``: one record (``Measurements`` or a file, see
    ``load_measurements``) or a list of them, fitted jointly.

    Each record is simulated with its own ``scenario`` (None or one name: every record's;
    a list: one per record, in order), driven by its own logged references (``replay``),
    from its own initial state; the parameters are shared by every record, except the
    patterns of ``free`` named in ``per_record``, fitted once per record (``PATH@RECORD``,
    RECORD the file's name). The residuals are simulated - measured at each file's own
    sample times, each signal divided by its noise level in its record
    (``twin.traces.weights.noise_levels``: from the scatter of second differences, floored
    at 0.1 % of its range), so every signal of every record counts by its information.
    scipy's ``least_squares`` (trust region reflective, bounds, parameters scaled to their
    bounds) minimises them all at once; its Jacobian is taken by forward differences (step
    ``FD_STEP`` of each range), the perturbed cases run as one batch per record
    (``workers`` threads; the compiled loop holds the GIL, so 1 by default; a record's
    case is run once for every point that agrees on its own coordinates). Stops after about
    ``max_simulations`` simulations. ``signals`` limits the compared signals (default:
    every measured one of each record).

    Before it, a global stage (``twin.fitting.starts``): with ``starts`` > 1, local fits of
    at most ``START_ITERATIONS`` iterations each (on the means of the first stage) from the
    line's values and the ``starts - 1`` best of ``SCREEN * (starts - 1)`` Latin-hypercube
    points over the bounds (``seed``); the best of them starts the local stages, and the
    result says how many reached the best cost. ``starts=1``: the line's values only.

    ``profile``: profile-likelihood intervals (``twin.fitting.intervals.profile_intervals``,
    for confidence regions that are not ellipsoids: each parameter's profile refits the
    others, some 2 x 12 short fits per parameter) instead of value ± t stderr.
    """
    started = time.perf_counter()
    original = load_line(line)
    items: list[Measurements | str | Path] = (
        list(data) if isinstance(data, list | tuple) else [data])  # type: ignore[list-item]
    if not items:
        raise ArgumentError("data: no record to fit")
    records = prepare_records(original, items, scenario_list(scenario, len(items)), signals)
    coords = coordinates(records, free, per_record)
    params = coords.parameters
    if not params:
        raise ArgumentError("free: no parameter to fit")
    points = sum(r.points for r in records)
    if points <= len(params):
        raise ArgumentError(f"{' + '.join(r.data.source for r in records)}: {points} "
                            f"measured points cannot fit {len(params)} parameters")
    own = [coords.of_record(k) for k in range(len(records))]
    substeps = []
    for k, record in enumerate(records):
        start = {params[i].path: params[i].start for i in own[k]}
        corners = [{params[i].path: v} for i in own[k] for v in (params[i].low, params[i].high)]
        substeps.append(common_substeps(record.driven, [start, *corners]))
    count = [0]
    memo: list[dict[bytes, tuple[np.ndarray, Run]]] = [{} for _ in records]

    def cases(xs: list[np.ndarray]) -> list[list[tuple[np.ndarray, Run]]]:
        """Per point of ``xs``, per record: (weighted residuals: signals x points, NaN where
        nothing was measured; run). A record's case runs once for every point that agrees on
        the coordinates acting on it."""
        out: list[list[tuple[np.ndarray, Run]]] = [[] for _ in xs]
        for k, record in enumerate(records):
            keys = [np.ascontiguousarray(x[own[k]], dtype=float).tobytes() for x in xs]
            todo = [key for key in dict.fromkeys(keys) if key not in memo[k]]
            runs = run_cases(record.driven, record.data, record.names,
                             [coords.case(k, np.frombuffer(key)) for key in todo],
                             workers, substeps[k])
            count[0] += len(todo)
            for key, run in zip(todo, runs, strict=True):
                memo[k][key] = (record.weighted(run), run)
            if len(memo[k]) > 4 * len(params) + 8:  # keep memory bounded: drop the oldest
                wanted = set(keys)
                old = [key for key in memo[k] if key not in wanted]
                for key in old[:len(memo[k]) - 2 * len(params)]:
                    del memo[k][key]
            for i, key in enumerate(keys):
                out[i].append(memo[k][key])
        return out

    def flat(parts: list[tuple[np.ndarray, Run]], smooth: bool) -> np.ndarray:
        """Every record's residuals in one vector (as means over each record's window in
        the first stage)."""
        return np.concatenate([blocks(r, record.window if smooth else 1)
                               for (r, _), record in zip(parts, records, strict=True)])

    def stage(smooth: bool, x0: np.ndarray, budget: int) -> Any:
        def residual(x: np.ndarray) -> np.ndarray:
            return flat(cases([np.array(x, dtype=float)])[0], smooth)

        def jacobian(x: np.ndarray) -> np.ndarray:
            x = np.array(x, dtype=float)
            steps = np.where(x + FD_STEP <= 1.0, FD_STEP, -FD_STEP)
            out = cases([x, *(x + np.eye(len(x))[i] * steps[i] for i in range(len(x)))])
            base = flat(out[0], smooth)
            return np.column_stack([(flat(out[i + 1], smooth) - base) / steps[i]
                                    for i in range(len(x))])

        from scipy.optimize import least_squares

        solution = least_squares(residual, x0, jac=jacobian, bounds=(0.0, 1.0),
                                 method="trf", x_scale=1.0,
                                 max_nfev=max(2, budget // (len(params) + 1)),
                                 ftol=1e-10, xtol=1e-8, gtol=1e-10)
        solution.jac_at = jacobian
        return solution

    x0 = np.clip([p.scaled(p.start) for p in params], 0.0, 1.0)
    before = [run for _, run in cases([x0])[0]]
    smoothing = any(record.window > 1 for record in records)
    found: GlobalStage | None = None
    if starts > 1:
        def local(start: np.ndarray) -> tuple[np.ndarray, float]:
            end = stage(True, start, START_ITERATIONS * (len(params) + 1))
            return np.asarray(end.x), float(end.cost)

        def screen(xs: np.ndarray) -> np.ndarray:
            # batches of a Jacobian's size: the memo then holds no more runs than a fit's
            size = len(params) + 1
            return np.array([0.5 * float(np.sum(flat(parts, True) ** 2))
                             for k in range(0, len(xs), size)
                             for parts in cases(list(xs[k:k + size]))])

        spent = count[0]
        chosen = latin_starts(x0, starts, screen, seed)
        found = global_stage(chosen, local, lambda: count[0])
        found = replace(found, simulations=count[0] - spent)
        x_start = found.best
        spent = count[0]
    else:
        spent = 0
        x_start = x0
    if smoothing:
        x_start = stage(True, x_start, max_simulations // 2).x
    solution = stage(False, x_start, max_simulations - (count[0] - spent))
    x = np.asarray(solution.x)
    parts = cases([x])[0]
    r = flat(parts, False)
    jac = solution.jac_at(x)
    m, n = len(r), len(params)
    spans = np.array([p.high - p.low for p in params])
    variance = float(r @ r) / max(1, m - n)
    weighted = [w for w, _ in parts]
    honest = honest_covariance(jac, weighted)
    stderr = honest.stderr * spans
    value = np.array([p.unscaled(float(v)) for p, v in zip(params, x, strict=True)])
    low, high = np.array([p.low for p in params]), np.array([p.high for p in params])
    ci95, kinds, at = intervals(value, stderr, low, high, honest.blocks - n)
    if profile:
        scaled, kinds = profile_intervals(lambda v: flat(cases([np.array(v, float)])[0], False),
                                          x, honest.stderr, honest.stderr_noise,
                                          honest.blocks - n)
        ci95 = low[:, None] + scaled * spans[:, None]
    scale = np.sqrt(np.clip(np.diag(honest.cov), 1e-300, None))
    correlation = np.clip(honest.cov / np.outer(scale, scale), -1.0, 1.0)
    ident = identifiability(jac, ci95, low, high, correlation, list(coords.labels))
    raw = value.copy()
    for i, p in enumerate(params):
        if not ident.identifiable[i]:
            # no confident value: the line's (within the bounds), the bounds as the interval
            # and at most the standard deviation of a value spread evenly over them
            value[i] = min(max(p.start, p.low), p.high)
            ci95[i] = (p.low, p.high)
            kinds[i], at[i] = "bounds", ""
            even = (p.high - p.low) / math.sqrt(12.0)
            stderr[i] = min(stderr[i], even) if math.isfinite(stderr[i]) else even
    taus = honest.taus or (honest.tau,)
    fits = tuple(_record_fit(record, before[k], parts[k], len(own[k]),
                             taus[k] * record.data.sample_period)
                 for k, record in enumerate(records))
    checks = merged_checks([(f.label, f.checks) for f in fits])
    failure = "; ".join(f"{f.label}: {f.after.failure}" if len(fits) > 1 else f.after.failure
                        for f in fits if f.after.failure)
    verdict = judge(residual_scale=math.sqrt(variance), converged=bool(solution.status > 0),
                    message=str(solution.message), failure=failure,
                    at_bound=[(label, a) for label, a in zip(coords.labels, at, strict=True)
                              if a],
                    reached=found.reached if found else None,
                    starts=found.count if found else None, lacks=checks.serious,
                    records=[(f.label, f.residual_scale) for f in fits])
    shared = coords.shared
    fitted = driven_fitted(original, [params[i] for i in shared], value[shared],
                           ident.identifiable[shared])
    return FitResult(
        line=original, fitted_line=fitted, records=fits, parameters=params,
        owner=coords.owner, labels=coords.labels, value=value, raw_value=raw,
        stderr=stderr, ci95=ci95, correlation=correlation, identifiability=ident,
        simulations=count[0], cost=0.5 * float(r @ r), converged=bool(solution.status > 0),
        message=str(solution.message), residual_scale=math.sqrt(variance),
        seconds=time.perf_counter() - started, global_stage=found,
        verdict=verdict, interval_kind=tuple(kinds), at_bound=tuple(at),
        stderr_noise=honest.stderr_noise * spans, effective_points=honest.blocks,
        correlation_time=max(f.correlation_time for f in fits), checks=checks)


def _record_fit(record: FitRecord, before: Run, part: tuple[np.ndarray, Run], acting: int,
                correlation: float) -> RecordFit:
    """What the fit gives for ``record``: ``part`` its (weighted residuals, run) at the
    fitted values, ``acting`` the parameters acting on it, ``correlation`` its residuals'
    correlation time [s]."""
    weighted, after = part
    checks = model_checks(record.data.time[::record.data.stride],
                          dict(zip(record.names, weighted, strict=True)), record.measured_signals())
    finite = weighted[np.isfinite(weighted)]
    return RecordFit(record, before, after, residual_scale(weighted, acting),
                     0.5 * float(finite @ finite), correlation, checks)


def driven_fitted(line: Line | BranchedLine, params: Sequence[FreeParameter],
                  value: np.ndarray, identifiable: np.ndarray) -> Line | BranchedLine:
    """``line`` (as loaded, without the scenario the fit ran) with each identifiable parameter
    set to its fitted value (the others keep the line's: the data gave them no confident
    value)."""
    changes = {p.path: float(v) for p, v, ok in zip(params, value, identifiable, strict=True)
               if ok and math.isfinite(v)}
    return line.replace(changes) if changes else line
