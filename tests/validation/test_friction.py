"""Friction as drives measure it (issue 21 item 9, docs/winder.md F1-F2): a table of friction
torque against shaft speed on rollers and in a winder's compensation, and break-away torque."""

from __future__ import annotations

import numpy as np
import pytest

import webline
from webline.errors import LineFileError
from webline.sim.elements import layout as L

IDLER_RADIUS = 1.5 * 0.0254  # hswl's idler [m]
IDLER = 3  # its node; spans 2 (span3a) in, 3 (span3b) out
#: measured at 0/25/50/75/100 % of 80 rad/s (the idler runs at 66.7 rad/s at 500 ft/min)
TABLE = {"speed": [0.0, 20.0, 40.0, 60.0, 80.0], "torque": [0.02, 0.03, 0.05, 0.08, 0.12]}


def _idler_torque(result):
    """Torque the web puts on hswl's idler [N·m]: r (T_out - T_in)."""
    return IDLER_RADIUS * (result.tension[:, IDLER] - result.tension[:, IDLER - 1])


def test_idler_friction_follows_the_measured_table_in_steady_running(hswl):
    """At constant speed the web's torque on an idle roller is its friction: b ω plus the
    table interpolated by hand at ω (between the 75 and 100 % points) - 1e-9 N·m: the
    settled loop's residue, far below the 0.1 N·m measured."""
    result = webline.simulate(hswl.replace({"rollers.idler.friction_table": TABLE}), 5.0)
    omega = result.omega[-1, IDLER]
    assert 60.0 < omega < 80.0
    expected = 1e-4 * omega + np.interp(omega, TABLE["speed"], TABLE["torque"])  # tanh = 1
    assert _idler_torque(result)[-1] == pytest.approx(expected, abs=1e-9)
    assert expected > 0.09  # the table, not the 0.0067 N·m bearing drag, sets it


def test_a_one_point_table_is_coulomb_friction(hswl):
    """Limiting case: a table of one point c is Coulomb friction c (same smoothing at rest):
    the same run to 1e-9 (relative: only the order of the sums differs)."""
    speed = {"type": "ramp", "initial": 0.0, "final": "500 ft/min", "start": 0.1,
             "duration": 1.0}
    coulomb = webline.simulate(hswl.replace({"rollers.idler.coulomb_friction": 0.05,
                                             "speed": speed}), 1.5)
    table = webline.simulate(hswl.replace({
        "rollers.idler.friction_table": {"speed": [0.0], "torque": [0.05]}, "speed": speed}), 1.5)
    np.testing.assert_allclose(table.states, coulomb.states, rtol=1e-9, atol=1e-9)


def test_an_idler_at_rest_breaks_away_at_its_static_friction(hswl):
    """Starting from rest, an idle roller with break-away torque B = 0.2 N·m (running
    Coulomb 0.01 N·m) stays at rest while the web's torque on it is below B (the web
    stretches downstream of it), starts when it reaches B, then runs with its running
    friction only. Without B it starts at once."""
    line = hswl.with_scenario("startup").replace({"rollers.idler.coulomb_friction": 0.01})
    stuck = webline.simulate(line.replace({"rollers.idler.breakaway_torque": 0.2}), 3.0)
    free = webline.simulate(line, 3.0)
    assert stuck.plan.nodes[IDLER, L.N_BREAKAWAY] == 0.2
    torque, omega, time = _idler_torque(stuck), stuck.omega[:, IDLER], stuck.time
    start = int(np.argmax(np.abs(omega) >= 0.01))
    assert time[start] > 1.1  # the line starts at 1 s; the idler waits
    assert np.abs(omega[:start]).max() < 0.01  # at rest (the stick band)
    # it starts at B: the torque reaches B (to 5 %: the web keeps stretching while the
    # roller leaves the 0.01 rad/s band, 3 % measured) and not before
    assert torque[:start].max() == pytest.approx(0.2, rel=0.05)
    assert torque[:start - 20].max() < 0.2  # 20 ms before it started: still below B
    # once moving, only running friction and inertia: b ω + c + J dω/dt, far below B
    late = time > 2.5
    accel = np.gradient(omega, time)
    running = 1e-4 * omega + 0.01 * np.tanh(omega / 0.1) + 0.001 * accel
    np.testing.assert_allclose(torque[late], running[late], atol=2e-3)
    assert torque[late].max() < 0.1
    first = int(np.argmax(np.abs(free.omega[:, IDLER]) >= 0.01))
    assert free.time[first] < 1.05 and _idler_torque(free)[:first].max() < 0.02


def test_compensating_the_measured_friction_holds_an_open_loop_rewind(hswl):
    """An open-loop rewind (T_ref R / n, no loadcell) whose shaft has the measured friction
    table: compensating the same table brings the steady tension to the reference; without
    it the tension falls short by the friction over the radius (≈ 8 N at 17 rad/s)."""
    line = webline.load_line("rockwell")
    table = {"speed": [0.0, 10.0, 20.0, 30.0, 40.0], "torque": [0.3, 0.5, 0.8, 1.0, 1.1]}
    line = line.replace({"rollers.rewind.friction_table": table})
    friction = line.rewind.friction
    errors = []
    for comp in (None, table):
        winder = {"mode": "open_loop", "viscous_friction": friction}
        if comp is not None:
            winder["friction_table"] = comp
        result = webline.simulate(line.replace({"rollers.rewind.winder": winder}), 6.0)
        k = line.zones[line.controlled_zone(line.n_nodes - 1)].loadcell
        errors.append(result.tension[-1, k] - result.tension_ref[-1, k])
    reference = 10 * 4.4482216152605
    assert errors[0] < -0.12 * reference  # the uncompensated table: ~8 N short
    assert abs(errors[1]) < 0.01 * reference  # as the matched viscous friction alone: 1 %


@pytest.mark.parametrize(("changes", "key"), [
    ({"rollers.idler.friction_table": {"speed": [0, 10], "torque": [0.1]}},
     "rollers[3].friction_table.torque"),
    ({"rollers.idler.friction_table": {"speed": [10, 0], "torque": [0.1, 0.2]}},
     "rollers[3].friction_table.speed"),
    ({"rollers.idler.breakaway_torque": 0.01, "rollers.idler.coulomb_friction": 0.02},
     "rollers[3].breakaway_torque"),
])
def test_friction_that_describes_no_drive_is_refused(hswl, changes, key):
    with pytest.raises(LineFileError) as error:
        hswl.replace(changes)
    assert key in str(error.value)


def test_linear_rows_with_a_friction_table_match_finite_differences(hswl):
    """The idler's speed row gains -dτ_f/dω = -(f'(|ω|) |tanh| + f (1 - tanh²)/ω_s)/J (F1):
    the open-loop linear model equals central differences of the compiled right-hand side
    (1e-6, as the other linear rows are checked)."""
    from fd_helpers import jacobian, plant_derivative

    line = hswl.replace({"rollers.idler.friction_table": TABLE})
    op = webline.operating_point(line)
    f, z0, _ = plant_derivative(line, op)
    sys = webline.linearize(line, loop="open")
    fd = jacobian(f, z0, op.torque, np.maximum(np.abs(z0), 1.0))
    np.testing.assert_allclose(sys.A, fd, rtol=1e-6, atol=1e-6 * np.abs(sys.A).max())
    slope = (0.12 - 0.08) / 20.0  # the 75-100 % segment, where the idler runs
    row = line.n_spans + IDLER
    assert sys.A[row, row] == pytest.approx(-(1e-4 + slope) / 0.001, rel=1e-6)
