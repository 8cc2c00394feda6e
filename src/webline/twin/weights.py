"""How much each measured signal counts in a fit: its noise level."""

from __future__ import annotations

import math

import numpy as np

#: a noise level is at least this share of the signal's range (or of its magnitude, for a
#: constant signal): a noiseless trace (a simulation's own file) would otherwise weigh
#: without bound
FLOOR = 1e-3
#: MAD of a normal distribution = 0.6745 σ
MAD_TO_SIGMA = 1.0 / 0.6745


def noise_level(values: np.ndarray) -> float:
    """Standard deviation [the signal's unit] of white measurement noise on ``values``
    (samples at the file's rate): the robust scatter (MAD) of the second differences, which
    for white noise of variance σ² have variance 6σ² and remove a smooth trend, floored at
    ``FLOOR`` of the range."""
    y = values[np.isfinite(values)]
    if len(y) < 5:
        return math.nan
    d2 = np.diff(y, 2)
    sigma = MAD_TO_SIGMA * float(np.median(np.abs(d2 - np.median(d2)))) / math.sqrt(6.0)
    size = float(np.ptp(y)) or float(np.max(np.abs(y)))
    return max(sigma, FLOOR * size, 1e-12)


def noise_levels(signals: dict[str, np.ndarray]) -> dict[str, float]:
    """``noise_level`` of each signal."""
    return {name: noise_level(values) for name, values in signals.items()}
