"""Min/max decimation for plots keeps every peak and the time order."""

from __future__ import annotations

import numpy as np

from webline.sim.results.decimate import envelope, envelope_indices


def test_short_signals_are_kept_whole() -> None:
    assert np.array_equal(envelope_indices(np.arange(10.0), bins=5), np.arange(10))


def test_one_tick_spike_survives_and_order_is_kept() -> None:
    time = np.linspace(0.0, 60.0, 60_001)  # 60 s at 1 kHz
    values = np.sin(time)
    values[31_337] = 50.0  # a one-tick spike
    values[7] = -50.0
    t, y = envelope(time, values, bins=1000)
    assert len(t) <= 2 * 1000 + 60_001 // 1000 + 1
    assert y.max() == 50.0 and y.min() == -50.0
    assert np.all(np.diff(t) > 0)
    # every slice's extremes are kept: per slice of 60 samples, the same max and min
    keep = envelope_indices(values, bins=1000)
    slices = values[:60_000].reshape(1000, 60)
    kept = keep[keep < 60_000].reshape(1000, 2)
    assert np.array_equal(values[kept].max(axis=1), slices.max(axis=1))
    assert np.array_equal(values[kept].min(axis=1), slices.min(axis=1))
