"""A chain's adaptive and MRAC drives stop adapting at a break's detection, as a branched
line's do (issue 35 item 5, docs/winder.md W8): the stop and the hold are not the running
line their estimates learn (left adapting, the laminator's foil unwind b̂ ran from 0.05 to
24 N·m·s over a 5 s stop)."""

from __future__ import annotations

import numpy as np
import pytest

import webline
from webline.control.select import with_controller

BREAK = {"type": "web_break", "span": "span2", "at": 1.5, "stop_time": 2.0}


@pytest.mark.parametrize("family", ["adaptive", "mrac"])
def test_estimates_keep_their_values_from_the_detection(hswl, family):
    """hswl, every drive ``family``, the web broken in span2 at 1.5 s: every estimate
    (adaptive b̂; MRAC k̂_T, k̂_V, ĉ) is, from the first record after the detection to the
    end of the hold, the value it had at the detection, to the bit; and it did adapt before."""
    line = with_controller(hswl, family).replace({"disturbances": [BREAK]})
    result = webline.simulate(line, 5.0)
    detected = result.break_monitor[0]
    assert 1.5 <= detected < 1.7
    estimate = (result.friction_estimate if family == "adaptive"
                else result.mrac_gains.reshape(len(result.time), -1))
    after = np.flatnonzero(result.time > detected + result.plan.dt)
    frozen = estimate[after[0]]
    assert np.array_equal(estimate[after], np.broadcast_to(frozen, estimate[after].shape))
    assert not np.array_equal(estimate[0], frozen)  # it learned while running
