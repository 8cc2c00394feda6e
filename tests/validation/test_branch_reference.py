"""The branch kernel's fixed-step RK4 against an adaptive reference (scipy DOP853 at 1e-12)
on the same right-hand side with the same held torque commands: the step webline chooses
from the plant's fastest mode (h |λ|max <= 0.5) keeps the integration error far below what
any result shows (docs/branching.md)."""

from __future__ import annotations

import numpy as np
from scipy.integrate import solve_ivp

import webline
from webline.sim.branches.loop.plant import rhs


def test_rk4_sub_steps_match_an_adaptive_reference_through_a_layer_upset():
    result = webline.simulate("laminator", 2.4, scenario="layer-upset")
    plan, rec = result.plan, result.rec
    n_x = plan.n_x
    window = np.nonzero(rec[:, 0] >= 1.9)[0]  # 0.1 s before the film's tension step to 0.4 after
    x = rec[window[0], 1:1 + n_x].copy()
    work, dx = plan.scratch(), np.zeros(n_x)

    def rate(_t: float, y: np.ndarray, cmd: np.ndarray) -> np.ndarray:
        rhs(y, cmd, plan.wound, *plan.tables(), dx, work)
        return dx.copy()

    worst = np.zeros(n_x)
    for j in window[:-1]:  # each controller period with its held torque commands
        x = solve_ivp(rate, (rec[j, 0], rec[j + 1, 0]), x, method="DOP853", rtol=1e-12,
                      atol=1e-12, args=(rec[j, 1 + n_x:],)).y[:, -1]
        worst = np.maximum(worst, np.abs(x - rec[j + 1, 1:1 + n_x]))
    n_s = len(plan.line.spans)
    moved = float(np.max(np.ptp(rec[window, 1:1 + n_s], axis=0)))
    assert moved > 25.0  # the film's 30 N step: the comparison is not of a still line
    # RK4's error per step at h |λ| <= 0.5 is h⁵ λ⁵ / 120 ~ 3e-4 of a fast mode's amplitude;
    # the fast modes (rollers on their spans) carry a small part of the transient, so the
    # tensions' error is ~2e-6 of the 30 N step (measured 5.6e-5 N): 1e-5 of it leaves room
    assert np.max(worst[:n_s]) < 1e-5 * moved
