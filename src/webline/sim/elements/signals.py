"""Compiled signal sources for the kernel: reference profiles, sinusoids, measurement noise."""

from __future__ import annotations

import math
from typing import Any

import numba as nb
import numpy as np
from numba.core.cpu import CPUTargetOptions

#: Fast-math flags that keep NaN/inf semantics (the loop checks finiteness), and numpy's error
#: model (no Python ZeroDivisionError branch on every division).
FAST = {"nsz", "arcp", "contract", "afn", "reassoc"}
njit = nb.njit(cache=True, fastmath=FAST, error_model="numpy")

# The kernel and its helpers are compiled without numba's reference counting (``_nrt``, numba's
# own switch, absent from its type stubs): every array they touch is allocated by the Python
# caller, and with it each array handed to a helper costs an atomic incref/decref pair per
# call, a third of the run time (measured with perf). A test checks that the compiled loop
# makes no NRT call.
# Should a numba release drop the switch, the kernel still runs, only slower.
_NO_NRT: dict[str, Any] = {"_nrt": False} if hasattr(CPUTargetOptions, "_nrt") else {}
#: The simulation loop (``kernel.compiled_loop``).
loop_njit = nb.njit(cache=True, fastmath=FAST, error_model="numpy", **_NO_NRT)
#: Helpers of the loop: compiled once per signature and inlined by LLVM (``forceinline``), so
#: the structure constants of each compiled loop reach them. numba's own IR-level inlining
#: would do the same at 25x the compile time (it deep-copies the helpers' IR per call site).
jit = nb.njit(cache=True, fastmath=FAST, error_model="numpy", forceinline=True, **_NO_NRT)


@jit
def _segment(p: int, t: float, prof_t: np.ndarray, prof_off: np.ndarray) -> int:
    """Index lo of the breakpoints with prof_t[lo] <= t < prof_t[lo + 1], or -1 outside."""
    lo, hi = prof_off[p], prof_off[p + 1] - 1
    if t >= prof_t[hi] or t < prof_t[lo]:
        return -1
    while hi - lo > 1:  # invariant: prof_t[lo] <= t < prof_t[hi]
        mid = (lo + hi) // 2
        if prof_t[mid] <= t:
            lo = mid
        else:
            hi = mid
    return lo


@jit
def profile_at(p: int, t: float, prof_t: np.ndarray, prof_v: np.ndarray,
               prof_off: np.ndarray) -> float:
    """Value at ``t`` [s] of profile ``p`` of the concatenated breakpoint arrays: the rule of
    ``webline.profiles.pwl_value``, by bisection without array views."""
    lo = _segment(p, t, prof_t, prof_off)
    if lo < 0:
        return prof_v[prof_off[p]] if t < prof_t[prof_off[p]] else prof_v[prof_off[p + 1] - 1]
    return prof_v[lo] + (prof_v[lo + 1] - prof_v[lo]) * (t - prof_t[lo]) / (
        prof_t[lo + 1] - prof_t[lo])


@jit
def profile_slope_at(p: int, t: float, prof_t: np.ndarray, prof_v: np.ndarray,
                     prof_off: np.ndarray) -> float:
    """Rate of change [unit/s] of profile ``p`` at ``t`` (``webline.profiles.pwl_slope``)."""
    lo = _segment(p, t, prof_t, prof_off)
    if lo < 0:
        return 0.0
    return (prof_v[lo + 1] - prof_v[lo]) / (prof_t[lo + 1] - prof_t[lo])


@jit
def sines(table: np.ndarray, t: float) -> float:
    """Sum of amplitude·sin(2π f t + phase) over rows (amplitude, frequency, phase)."""
    total = 0.0
    for r in range(table.shape[0]):
        total += table[r, 0] * math.sin(2.0 * math.pi * table[r, 1] * t + table[r, 2])
    return total


_GOLDEN = np.uint64(0x9E3779B97F4A7C15)
_MIX1 = np.uint64(0xBF58476D1CE4E5B9)
_MIX2 = np.uint64(0x94D049BB133111EB)
_TWO53 = 1.0 / 9007199254740992.0


@jit
def _splitmix64(z: np.uint64) -> np.uint64:
    z = z + _GOLDEN
    z = (z ^ (z >> np.uint64(30))) * _MIX1
    z = (z ^ (z >> np.uint64(27))) * _MIX2
    return z ^ (z >> np.uint64(31))


@jit
def gaussian(seed: int, tick: int, channel: int) -> float:
    """A standard normal number that depends only on (seed, tick, channel).

    Counter-based (splitmix64 + Box-Muller), so a run split into chunks draws exactly the
    same noise as one run, and every channel is independent of the others.
    """
    key = _splitmix64(np.uint64(seed) * _MIX2 + np.uint64(tick) * _GOLDEN
                      + np.uint64(channel) * _MIX1)
    a = _splitmix64(key)
    b = _splitmix64(a)
    u1 = (float(a >> np.uint64(11)) + 1.0) * _TWO53  # in (0, 1]
    u2 = float(b >> np.uint64(11)) * _TWO53
    return math.sqrt(-2.0 * math.log(u1)) * math.cos(2.0 * math.pi * u2)
