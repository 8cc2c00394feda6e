"""Decimation for plotting: keep each pixel's minimum and maximum so that peaks survive.

A 60 s run at 1 kHz has 60 000 records per signal; a figure is about 1000 pixels wide.
Plotting every record costs seconds and shows nothing more than the envelope of each pixel
column; plotting every n-th record hides short peaks (a tension spike of one tick).
"""

from __future__ import annotations

import numpy as np

#: pixel columns of a typical figure: the envelope keeps 2 points per column
DEFAULT_BINS = 1000


def envelope_indices(values: np.ndarray, bins: int = DEFAULT_BINS) -> np.ndarray:
    """Indices into ``values`` (1-D) that keep the minimum and the maximum of each of ``bins``
    equal slices, in time order, plus every sample of the short remainder. All indices when
    there are at most ``2 bins`` samples."""
    n = len(values)
    if n <= 2 * bins:
        return np.arange(n)
    width = n // bins
    blocks = values[:bins * width].reshape(bins, width)
    start = np.arange(bins) * width
    pairs = np.column_stack([start + np.argmin(blocks, axis=1),
                             start + np.argmax(blocks, axis=1)])
    return np.concatenate([np.sort(pairs, axis=1).ravel(), np.arange(bins * width, n)])


def envelope(time: np.ndarray, values: np.ndarray,
             bins: int = DEFAULT_BINS) -> tuple[np.ndarray, np.ndarray]:
    """(time, values) decimated to the min/max envelope of ``bins`` slices (1-D values)."""
    keep = envelope_indices(values, bins)
    return time[keep], values[keep]
