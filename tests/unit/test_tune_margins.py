"""Loop-at-a-time margins (``webline.twin.loop_margins``) against closed forms."""

from __future__ import annotations

import math

import numpy as np
import pytest

import webline
from webline.sim.plan import compile_plan
from webline.twin.loop_margins import _margins, feedback_rows, loop_margins


def test_margins_of_a_third_order_lag() -> None:
    """L = K/(s+1)³: the phase reaches -180° at ω = √3, where |L| = K/8, so the gain margin
    is 8/K; |L| = 1 at ω = √(K^(2/3) - 1), phase margin 180° - 3 atan(ω)."""
    k = 4.0
    omega = np.logspace(-2, 2, 4000)
    loop = k / (1j * omega + 1.0) ** 3
    gm, down, pm, wc = _margins(omega, loop)
    wc_exact = math.sqrt(k ** (2 / 3) - 1.0)
    # a dense grid with linear interpolation between points: 1e-4 relative
    assert gm == pytest.approx(8.0 / k, rel=1e-4)
    assert down == math.inf  # no crossing outside the unit circle
    assert pm == pytest.approx(180.0 - 3.0 * math.degrees(math.atan(wc_exact)), abs=1e-2)
    assert wc == pytest.approx(wc_exact, rel=1e-3)


def test_conditionally_stable_loop_has_a_reduction_margin() -> None:
    """L = K (s+1)² / s³ crosses -180° at ω = 1 with |L| = 2K (the gain may fall by 2K before
    the loop goes unstable) and never again: a reduction margin, no gain margin."""
    k = 2.0
    omega = np.logspace(-2, 3, 6000)
    s = 1j * omega
    gm, down, _, _ = _margins(omega, k * (s + 1.0) ** 2 / s**3)
    assert gm == math.inf
    assert down == pytest.approx(2.0 * k, rel=1e-4)


def test_feedback_rows_rebuild_the_closed_loop() -> None:
    """A_cl's plant rows are A + B K: the recovered K closes the open plant exactly."""
    plan = compile_plan(webline.load_line("converter"))
    a_cl, b_full, k = feedback_rows(plan)
    n = webline.linearize(webline.load_line("converter"), loop="open").A.shape[0]
    open_a = np.asarray(webline.linearize(webline.load_line("converter"), loop="open").A)
    rebuilt = open_a + b_full[:n] @ k[:, :n]
    assert np.allclose(rebuilt, a_cl[:n, :n], rtol=1e-10, atol=1e-9 * np.abs(a_cl).max())


def test_converter_loops_have_the_margins_of_a_critically_damped_design() -> None:
    """The built-in converter's PI loops (critically damped by design, 2 ms torque lags,
    1 kHz sampling) keep ≥ 40° of phase and ≥ 6 dB of gain; its dancer loop alone is
    conditionally stable (an integrator on the position of an integrating carriage)."""
    margins = {m.drive: m for m in loop_margins(compile_plan(webline.load_line("converter")))}
    assert set(margins) == {"unwind", "infeed", "drum", "chill", "rewind"}
    for m in margins.values():
        assert m.phase_margin >= 40.0 and m.gain_margin_db >= 6.0 and m.open_unstable == 0
    assert math.isfinite(margins["unwind"].reduction_margin)
    assert all(margins[d].reduction_margin == math.inf for d in ("infeed", "drum", "chill"))
