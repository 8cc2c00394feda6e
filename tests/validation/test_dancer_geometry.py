"""Dancers with n web strands (festoon accumulators) and spans at an angle to the travel
(issue 21 item 9, docs/winder.md D0-D2 generalised): each span lengthens by g dy,
g = (strands/2) cos(angle), and pulls the carriage back with g T."""

from __future__ import annotations

import math

import numpy as np
import pytest
from fd_helpers import jacobian, plant_derivative
from test_dancer import T_REF, dancer_line, load_step, position

import webline

#: a festoon of 6 strands whose entry and exit spans lean 20° and 10° off the travel
GEOMETRY = {"strands": 6, "angle_in": "20 deg", "angle_out": "10 deg"}
G_IN, G_OUT = 3 * math.cos(math.radians(20)), 3 * math.cos(math.radians(10))


@pytest.fixture(scope="module")
def festoon_run():
    line = dancer_line(load=load_step(1.2), position=0.05, travel=0.1, **GEOMETRY)
    return line, webline.simulate(line, 15.0)


def test_web_length_conserved_with_strands_and_angles(festoon_run):
    """Σ L_k(y)(1 - s_k/EA) + rewound - unwound stays constant to 1e-7 m while the carriage
    moves by mm, L_k(y) = L_k + g_k (y - y_set): D1 with dL/dt = g ẏ keeps it exactly (the
    move stores (g_in + g_out) x 7 mm = 4 cm of web, 10⁵ times the tolerance)."""
    line, result = festoon_run
    y = position(result)
    assert y.max() - y.min() > 5e-3
    np.testing.assert_allclose(result.span_lengths[:, 0] - line.spec.spans[0].length,
                               G_IN * (y - 0.05), rtol=1e-12, atol=1e-15)
    balance = result.web_unwound - result.web_rewound - (result.web_stored
                                                         - result.web_stored[0])
    assert np.abs(balance).max() < 1e-7


def test_the_carriage_balances_g_in_t_in_plus_g_out_t_out(festoon_run):
    """At rest the load holds the strands: F = g_in T_in + g_out T_out, i.e. the festoon's
    n T (n = 6) times the cosines; position control brings the carriage back to its set
    position. 0.1 %: the loops' residue after 14 s."""
    _, result = festoon_run
    assert abs(position(result)[-1] - 0.05) < 2e-4
    pull = G_IN * result.tension[-1, 0] + G_OUT * result.tension[-1, 1]
    assert pull == pytest.approx(2 * T_REF * 1.2, rel=1e-3)


def test_linear_rows_match_finite_differences_with_the_geometry():
    line = dancer_line("none", stiffness=500.0, **GEOMETRY)
    op = webline.operating_point(line)
    f, z0, _ = plant_derivative(line, op)
    sys = webline.linearize(line, loop="open")
    fd = jacobian(f, z0, op.torque, np.maximum(np.abs(z0), 1.0))
    np.testing.assert_allclose(sys.A, fd, rtol=1e-6, atol=1e-6 * np.abs(sys.A).max())


def test_festoon_mode_is_its_spring_mass_frequency():
    """Far ends held: each span is a spring (EA - T)/L_k seen through g_k twice (its
    stretch g_k dy, its pull g_k ΔT), ω² = (k + (EA - T)(g_in²/L1 + g_out²/L2)) / M."""
    k, mass = 3000.0, 5.0
    line = dancer_line("none", neighbours=1e4, stiffness=k, mass=mass, damping=0.0, **GEOMETRY)
    eig = np.linalg.eigvals(webline.linearize(line, loop="open").A)
    ea, tension = line.ea, webline.operating_point(line).tension[0]
    expected = math.sqrt((k + (ea - tension) * (G_IN**2 + G_OUT**2) / 1.524) / mass)
    nearest = eig[np.argmin(np.abs(np.abs(eig.imag) - expected))]
    assert abs(nearest.imag) == pytest.approx(expected, rel=1e-3)  # as for 2 strands


def test_a_dancer_sensor_reads_the_load_over_the_geometry():
    """As a tension sensor, T = (F - k (y - y_set)) / (g_in + g_out): the zone holds its
    reference (1 %) and the spring takes the extra load."""
    k = 2000.0
    result = webline.simulate(dancer_line("tension", load=load_step(1.2), stiffness=k,
                                          **GEOMETRY), 15.0)
    assert result.tension[-1, 0] == pytest.approx(T_REF, rel=0.01)
    extra = 2 * T_REF * 1.2 - (G_IN + G_OUT) * T_REF
    assert position(result)[-1] - 0.15 == pytest.approx(extra / k, rel=0.03)


def test_a_span_at_90_degrees_is_refused():
    from webline.errors import LineFileError

    with pytest.raises(LineFileError, match="angle_out"):
        dancer_line(angle_out="90 deg")
