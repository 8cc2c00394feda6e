"""Web slip inside the simulated line (issue 6, thesis Ch. 5).

A disturbance downstream of a slipping roller reaches the span upstream of it (5.33 with web
speeds); with enough friction the slip model is the no-slip model to rounding; slip dissipates
power, never produces it (second law, E-5.3); web length is conserved with slip.
"""

from __future__ import annotations

import numpy as np
import pytest

import webline

RIPPLE = [{"type": "speed_ripple", "roller": "rewind", "amplitude": "20 ft/min",
           "frequency": "2 Hz"}]


def process_roller_contact(line: webline.Line, friction: float | None) -> webline.Line:
    data = line.spec.model_dump(exclude_none=True)
    data["disturbances"] = RIPPLE
    if friction is not None:
        data["rollers"][2]["wrap"] = "180 deg"
        data["rollers"][2]["contact"] = {"type": "traction", "friction": friction,
                                         "viscous": "2000 N*s/m"}
    return webline.load_line(data)


@pytest.fixture(scope="module")
def adhered(hswl):
    return webline.simulate(process_roller_contact(hswl, None), 6.0)


def test_enough_friction_gives_the_no_slip_model_exactly(hswl, adhered):
    """Same trajectory to rounding: the traction line is another structure, so another
    compiled loop (``kernel.compiled_loop``) whose fast-math sums may round differently
    (measured: 1e-15 relative); 1e-12 leaves room and still catches any model difference."""
    result = webline.simulate(process_roller_contact(hswl, 1.0), 6.0)
    assert not result.slipping.any()
    scale = np.abs(adhered.states).max(axis=0)
    assert (np.abs(result.states - adhered.states) / scale).max() < 1e-12


def test_upstream_span_responds_when_the_roller_slips(hswl, adhered):
    settled = slice(2000, None)  # after the first 2 s
    base = adhered.tension[settled, 1].std()
    responses = []
    for friction in (0.001, 0.003, 0.01):
        result = webline.simulate(process_roller_contact(hswl, friction), 6.0)
        assert result.slipping[:, 2].mean() > 0.3
        responses.append(result.tension[settled, 1].std())
        # second law: slip dissipates power at every sample
        assert result.slip_power.min() >= 0.0
        # web balance with slip: unwound = rewound + stored, to solver accuracy
        balance = result.web_unwound - result.web_rewound - (result.web_stored
                                                              - result.web_stored[0])
        assert np.abs(balance).max() < 1e-7
    # the less friction, the more the downstream ripple reaches span 2 (above the adhered
    # response, which only the process roller's own speed loop lets through)
    assert responses[0] > responses[1] > responses[2] > base
    assert responses[0] > 1.2 * base


def test_slip_matches_the_adaptive_reference(hswl):
    line = process_roller_contact(hswl, 0.003)
    fast = webline.simulate(line, 1.0)
    ref = webline.simulate_reference(line, 1.0)
    assert np.array_equal(fast.slipping, ref.slipping)
    np.testing.assert_allclose(fast.tension, ref.tension, rtol=1e-6)
