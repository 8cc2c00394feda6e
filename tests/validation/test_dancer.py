"""The dancer (issue 15, docs/winder.md): web length conserved while it moves, its linear
rows against finite differences of the compiled equations, its mode against the
spring-mass frequency, and what position control and the dancer as a tension sensor hold."""

from __future__ import annotations

import math

import numpy as np
import pytest
from fd_helpers import jacobian, plant_derivative

import webline

T_REF = 10 * 4.4482216152605  # rockwell's 10 lbf [N]


def dancer_line(use: str = "position", neighbours: float = 1.0, **carriage: object):
    """rockwell, whose dancer sits between unwind and pull roll (two 5 ft spans), with the
    carriage given here; ``neighbours`` multiplies the inertia of the unwind and pull roll."""
    data = webline.load_line("rockwell").spec.model_dump(exclude_none=True)
    assert data["rollers"][1]["type"] == "dancer"
    assert [s["length"] for s in data["spans"][:2]] == pytest.approx([1.524, 1.524])
    c = {"mass": 5.0, "travel": 0.3, "position": 0.15, "damping": 100.0, "use": use}
    c.update(carriage)
    data["rollers"][1].update(radius=0.05, inertia=0.002, friction=1e-4, dancer=c)
    for i in (0, 2):
        data["rollers"][i]["inertia"] *= neighbours
    return webline.load_line(data)


def load_step(factor: float) -> dict:
    """The dancer's load: twice the tension reference, times ``factor`` from 1 s on."""
    return {"type": "steps", "initial": 2 * T_REF, "steps": [{"time": 1.0,
                                                              "value": 2 * T_REF * factor}]}


def position(result) -> np.ndarray:
    return result.states[:, result.plan.state_names.index("dancer.position")]


def test_web_length_conserved_while_the_dancer_moves():
    result = webline.simulate(dancer_line(load=load_step(1.2)), 15.0)
    y = position(result)
    assert y.max() - y.min() > 3e-3  # it moved by millimetres (the spans by as much)
    balance = result.web_unwound - result.web_rewound - (result.web_stored
                                                         - result.web_stored[0])
    # the invariant sum L_k(y)(1 - s_k/EA) + rewound - unwound is bilinear in (y, s): RK4 at
    # 1 ms keeps it to ~1e-12 m; a missing (EA - s) dL/dt term shows up at the mm of travel
    assert np.abs(balance).max() < 1e-7
    # position control: back at the set position, and the spans at load / 2 (force balance)
    assert abs(y[-1] - 0.15) < 2e-4
    assert result.tension[-1, 0] == pytest.approx(1.2 * T_REF, rel=0.01)


def test_dancer_as_tension_sensor_holds_the_reference():
    k = 2000.0
    result = webline.simulate(dancer_line("tension", load=load_step(1.2), stiffness=k), 15.0)
    # the tension loop holds the reference; the spring takes the extra load: y - y_set = ΔF/k
    assert result.tension[-1, 0] == pytest.approx(T_REF, rel=0.01)
    assert position(result)[-1] - 0.15 == pytest.approx(0.4 * T_REF / k, rel=0.02)


def test_linear_rows_match_finite_differences():
    line = dancer_line("none", stiffness=500.0)
    op = webline.operating_point(line)
    f, z0, _ = plant_derivative(line, op)
    sys = webline.linearize(line, loop="open")
    assert sys.state_labels[-2:] == ["dancer_position", "dancer_velocity"]
    fd = jacobian(f, z0, op.torque, np.maximum(np.abs(z0), 1.0))
    np.testing.assert_allclose(sys.A, fd, rtol=1e-6, atol=1e-6 * np.abs(sys.A).max())


def test_dancer_mode_is_its_spring_mass_frequency():
    # with heavy neighbours the spans' far ends stand still: the web is a spring of
    # (EA - T)(1/L1 + 1/L2) in parallel with the dancer's own (symmetric spans: the dancer
    # roller does not turn), so ω² = (k + (EA - T)(1/L1 + 1/L2)) / M
    k, mass = 3000.0, 5.0
    line = dancer_line("none", neighbours=1e4, stiffness=k, mass=mass, damping=0.0)
    eig = np.linalg.eigvals(webline.linearize(line, loop="open").A)
    ea, tension = line.ea, webline.operating_point(line).tension[0]
    expected = math.sqrt((k + (ea - tension) * 2 / 1.524) / mass)
    nearest = eig[np.argmin(np.abs(np.abs(eig.imag) - expected))]
    # the remaining coupling (transport terms, unwind-roll web) shifts it by < 0.1 %
    assert abs(nearest.imag) == pytest.approx(expected, rel=1e-3)


def test_closed_loop_with_position_control_matches_finite_differences():
    # the cascaded PI written out here, the unwind's outer loop on y - y_set (independent of
    # linearize.controller_matrices and sim.linear.dancer_linear)
    from test_linearize import continuous_pi

    from webline.sim.elements import layout as L

    # the helper measures every speed on the roller: the rewind's encoder goes there too
    line = dancer_line("position", stiffness=500.0).replace(
        {"rollers.rewind.drive.feedback": "load"})
    op = webline.operating_point(line)
    f, z0, plan = plant_derivative(line, op)
    sys = webline.linearize(line, loop="closed")
    refs = np.array([op.line_speed] + [op.tension[z.loadcell] for z in line.zones])
    n_z, y_state = len(z0), sys.state_labels.index("dancer_position")
    y_set = plan.nodes[1, L.N_DSET]
    _, istate = plan.initial_state(op)
    xi0 = np.array([v for d, row in enumerate(plan.drives)
                    for v in ([istate[d, 0], istate[d, 1]] if row[L.D_ROLE] else [istate[d, 0]])])
    lc = int(plan.drives[0, L.D_LOADCELL])

    def closed(w: np.ndarray, _: object) -> np.ndarray:
        z, xi = w[:n_z].copy(), w[n_z:]
        z[lc] = refs[int(plan.drives[0, L.D_REF])] - (z[y_state] - y_set)  # what it reads
        u, dxi = continuous_pi(plan, op, z, xi, refs)
        return np.concatenate([f(w[:n_z], u), dxi])

    w0 = np.concatenate([z0, xi0])
    fd = jacobian(closed, w0, None, np.maximum(np.abs(w0), 1.0))
    np.testing.assert_allclose(sys.A, fd, rtol=1e-5, atol=1e-6 * np.abs(sys.A).max())
