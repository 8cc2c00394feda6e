"""``webline.twin.fitting.fit``: a line's uncertain parameters fitted to measured traces by
weighted least squares, with standard errors, 95 % intervals, correlations and a verdict on
which parameters the data can identify."""

from __future__ import annotations

import itertools
import math
import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from webline.errors import ArgumentError
from webline.line import Line
from webline.twin.fitting.free import FreeParameter, parse_free
from webline.twin.fitting.identify import Identifiability, identifiability
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


def signal_rows(r: np.ndarray) -> list[np.ndarray]:
    """Per signal, the rows (in ``blocks(r, 1)``'s order) of its measured points."""
    counts = np.isfinite(r).sum(axis=1)
    edges = np.concatenate([[0], np.cumsum(counts)])
    return [np.arange(a, b) for a, b in itertools.pairwise(edges)]


def covariance(jac: np.ndarray, rows: list[np.ndarray], dof: int,
               r: np.ndarray) -> np.ndarray:
    """Covariance of the scaled parameters: the sandwich A⁻¹ (Σₛ vₛ JₛᵀJₛ) A⁻¹ with
    A = JᵀJ and vₛ the residual variance of signal s (its noise level as estimated from the
    data is only an estimate: a signal whose residuals are larger than its weight assumed
    counts with its own scatter), scaled by m / dof for the parameters fitted."""
    inverse = np.linalg.pinv(jac.T @ jac)
    middle = np.zeros_like(inverse)
    m = sum(len(idx) for idx in rows)
    for idx in rows:
        if len(idx):
            part = jac[idx]
            middle += float(np.mean(r[idx] ** 2)) * (part.T @ part)
    return inverse @ middle @ inverse * (m / max(1, dof))


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
    the optimiser's number for it), ``stderr`` (from ``covariance``: (JᵀJ)⁻¹ at the
    solution, each signal's part scaled by its own residual variance), ``ci95`` (value ±
    t₀.₉₇₅,m-n · stderr; the bounds for a parameter the data do not identify) per
    parameter; ``correlation`` (n × n);
    ``identifiability`` (which parameters the data cannot separate, and why);
    ``simulations`` run; ``cost`` (½Σr², r in noise levels); ``converged`` (scipy's
    convergence test was met);
    ``residual_scale`` √(Σr²/(m - n)): about 1 where the residuals are the signals' noise, more
    where the model misses something (the intervals then assume it does not);
    ``noise`` the noise level [SI] each signal was weighted by; ``before`` / ``after`` the
    compared signals with the line's and the fitted values; ``fitted_line`` the line as
    loaded (no scenario) with the identified values."""

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
                rows.append(f"  {p.path} = {self.value[i]:.4g} {p.unit} ± {self.stderr[i]:.2g} "
                            f"(95 %: {self.ci95[i, 0]:.4g} .. {self.ci95[i, 1]:.4g})")
            else:
                rows.append(f"  {p.path}: not identifiable from this data "
                            f"({self.identifiability.reasons[i]})")
        return (f"<webline Fit of {Path(self.data.source).name}: {len(self.parameters)} "
                f"parameters, {self.simulations} simulations, cost {self.cost:.4g}, residuals "
                f"{self.residual_scale:.3g} x the noise, "
                f"{'converged' if self.converged else 'not converged'}>\n" + "\n".join(rows))


def fit(line: Line | str | Path, data: Measurements | str | Path,
        free: Mapping[str, object], *, scenario: str | None = None,
        signals: Sequence[str] | None = None, max_simulations: int = 400,
        workers: int | None = 1) -> FitResult:
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
    coarse = stage(window, x0, max_simulations // 2) if window > 1 else None
    solution = stage(1, coarse.x if coarse is not None else x0,
                     max_simulations - count[0])
    x = np.asarray(solution.x)
    r = blocks(cases([x])[0][0], 1)
    after = cases([x])[0][1]
    jac = solution.jac_at(x)
    m, n = len(r), len(params)
    spans = np.array([p.high - p.low for p in params])
    variance = float(r @ r) / max(1, m - n)
    cov_x = covariance(jac, signal_rows(cases([x])[0][0]), m - n, r)
    stderr = np.sqrt(np.clip(np.diag(cov_x), 0.0, None)) * spans
    value = np.array([p.unscaled(float(v)) for p, v in zip(params, x, strict=True)])
    from scipy.stats import t as student

    half = float(student.ppf(0.975, max(1, m - n))) * stderr
    ci95 = np.column_stack([value - half, value + half])
    scale = np.sqrt(np.clip(np.diag(cov_x), 1e-300, None))
    correlation = np.clip(cov_x / np.outer(scale, scale), -1.0, 1.0)
    ident = identifiability(jac, ci95, np.array([p.low for p in params]),
                            np.array([p.high for p in params]), correlation,
                            [p.path for p in params])
    raw = value.copy()
    for i, p in enumerate(params):
        if not ident.identifiable[i]:
            # no confident value: the line's (within the bounds), the bounds as the interval
            # and at most the standard deviation of a value spread evenly over them
            value[i] = min(max(p.start, p.low), p.high)
            ci95[i] = (p.low, p.high)
            even = (p.high - p.low) / math.sqrt(12.0)
            stderr[i] = min(stderr[i], even) if math.isfinite(stderr[i]) else even
    fitted = driven_fitted(original, params, value, ident.identifiable)
    return FitResult(
        line=line, fitted_line=fitted, data=data, parameters=tuple(params), value=value,
        raw_value=raw,
        stderr=stderr, ci95=ci95, correlation=correlation, identifiability=ident,
        simulations=count[0], cost=0.5 * float(r @ r), converged=bool(solution.status > 0),
        message=str(solution.message), residual_scale=math.sqrt(variance),
        seconds=time.perf_counter() - started, noise=noise,
        signals=tuple(names), before=before, after=after)


def driven_fitted(line: Line, params: Sequence[FreeParameter], value: np.ndarray,
                  identifiable: np.ndarray) -> Line:
    """``line`` (as loaded, without the scenario the fit ran) with each identifiable parameter
    set to its fitted value (the others keep the line's: the data gave them no confident
    value)."""
    changes = {p.path: float(v) for p, v, ok in zip(params, value, identifiable, strict=True)
               if ok and math.isfinite(v)}
    return line.replace(changes) if changes else line
