"""``webline.twin.fitting.fit``: a line's uncertain parameters fitted to measured traces by
weighted least squares, with standard errors, 95 % intervals, correlations and a verdict on
which parameters the data can identify."""

from __future__ import annotations

import math
import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np

from webline.errors import ArgumentError
from webline.line import Line
from webline.twin.fitting.checks import ModelChecks, model_checks
from webline.twin.fitting.free import FreeParameter, parse_free
from webline.twin.fitting.identify import Identifiability, identifiability
from webline.twin.fitting.intervals import honest_covariance, intervals, profile_intervals
from webline.twin.fitting.starts import GlobalStage, global_stage, latin_starts
from webline.twin.fitting.verdict import Verdict, judge
from webline.twin.traces.drive import driven_line
from webline.twin.traces.measurements import Measurements
from webline.twin.traces.replay import as_measurements
from webline.twin.traces.runs import Run, common_substeps, compared_time, run_cases
from webline.twin.traces.single_path import single_path_line
from webline.twin.traces.weights import noise_levels

#: forward-difference step of the Jacobian, as a share of each parameter's bounds
FD_STEP = 1e-3
#: residual [noise levels] of a point a failed simulation did not reach
FAILED_RESIDUAL = 1e3
#: the first stage compares means over windows of this length [s]: an oscillation whose
#: phase shifts with a parameter (a light roller ringing on its spans) makes the residuals
#: of single samples a landscape of narrow valleys; its means lead into the right one, and
#: the second stage then fits every sample from there
SMOOTH_SECONDS = 0.1
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

    ``value`` (a parameter the data do not identify keeps the line's: ``raw_value`` holds
    the optimiser's number for it), ``stderr`` (``twin.fitting.intervals``: a batch-means
    sandwich over blocks of the residuals' correlation time, at least the noise-only error
    times the residual scale where it exceeds 1; ``stderr_noise`` the noise-only error
    (JᵀJ)⁻¹ of earlier versions), ``ci95`` (value ± t₀.₉₇₅ · stderr with
    ``effective_points`` - n degrees of freedom: the blocks; one-sided at a bound; the
    bounds for a parameter the data do not identify: ``interval_kind`` says which,
    ``at_bound`` "low"/"high"/"") per parameter; ``correlation`` (n × n);
    ``correlation_time`` [s] of the residuals (the longest of the signals');
    ``identifiability`` (which parameters the data cannot separate, and why);
    ``simulations`` run; ``cost`` (½Σr², r in noise levels); ``converged`` (scipy's
    convergence test was met);
    ``residual_scale`` √(Σr²/(m - n)): about 1 where the residuals are the signals' noise, more
    where the model misses something (the intervals then assume it does not);
    ``noise`` the noise level [SI] each signal was weighted by; ``before`` / ``after`` the
    compared signals with the line's and the fitted values; ``fitted_line`` the line as
    loaded (no scenario) with the identified values; ``global_stage`` (None for one start);
    ``verdict`` good / poor / failed with its reasons (``twin.fitting.verdict``);
    ``checks`` the residuals' whiteness and input correlation (``twin.fitting.checks``)."""

    line: Line
    fitted_line: Line
    data: Measurements
    parameters: tuple[FreeParameter, ...]
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
    noise: dict[str, float]
    signals: tuple[str, ...]
    before: Run
    after: Run
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
    def time(self) -> np.ndarray:
        """The compared points [s]."""
        return compared_time(self.data)

    def residuals(self) -> dict[str, np.ndarray]:
        """Simulated with the fitted values minus measured, per signal [SI]."""
        return {n: self.after.values[n] - self.data.signals[n][::self.data.stride]
                for n in self.signals}

    def table(self) -> Any:
        """One row per parameter: path, unit, line value, fitted value, stderr, ci95 low and
        high, identifiable, why not (SI), as a ``pandas.DataFrame``."""
        import pandas as pd

        return pd.DataFrame([{
            "parameter": p.path, "unit": p.unit, "line value": p.start,
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
                rows.append(f"  {p.path} = {self.value[i]:.4g} {p.unit} ± {self.stderr[i]:.2g} "
                            f"(95 %: {self.ci95[i, 0]:.4g} .. {self.ci95[i, 1]:.4g}{mark})")
            else:
                rows.append(f"  {p.path}: not identifiable from this data "
                            f"({self.identifiability.reasons[i]})")
        return (f"<webline Fit of {Path(self.data.source).name}: {len(self.parameters)} "
                f"parameters, {self.simulations} simulations, cost {self.cost:.4g}, residuals "
                f"{self.residual_scale:.3g} x the noise, "
                f"{'converged' if self.converged else 'not converged'}"
                + (f", {self.global_stage.summary()}" if self.global_stage else "")
                + ">\n" + "\n".join(rows) + "\n" + self.verdict.line()
                + "".join(f"\nmodel check: {f}" for f in self.checks.findings))


def fit(line: Line | str | Path, data: Measurements | str | Path,
        free: Mapping[str, object], *, scenario: str | None = None,
        signals: Sequence[str] | None = None, max_simulations: int = 400,
        workers: int | None = 1, starts: int = STARTS, seed: int = 0,
        profile: bool = False) -> FitResult:
    """Fit the ``free`` parameters of ``line`` ({path: "LOW .. HIGH UNIT"}, paths as
    ``Line.replace`` takes them, ``*`` for every element: ``rollers.*.friction``) to the
    measured traces ``data`` (``Measurements`` or a file, see ``load_measurements``).

    The line is driven by the logged references (``replay``) and simulated over the record;
    the residuals are simulated - measured at the file's own sample times, each signal
    divided by its noise level (``twin.traces.weights.noise_levels``: from the scatter of second
    differences, floored at 0.1 % of its range), so every signal counts by its information.
    scipy's ``least_squares`` (trust region reflective, bounds, parameters scaled to their
    bounds) minimises them; its Jacobian is taken by forward differences (step ``FD_STEP``
    of each range), the n perturbed cases run as one batch (``workers`` threads; the
    compiled loop holds the GIL, so 1 by default). Stops after about ``max_simulations``
    simulations. ``signals`` limits the compared signals (default: every measured one).

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
    line = original = single_path_line(line, "fit")
    if scenario is not None:
        line = line.with_scenario(scenario)
    data = as_measurements(data, line)
    driven = driven_line(data, line).line
    params = parse_free(driven, free)
    if not params:
        raise ArgumentError("free: no parameter to fit")
    names = list(signals) if signals is not None else data.names
    unknown = [n for n in names if n not in data.signals]
    if unknown:
        raise ArgumentError(f"signals: {unknown[0]!r} is not in {data.source}")
    measured = np.stack([data.signals[n][::data.stride] for n in names])
    noise = noise_levels({n: data.signals[n][::data.stride] for n in names})
    weight = np.array([1.0 / noise[n] for n in names])[:, None]
    if np.isfinite(measured).sum() <= len(params):
        raise ArgumentError(f"{data.source}: {int(np.isfinite(measured).sum())} measured "
                            f"points cannot fit {len(params)} parameters")
    corners = [{p.path: v} for p in params for v in (p.low, p.high)]
    substeps = common_substeps(driven, [{p.path: p.start for p in params}, *corners])
    count = [0]
    memo: dict[bytes, tuple[np.ndarray, Run]] = {}

    def cases(xs: list[np.ndarray]) -> list[tuple[np.ndarray, Run]]:
        """(weighted residuals: signals x points, NaN where nothing was measured; run)."""
        todo = [x for x in dict.fromkeys(x.tobytes() for x in xs) if x not in memo]
        runs = run_cases(driven, data, names, [
            {p.path: p.unscaled(float(v))
             for p, v in zip(params, np.frombuffer(x), strict=True)} for x in todo],
            workers, substeps)
        count[0] += len(todo)
        for x, run in zip(todo, runs, strict=True):
            simulated = np.stack([run.values[n] for n in names])
            r = np.where(np.isfinite(simulated), (simulated - measured) * weight,
                         FAILED_RESIDUAL)
            memo[x] = (np.where(np.isfinite(measured), r, np.nan), run)
        if len(memo) > 4 * len(params) + 8:  # keep memory bounded: drop the oldest
            wanted = {x.tobytes() for x in xs}
            for key in [k for k in memo if k not in wanted][:len(memo) - 2 * len(params)]:
                del memo[key]
        return [memo[x.tobytes()] for x in xs]

    def stage(window: int, x0: np.ndarray, budget: int) -> Any:
        def residual(x: np.ndarray) -> np.ndarray:
            return blocks(cases([np.array(x, dtype=float)])[0][0], window)

        def jacobian(x: np.ndarray) -> np.ndarray:
            x = np.array(x, dtype=float)
            steps = np.where(x + FD_STEP <= 1.0, FD_STEP, -FD_STEP)
            out = cases([x, *(x + np.eye(len(x))[i] * steps[i] for i in range(len(x)))])
            base = blocks(out[0][0], window)
            return np.column_stack([(blocks(out[i + 1][0], window) - base) / steps[i]
                                    for i in range(len(x))])

        from scipy.optimize import least_squares

        solution = least_squares(residual, x0, jac=jacobian, bounds=(0.0, 1.0),
                                 method="trf", x_scale=1.0,
                                 max_nfev=max(2, budget // (len(params) + 1)),
                                 ftol=1e-10, xtol=1e-8, gtol=1e-10)
        solution.jac_at = jacobian
        return solution

    x0 = np.clip([p.scaled(p.start) for p in params], 0.0, 1.0)
    before = cases([x0])[0][1]
    window = max(1, round(SMOOTH_SECONDS / data.sample_period))
    found: GlobalStage | None = None
    if starts > 1:
        def local(start: np.ndarray) -> tuple[np.ndarray, float]:
            end = stage(window, start, START_ITERATIONS * (len(params) + 1))
            return np.asarray(end.x), float(end.cost)

        def screen(xs: np.ndarray) -> np.ndarray:
            # batches of a Jacobian's size: the memo then holds no more runs than a fit's
            size = len(params) + 1
            return np.array([0.5 * float(np.sum(blocks(out[0], window) ** 2))
                             for k in range(0, len(xs), size)
                             for out in cases(list(xs[k:k + size]))])

        spent = count[0]
        chosen = latin_starts(x0, starts, screen, seed)
        found = global_stage(chosen, local, lambda: count[0])
        found = replace(found, simulations=count[0] - spent)
        x_start = found.best
        spent = count[0]
    else:
        spent = 0
        x_start = x0
    if window > 1:
        x_start = stage(window, x_start, max_simulations // 2).x
    solution = stage(1, x_start, max_simulations - (count[0] - spent))
    x = np.asarray(solution.x)
    r = blocks(cases([x])[0][0], 1)
    after = cases([x])[0][1]
    jac = solution.jac_at(x)
    m, n = len(r), len(params)
    spans = np.array([p.high - p.low for p in params])
    variance = float(r @ r) / max(1, m - n)
    honest = honest_covariance(jac, cases([x])[0][0])
    stderr = honest.stderr * spans
    value = np.array([p.unscaled(float(v)) for p, v in zip(params, x, strict=True)])
    low, high = np.array([p.low for p in params]), np.array([p.high for p in params])
    ci95, kinds, at = intervals(value, stderr, low, high, honest.blocks - n)
    if profile:
        scaled, kinds = profile_intervals(lambda v: blocks(cases([np.array(v, float)])[0][0], 1),
                                          x, honest.stderr, honest.stderr_noise,
                                          honest.blocks - n)
        ci95 = low[:, None] + scaled * spans[:, None]
    scale = np.sqrt(np.clip(np.diag(honest.cov), 1e-300, None))
    correlation = np.clip(honest.cov / np.outer(scale, scale), -1.0, 1.0)
    ident = identifiability(jac, ci95, low, high, correlation, [p.path for p in params])
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
    fitted = driven_fitted(original, params, value, ident.identifiable)
    weighted = cases([x])[0][0]
    checks = model_checks(compared_time(data), dict(zip(names, weighted, strict=True)),
                          dict(zip(names, measured, strict=True)))
    verdict = judge(residual_scale=math.sqrt(variance), converged=bool(solution.status > 0),
                    message=str(solution.message), failure=after.failure,
                    at_bound=[(p.path, a) for p, a in zip(params, at, strict=True) if a],
                    reached=found.reached if found else None,
                    starts=found.count if found else None, lacks=checks.serious)
    return FitResult(
        line=line, fitted_line=fitted, data=data, parameters=tuple(params), value=value,
        raw_value=raw,
        stderr=stderr, ci95=ci95, correlation=correlation, identifiability=ident,
        simulations=count[0], cost=0.5 * float(r @ r), converged=bool(solution.status > 0),
        message=str(solution.message), residual_scale=math.sqrt(variance),
        seconds=time.perf_counter() - started, noise=noise,
        signals=tuple(names), before=before, after=after, global_stage=found,
        verdict=verdict, interval_kind=tuple(kinds), at_bound=tuple(at),
        stderr_noise=honest.stderr_noise * spans, effective_points=honest.blocks,
        correlation_time=honest.tau * data.sample_period, checks=checks)


def driven_fitted(line: Line, params: Sequence[FreeParameter], value: np.ndarray,
                  identifiable: np.ndarray) -> Line:
    """``line`` (as loaded, without the scenario the fit ran) with each identifiable parameter
    set to its fitted value (the others keep the line's: the data gave them no confident
    value)."""
    changes = {p.path: float(v) for p, v, ok in zip(params, value, identifiable, strict=True)
               if ok and math.isfinite(v)}
    return line.replace(changes) if changes else line
