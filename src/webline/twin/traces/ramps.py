"""A speed reference reconstructed from a measured speed, for a log that lacks the PLC's
reference (issue 36 item 4). The measurement is the reference plus the speed loop's small
tracking error plus sensor noise; taking it as the reference hands its noise to the inertia
compensation, which differentiates it (50 ms bin means of 2 mm/s noise left 1.9 N m RMS on
the converter's unwind torque, 90 times the torque noise).

A PLC's ramp generator commands a sequence of ramps and holds: a continuous piecewise-linear
profile. ``fit_ramps`` finds one: knots added one at a time where the smoothed residual is
largest, their times then fitted (the values at given knot times are a linear least-squares
problem), until the residuals are the noise. A low-pass without phase shift would round
every corner over its time constant, which the inertia compensation sees as a torque pulse
(1 Hz: 3.6 N m RMS on that unwind in the half second after the start of a ramp). Where no
short ramp sequence explains the measurement to its noise (an S-curve, a speed that drifts),
the reconstruction falls back to that zero-phase low-pass and says it is ambiguous.
"""

from __future__ import annotations

import math

import numpy as np

#: most knots of a ramp profile (a start-up, three speeds, a stop: about a dozen)
MAX_KNOTS = 24
#: the ramp profile explains the measurement when its residual RMS is within this factor
#: of the noise level
NOISE_FACTOR = 1.15
#: the fallback: a second-order Butterworth low-pass of this cut-off [Hz], forwards and
#: backwards
SMOOTH_HZ = 1.0
#: a segment whose slope is within this many standard errors of zero is a hold
HOLD_SIGMAS = 3.0
#: knot times are refined while a profile has at most this many knots
REFINED_KNOTS = 8
#: residuals are averaged over this time [s] to place a new knot (noise must not place it)
KNOT_WINDOW = 0.2


def smoothed(time: np.ndarray, values: np.ndarray, cutoff: float = SMOOTH_HZ) -> np.ndarray:
    """``values`` (finite, on increasing ``time`` [s]) low-passed without phase shift: a
    second-order Butterworth of ``cutoff`` [Hz] run forwards and backwards
    (``scipy.signal.filtfilt``, padded by odd reflection); the values as they are where the
    record is too short or too slowly sampled to filter."""
    from scipy.signal import butter, filtfilt

    if len(time) < 16:
        return values
    rate = (len(time) - 1) / float(time[-1] - time[0])
    if cutoff >= 0.45 * rate:
        return values
    b, a = butter(2, cutoff / (0.5 * rate))
    pad = min(len(values) - 1, 3 * round(rate / cutoff))
    return np.asarray(filtfilt(b, a, values, padtype="odd", padlen=pad))


def _values_at(knots: np.ndarray, t: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Least-squares values at ``knots`` of the continuous piecewise-linear fit to (t, v)."""
    basis = np.column_stack([np.interp(t, knots, np.eye(len(knots))[j]) for j in range(len(knots))])
    return np.linalg.lstsq(basis, v, rcond=None)[0]


def _holds(
    knots: np.ndarray, values: np.ndarray, t: np.ndarray, v: np.ndarray, noise: float
) -> np.ndarray:
    """``values`` at ``knots`` refitted with every segment whose slope is within
    ``HOLD_SIGMAS`` standard errors of zero made exactly flat (a hold: a noisy rest must not
    become a slow ramp, which the inertia compensation would turn into a torque)."""
    tied = list(range(len(knots)))  # the value each knot takes (its group)
    for j in range(len(knots) - 1):
        inside = (t >= knots[j]) & (t <= knots[j + 1])
        n, span = int(inside.sum()), float(knots[j + 1] - knots[j])
        if n < 3 or span <= 0:
            continue
        slope_se = noise * math.sqrt(12.0 / n) / span  # least-squares slope of n points
        if abs(values[j + 1] - values[j]) / span < HOLD_SIGMAS * slope_se:
            old = tied[j + 1]
            tied = [tied[j] if g == old else g for g in tied]
    groups = sorted(set(tied))
    if len(groups) == len(knots):
        return values
    hats = np.column_stack([np.interp(t, knots, np.eye(len(knots))[j]) for j in range(len(knots))])
    basis = np.column_stack(
        [hats[:, [k for k, g in enumerate(tied) if g == group]].sum(axis=1) for group in groups]
    )
    shared = np.linalg.lstsq(basis, v, rcond=None)[0]
    return np.array([shared[groups.index(g)] for g in tied])


def _refine(knots: np.ndarray, t: np.ndarray, v: np.ndarray) -> np.ndarray:
    """The interior knot times moved to minimise the residual (the end knots stay)."""
    from scipy.optimize import least_squares

    if len(knots) <= 2:
        return knots

    def residual(inner: np.ndarray) -> np.ndarray:
        k = np.concatenate([[t[0]], np.sort(inner), [t[-1]]])
        k = np.maximum.accumulate(k + np.arange(len(k)) * 1e-9)  # strictly increasing
        return np.interp(t, k, _values_at(k, t, v)) - v

    inner = least_squares(
        residual,
        knots[1:-1],
        bounds=(t[0], t[-1]),
        method="trf",
        x_scale=(t[-1] - t[0]) / len(knots),
        max_nfev=20,
    ).x
    return np.concatenate([[t[0]], np.sort(inner), [t[-1]]])


def fit_ramps(
    time: np.ndarray, values: np.ndarray, noise: float
) -> tuple[np.ndarray, np.ndarray] | None:
    """Knot times [s] and values of a continuous piecewise-linear profile (at most
    ``MAX_KNOTS``) whose residuals against ``values`` are within ``NOISE_FACTOR`` of
    ``noise`` (the measurement's noise level); None if there is none."""
    t, v = np.asarray(time, dtype=float), np.asarray(values, dtype=float)
    if len(t) < 16 or not noise > 0:
        return None
    rate = (len(t) - 1) / float(t[-1] - t[0])
    width = max(1, round(KNOT_WINDOW * rate))
    kernel = np.ones(width) / width
    knots = np.array([t[0], t[-1]])
    while True:
        if len(knots) <= REFINED_KNOTS:  # beyond, moving every knot costs more than it gives
            knots = _refine(knots, t, v)
        residual = np.interp(t, knots, _values_at(knots, t, v)) - v
        if float(np.sqrt(np.mean(residual**2))) <= NOISE_FACTOR * noise:
            return knots, _holds(knots, _values_at(knots, t, v), t, v, noise)
        if len(knots) >= MAX_KNOTS:
            return None
        local = np.abs(np.convolve(residual, kernel, mode="same"))
        knots = np.sort(np.append(knots, t[int(np.argmax(local))]))


def reconstructed(
    time: np.ndarray, values: np.ndarray, noise: float
) -> tuple[np.ndarray, np.ndarray, str]:
    """A reference from a measured speed: (times [s], values, how it was made, in words):
    ``fit_ramps``'s knots, else ``smoothed`` values (ambiguous)."""
    ok = np.isfinite(values)
    t, v = time[ok], values[ok]
    ramps = fit_ramps(t, v, noise)
    if ramps is not None:
        return (
            ramps[0],
            ramps[1],
            (
                f"a profile of {len(ramps[0]) - 1} linear segments "
                "(ramps and holds) fitted to it to its noise"
            ),
        )
    return (
        t,
        smoothed(t, v),
        (
            f"AMBIGUOUS: no sequence of up to {MAX_KNOTS - 1} ramps and "
            f"holds explains it to its noise, so it was smoothed ("
            f"{SMOOTH_HZ:g} Hz low-pass forwards and backwards), which "
            "rounds its corners; log the PLC's speed reference"
        ),
    )
