"""The Chapter 4 unwind model (``webline.analysis.unwind_model``, thesis 4.3-4.6, 4.12) against
webline's own linearisation of the same line (``webline.sim.linear.linearize``): the thesis's nine
states map onto webline's (twist = θm/n - θL; PI integrators I_s, I_t as combinations of x1,
x2, x3), and A_T, B_V, B_T, B_b must commute with that map to rounding."""

from __future__ import annotations

import numpy as np
import pytest

import webline
from webline.analysis.unwind_model import unwind_model
from webline.sim.core.plan import compile_plan
from webline.sim.elements import layout as L
from webline.sim.linear.linear_plant import plant_matrices
from webline.sim.linear.linearize import controller_matrices
from webline.studies.unwind_belt_ramp import case_line


def _webline_closed(line, t):
    """webline's closed loop [[A + B Kx, B Ki], [Gx, Gi]], its reference input matrix and
    the index of every unwind-section state in it."""
    plan = compile_plan(line)
    op = webline.operating_point(line, t)
    a, b, _, _ = plant_matrices(line, op)
    kx, ki, kr, gx, gi, gr = controller_matrices(plan, op)
    n = a.shape[0]
    cl = np.block([[a + b @ kx, b @ ki], [gx, gi]])
    ref = np.vstack([b @ kr, gr])
    ns, nn = line.n_spans, line.n_nodes
    motor = plan.linear_motor_state(0)
    index = {"T1": 0, "omega_L": ns, "tau": ns + nn, "omega_m": motor, "twist": motor + 1,
             "I_s": n, "I_t": n + 1, "omega_master": ns + 1}
    return cl, ref, index, op


@pytest.mark.parametrize("case", ["36mm", "12mm"])
@pytest.mark.parametrize("t", [0.0, 20.0])
def test_unwind_model_commutes_with_webline_linearisation(case, t):
    """M A_T = A_w M on the unwind section (M: thesis states -> webline's), to 1e-9 relative;
    B_V, B_T, B_b against the master-speed, reference and load-torque columns; the thesis
    realisation has two extra modes at 0 (the common angle and one PI state), the rest of its
    spectrum is webline's section spectrum."""
    line = case_line(case)
    model = unwind_model(line, t)
    cl, ref, ix, op = _webline_closed(line, t)
    plan = compile_plan(line)
    row, gains = plan.drives[0], plan.gains[0]
    n, r_un = model.ratio, op.radius[0]
    g = op.inertia[0] / (n * r_un) / row[L.D_GAINNORM]
    sigma = -1.0
    order = ["T1", "omega_L", "tau", "omega_m", "twist", "I_s", "I_t"]
    m = np.zeros((7, 9))
    m[0, 4] = m[1, 3] = m[2, 8] = m[3, 1] = 1.0
    m[4, 0], m[4, 2] = 1.0 / n, -1.0
    m[5, 7] = g * gains.speed_ki  # I_s = g Kis (x3 + σ Kpt x2 + σ Kit x1)
    m[5, 6] = g * gains.speed_ki * sigma * gains.tension_kp
    m[5, 5] = g * gains.speed_ki * sigma * gains.tension_ki
    m[6, 6] = gains.tension_ki  # I_t = Kit x2
    idx = [ix[k] for k in order]
    a_w = cl[np.ix_(idx, idx)]
    lhs, rhs = m @ model.a_t, a_w @ m
    np.testing.assert_allclose(lhs, rhs, rtol=0, atol=1e-9 * np.abs(rhs).max())
    # B_V: the master's web speed r1 ω1 enters the tension row; the feedforward is a reference
    np.testing.assert_allclose(m @ model.b_v - np.r_[0, 0, model.b_v[8], 0, 0,
                                                     m[5] @ model.b_v, 0],
                               cl[idx, ix["omega_master"]] / op.radius[1], atol=1e-9)
    # B_T: the zone's tension reference (reference column 1)
    np.testing.assert_allclose(m @ model.b_t, ref[idx, 1], rtol=1e-9,
                               atol=1e-9 * np.abs(ref[idx, 1]).max())
    # B_b (4.12): a torque on the unwind shaft enters as T1 does, divided by r
    np.testing.assert_allclose(model.b_brake[3], cl[ix["omega_L"], ix["T1"]] / r_un, rtol=1e-12)
    eig_t = np.sort_complex(np.linalg.eigvals(model.a_t))
    eig_w = np.sort_complex(np.linalg.eigvals(a_w))
    small = np.abs(eig_t) < 1e-6 * np.abs(eig_t).max()
    assert small.sum() == 2
    np.testing.assert_allclose(np.sort_complex(eig_t[~small]), eig_w, rtol=1e-6)


def test_the_rigid_contrast_sentence_says_less_or_more_as_its_numbers_do() -> None:
    """``unwind-belt-ramp``'s verdict on Fig. 4.5 against 4.6 quotes the rigid drive's std
    against the 36 mm belt's, and says "less" or "more" from them (never a negative "less")."""
    from webline.studies.unwind_belt_ramp import claims

    def row(std: float) -> dict:
        return {"tension_std_after_ramp_N": std, "least_damped_mode_real_1_s": -0.24,
                "least_damped_mode_imag_rad_s": 0.58}

    belts = {"36mm": row(6.86), "24mm": row(7.75), "12mm": row(11.19)}
    assert "19% less" in claims({**belts, "rigid": row(5.58)})  # 1 - 5.58/6.86
    assert "9% more" in claims({**belts, "rigid": row(7.50)})  # 7.50/6.86 - 1
    assert claims({**belts, "rigid": row(3.0)}).endswith(": reproduced")  # under half
