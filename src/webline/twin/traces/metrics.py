"""Error metrics of simulated against measured signals, one row per signal."""

from __future__ import annotations

from typing import Any

import numpy as np

from webline.twin.traces.weights import noise_level

#: R² is left blank (NaN, as the NRMSE of a constant signal) where the measured signal
#: varies about its mean by no more than this many times its noise level: a flat signal's
#: "total variation" is its noise, and 1 - SSE/SST then reads as -1e12 for a good match
FLAT = 2.0

#: the columns of ``signal_metrics``'s table
COLUMNS = ("signal", "unit", "points", "rms", "max_abs", "nrmse", "bias", "r2")


def one_signal(simulated: np.ndarray, measured: np.ndarray) -> dict[str, float]:
    """Metrics of ``simulated - measured`` over the points where both are finite: RMS, max
    abs error, bias (mean error) [the signal's unit], NRMSE (RMS over the measured range),
    R² (1 - residual over total sum of squares of the measured signal about its mean; NaN
    for a flat signal, whose standard deviation is at most ``FLAT`` noise levels)."""
    ok = np.isfinite(simulated) & np.isfinite(measured)
    e, y = simulated[ok] - measured[ok], measured[ok]
    if not len(e):
        return {"points": 0, "rms": np.nan, "max_abs": np.nan, "nrmse": np.nan,
                "bias": np.nan, "r2": np.nan}
    rms = float(np.sqrt(np.mean(e**2)))
    spread = float(np.ptp(y))
    total = float(np.sum((y - y.mean()) ** 2))
    if total <= len(y) * (FLAT * noise_level(y)) ** 2:
        total = 0.0  # a flat signal: no variation for R² to explain
    return {"points": int(ok.sum()), "rms": rms, "max_abs": float(np.max(np.abs(e))),
            "nrmse": rms / spread if spread > 0 else np.nan, "bias": float(np.mean(e)),
            "r2": 1.0 - float(np.sum(e**2)) / total if total > 0 else np.nan}


def signal_metrics(simulated: dict[str, np.ndarray], measured: dict[str, np.ndarray],
                   units: dict[str, str]) -> Any:
    """A tidy ``pandas.DataFrame`` (``COLUMNS``), one row per signal in both, SI units."""
    import pandas as pd

    rows = [{"signal": name, "unit": units.get(name, ""),
             **one_signal(simulated[name], measured[name])}
            for name in measured if name in simulated]
    return pd.DataFrame(rows, columns=list(COLUMNS))
