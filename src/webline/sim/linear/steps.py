"""The fixed step of every run, defined once: RK4 sub-steps per controller period from the
fastest mode, the stiffness limit and the record interval (every line, every loop: single
runs, sweeps, Monte Carlo, sessions).

RK4's region of absolute stability reaches 2.78 on the real axis and ±2.83 on the imaginary
one; its local error per step at h·|λ| = 0.5 is ~(0.5)^5/120 ≈ 3e-4 of the mode's amplitude,
so ``STEP_LIMIT`` keeps every mode both stable and accurate. The fastest mode comes from an
eigen-solve (or a bound, ``linear.fastest``) whose last digits are rounding: hswl's
500 1/s comes out as 500.000000002 from one model and 500.0 from another, and a plain
ceil(dt·λ/``STEP_LIMIT``) then takes two sub-steps for one and one for the other.
``SLACK`` absorbs that rounding: a rate within 1e-6 (relative) of an integer number of
sub-steps takes that number (h·|λ| at most 0.5000005, no change in accuracy or stability).
"""

from __future__ import annotations

import math

#: RK4 sub-steps keep h·|λ|max at or below this (accuracy ~3e-4 per step; stable to 2.78).
STEP_LIMIT = 0.5
#: Most RK4 sub-steps per controller period before a line is refused as too stiff.
MAX_SUBSTEPS = 200
#: Default cap on stored records; longer runs are decimated (the integration is not).
MAX_RECORDS = 200_000
#: Relative rounding of the fastest mode that does not add a sub-step (module docstring).
SLACK = 1e-6


def substeps_for(fastest: float, dt: float) -> int:
    """RK4 sub-steps per controller period ``dt`` [s] for a line whose fastest mode is
    ``fastest`` [1/s]: the fewest with h·|λ| <= ``STEP_LIMIT`` up to the relative ``SLACK``
    (at least one). May exceed ``MAX_SUBSTEPS``: the caller refuses the line, naming why."""
    return max(1, math.ceil(dt * fastest / STEP_LIMIT * (1.0 - SLACK)))


def too_stiff(fastest: float, dt: float) -> bool:
    """Whether a mode of ``fastest`` [1/s] needs more than ``MAX_SUBSTEPS`` sub-steps per
    controller period ``dt`` [s]."""
    return substeps_for(fastest, dt) > MAX_SUBSTEPS


def record_every(n_ticks: int, dt: float, interval: float | None = None) -> int:
    """Controller ticks between two stored records of a run of ``n_ticks`` ticks of ``dt``
    [s]: every ``interval`` [s] (rounded to whole ticks, at least one), or by default as few
    as keep the run within ``MAX_RECORDS`` records (the tick at t = 0 included)."""
    if interval is None:
        return max(1, math.ceil((n_ticks + 1) / MAX_RECORDS))
    return max(1, round(interval / dt))
