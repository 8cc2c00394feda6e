"""Model checks of a fit (issue 36 item 6), what a system-identification user expects from
``resid``: per signal, whether its residuals are white (a Ljung-Box test over the first
``LAGS`` lags), their correlation time and the window where they are largest; per drive,
whether its torque residual correlates with its roller's speed or acceleration (a friction
law, a transmission or a lag the line file lacks shows there). The findings are cautions:
where one is strong, the model likely lacks something the data show."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace

import numpy as np

from webline.twin.fitting.intervals import correlation_time

#: lags of the whiteness test
LAGS = 20
#: a signal's residuals are "not white" below this p-value of the Ljung-Box statistic
P_WHITE = 1e-3
#: an input-residual correlation is named when |ρ| exceeds this and 4/√(effective points)
RHO = 0.3
#: the input-residual correlation is searched over lags up to this [s]
MAX_LAG = 0.1
#: the window over which the largest residual is located [s]
WINDOW = 0.5
#: correlated residuals whose RMS over the worst window exceeds this many noise levels are
#: a model that lacks something (a correct model's windows stay near 1.2 at 200 Hz)
LOCAL_MISFIT = 2.0


@dataclass(frozen=True)
class SignalCheck:
    """One signal: residual RMS [noise levels], correlation time [s], Ljung-Box p-value,
    the window [s] of the largest residual RMS, and its RMS there [noise levels]."""

    signal: str
    rms: float
    correlation_time: float
    p_white: float
    window: tuple[float, float]
    window_rms: float


@dataclass(frozen=True)
class ModelChecks:
    """Per signal checks, the findings in words and those (``serious``) that say the model
    lacks something: correlated residuals of more than ``LOCAL_MISFIT`` noise levels over a
    window."""

    signals: tuple[SignalCheck, ...]
    findings: tuple[str, ...]
    serious: tuple[str, ...] = ()


def _ljung_box(e: np.ndarray) -> float:
    """p-value of white noise for ``e`` (finite) over ``LAGS`` lags."""
    from scipy.stats import chi2

    n = len(e)
    if n <= LAGS + 2:
        return math.nan
    e = e - e.mean()
    denom = float(e @ e)
    if denom <= 0:
        return 1.0
    rho = _lagged(e, e, LAGS)[LAGS + 1 :] / denom
    q = n * (n + 2) * float(np.sum(rho**2 / (n - np.arange(1, LAGS + 1))))
    return float(chi2.sf(q, LAGS))


def _lagged(e: np.ndarray, u: np.ndarray, max_lag: int) -> np.ndarray:
    """Σₜ e[t + k] u[t] for k = -max_lag..max_lag (zero outside the records), by FFT: one
    product of two transforms instead of a dot product per lag (a 60 s record at 1 kHz
    has 60 000 points)."""
    n = len(e)
    size = 1 << (n + max_lag).bit_length()
    c = np.fft.irfft(np.fft.rfft(e, size) * np.conj(np.fft.rfft(u, size)), size)
    return np.concatenate([c[size - max_lag :], c[: max_lag + 1]])


def _cross(e: np.ndarray, u: np.ndarray, max_lag: int) -> tuple[float, int]:
    """Largest |correlation| of ``e`` with ``u`` shifted by -max_lag..max_lag samples
    (positive: ``u`` leads) and its lag."""
    ok = np.isfinite(e) & np.isfinite(u)
    e, u = np.where(ok, e, 0.0), np.where(ok, u, 0.0)
    e, u = e - e[ok].mean(), u - u[ok].mean()
    se, su = float(np.sqrt(e @ e)), float(np.sqrt(u @ u))
    if se <= 0 or su <= 0:
        return 0.0, 0
    max_lag = min(max_lag, len(e) - 1)
    c = _lagged(e, u, max_lag)
    best = int(np.argmax(np.abs(c)))
    return float(c[best]) / (se * su), best - max_lag


def model_checks(
    time: np.ndarray, residuals: Mapping[str, np.ndarray], measured: Mapping[str, np.ndarray]
) -> ModelChecks:
    """The checks of the module docstring on weighted ``residuals`` (noise levels, per
    signal, at the compared points ``time`` [s]) and the ``measured`` signals [SI]."""
    dt = float(np.median(np.diff(time))) if len(time) > 1 else 1.0
    rows, findings, serious = [], [], []
    width = max(1, round(WINDOW / dt))
    for name, r in residuals.items():
        ok = np.isfinite(r)
        if ok.sum() < 8:
            continue
        tau = correlation_time(r)
        p = _ljung_box(r[ok])
        filled = np.where(ok, r, 0.0) ** 2
        moving = np.convolve(filled, np.ones(width) / width, mode="valid")
        k = int(np.argmax(moving)) if len(moving) else 0
        rows.append(
            SignalCheck(
                name,
                float(np.sqrt(np.mean(r[ok] ** 2))),
                tau * dt,
                p,
                (float(time[k]), float(time[min(k + width, len(time) - 1)])),
                float(np.sqrt(moving[k])) if len(moving) else math.nan,
            )
        )
        if p < P_WHITE and tau > 2.0:
            findings.append(
                f"{name}: residuals not white (correlated over {tau * dt:.3g} s, "
                f"largest {rows[-1].window_rms:.3g} x the noise in "
                f"{rows[-1].window[0]:.3g} .. {rows[-1].window[1]:.3g} s)"
            )
            if rows[-1].window_rms > LOCAL_MISFIT:
                serious.append(findings[-1])
        if name.startswith("torque[") and name.endswith("]"):
            speed = measured.get("speed[" + name[7:])
            if speed is None:
                continue
            points = max(1.0, ok.sum() / max(tau, 1.0))
            limit = max(RHO, 4.0 / math.sqrt(points))
            for what, u in (("speed", speed), ("acceleration", np.gradient(speed, dt))):
                rho, lag = _cross(r, u, max(1, round(MAX_LAG / dt)))
                if abs(rho) > limit:
                    findings.append(
                        f"{name}'s residual correlates with its roller's {what} "
                        f"(ρ = {rho:+.2f} at lag {lag * dt * 1e3:.3g} ms): a "
                        f"friction law, a transmission or a lag the line file "
                        f"lacks?"
                    )
    rows.sort(key=lambda c: -c.rms)
    return ModelChecks(tuple(rows), tuple(findings), tuple(serious))


def merged_checks(parts: Sequence[tuple[str, ModelChecks]]) -> ModelChecks:
    """The checks of a fit's records as one: a single record's as they are; several
    records' with each signal and finding named ``LABEL: ...`` by its record, signals largest
    residual first."""
    if len(parts) == 1:
        return parts[0][1]

    def named(label: str, items: Sequence[str]) -> list[str]:
        return [f"{label}: {item}" for item in items]

    rows = [replace(c, signal=f"{label}: {c.signal}") for label, checks in parts
            for c in checks.signals]
    rows.sort(key=lambda c: -c.rms)
    return ModelChecks(tuple(rows),
                       tuple(f for label, c in parts for f in named(label, c.findings)),
                       tuple(f for label, c in parts for f in named(label, c.serious)))
