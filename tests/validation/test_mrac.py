"""The decentralized MRAC of thesis Sec. 6.3 (``type = "mrac"``, ``webline.sim.drives.mrac``).

The law is checked on a section in isolation through the compiled functions themselves: the
Lyapunov function of the corrected proof (E-6.8) decreases along simulated trajectories with a
friction error, and the printed sign of (6.68b) makes it grow. On the HSWL: the MRAC removes a
50 % friction-model error that leaves the state feedback with a steady error, and runs stably
with the study's disturbances at 500, 1000 and 1500 ft/min.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg

import webline
from webline.control.sections import section_models
from webline.control.select import with_controller
from webline.sim.core.plan import compile_plan
from webline.sim.drives.mrac import mrac_adapt, mrac_feedback
from webline.sim.elements import layout as L
from webline.studies.hswl_controllers import disturbances

REWIND = 3  #: drive index of the HSWL's rewind section (a tension and a speed state)


def _section(hswl, leakage: float = 0.0):
    """Drive table, section model (A, b) and design closed loop A_m of the HSWL's rewind, MRAC
    with no leakage and a wide projection (the proof's law, unmodified)."""
    line = with_controller(hswl, "mrac", leakage=leakage, parameter_bound=1e4)
    plan = compile_plan(line)
    model = section_models(line, plan.op)[REWIND]
    design = plan.designs[REWIND]
    assert design is not None
    return plan, model.a, model.b.ravel(), design.closed, line


def _run(plan, a, b, a_m, sign: float, seconds: float = 20.0, dt: float = 2e-4):
    """Isolated rewind section with a friction error: the true plant is A = A_model + b δᵀ
    with δ_V = -b_err/(n r) (a 50 % friction error b_err), and the equilibrium input misses the
    torque b_err ω_ref/n. Returns V(t) of E-6.8 (physical units) and the final |e|."""
    drives = plan.drives.copy()
    d = REWIND
    if sign < 0:  # the printed (6.68b)
        drives[d, [L.D_GKT, L.D_GKV, L.D_GBIAS]] *= -1.0
    i = int(drives[d, L.D_NODE])
    n, r = plan.nodes[i, L.N_RATIO], plan.op.radius[i]
    b_err = 0.5 * plan.nodes[i, L.N_VISCOUS]
    delta = np.array([0.0, -b_err / (n * r)])
    offset = -b_err * plan.op.omega[i] / n  # the torque the equilibrium input lacks
    k0 = drives[d, [L.D_KT, L.D_KV]]
    gam = np.abs(plan.drives[d, [L.D_GKT, L.D_GKV]])
    gam_c = abs(plan.drives[d, L.D_GBIAS])
    # P of the law: A_mᵀP + P A_m = -u_s S² (the scaled Lyapunov equation, unscaled), P b = PB
    istate = np.zeros((len(drives), L.I_COLS))
    istate[d, L.I_KT], istate[d, L.I_KV] = k0
    x = np.array([1.0, 0.01])  # 1 N, 1 cm/s off the reference
    values, pb = [], drives[d, [L.D_PBT, L.D_PBV]]
    p_eff = _p_eff(a_m, b, pb)
    for step in range(int(seconds / dt)):
        u = mrac_feedback(d, x[0], x[1], 1.0, istate)
        k_err = k0 + delta - istate[d, [L.I_KT, L.I_KV]]
        c_err = offset - istate[d, L.I_BIAS]
        if step % 50 == 0:
            values.append(x @ p_eff @ x + np.sum(k_err**2 / gam) + c_err**2 / gam_c)
        x = x + dt * (a @ x + b * (u + offset + delta @ x))
        mrac_adapt(d, dt, x[0], x[1], istate, drives)
    return np.array(values), np.abs(x)


def _p_eff(a_m, b, pb):
    """The P for which the law's eᵀP b equals PBT e_T + PBV e_V: a solution of
    A_mᵀP + P A_m = -W for a diagonal W > 0, recovered from P b = pb (W's two entries are the
    unknowns, P is linear in them)."""
    basis = [scipy.linalg.solve_continuous_lyapunov(a_m.T, -np.diag(e)) for e in np.eye(2)]
    w = np.linalg.lstsq(np.column_stack([p @ b for p in basis]), pb, rcond=None)[0]
    assert np.all(w > 0)
    p = w[0] * basis[0] + w[1] * basis[1]
    np.testing.assert_allclose(p @ b, pb, rtol=1e-9)
    return p


def test_lyapunov_function_decreases_along_the_corrected_law(hswl):
    """V = eᵀPe + Σ k̃_j²/Γ_j + c̃²/γ_c never rises (sampled every 10 ms of a 0.2 ms Euler
    integration; 1e-9 relative allows rounding) and the error converges: in 20 s the tension
    and speed errors drop from 1 N, 1 cm/s below 1e-4 N and 1e-7 m/s (γ = 1/s: the bias, the
    slowest estimate, has a time constant of seconds). V itself need not go to zero: k̃ has
    no persistent excitation."""
    plan, a, b, a_m, _ = _section(hswl)
    values, error = _run(plan, a, b, a_m, +1.0)
    rises = np.diff(values) / values[:-1]
    assert rises.max() < 1e-9
    assert values[-1] < 0.1 * values[0]
    assert error[0] < 1e-4 and error[1] < 1e-7


def test_printed_sign_of_6_68b_makes_the_lyapunov_function_grow(hswl):
    """With dk̂/dt = -(eᵀP b) x as printed, V grows tenfold or the section diverges (E-6.8):
    the estimates move the wrong way."""
    plan, a, b, a_m, _ = _section(hswl)
    with np.errstate(all="ignore"):
        values, _ = _run(plan, a, b, a_m, -1.0, seconds=2.0)
    finite = values[np.isfinite(values)]
    assert len(finite) < len(values) or finite.max() > 10 * values[0]


def test_mrac_removes_a_friction_model_error(hswl):
    """Friction model 50 % low everywhere, constant references, no disturbance: the state
    feedback keeps a steady tension error of several N (no integral action), the MRAC's bias
    and gains bring it below 0.05 N within 40 s."""
    wrong = {hswl.node_name(i): {"friction_estimate": 0.5 * hswl.spec.rollers[i].friction}
             for i in hswl.drives}
    loadcells = [z.loadcell for z in hswl.zones]
    final = {}
    for family in ("state_feedback", "mrac"):
        result = webline.simulate(with_controller(hswl, family, overrides=wrong), 40.0)
        final[family] = np.abs(result.tension[-1] - result.tension_ref[-1])[loadcells].max()
    assert final["state_feedback"] > 1.0
    assert final["mrac"] < 0.05
    # the recorded bias ĉ has learnt the equilibrium input's error: the missing friction torque
    # d = (b - 0.5 b) ω / n at the motor, entering u with the opposite sign; the σ-modification
    # leaks ĉ towards 0, which leaves it 2-3 % short (tolerance 5 %)
    bias = result.mrac_gains[-1, :, 2]
    for d, i in enumerate(hswl.drives):
        missing = 0.5 * hswl.spec.rollers[i].friction * result.omega[-1, i] / \
            hswl.spec.rollers[i].drive.ratio
        assert bias[d] == pytest.approx(-missing, rel=0.05)
    assert {"mrac_gain_tension", "mrac_gain_speed", "mrac_bias"} <= set(result.to_xarray())


@pytest.mark.parametrize("fpm", [500.0, 1000.0, 1500.0])
def test_mrac_stable_with_the_study_disturbances(hswl, fpm):
    """The study's ripple, eccentricity and noise, 20 s: verdict ok or warning, every tension
    error below 1 N (the ripple's amplitude is 4.4 N) and every k̂ inside its projection box."""
    line = with_controller(hswl.replace(speed=f"{fpm} ft/min"), "mrac")
    result = webline.simulate(line.replace(disturbances=disturbances()), 20.0)
    assert result.verdict.status in ("ok", "warning")
    loadcells = [z.loadcell for z in hswl.zones]
    err = (result.tension - result.tension_ref)[result.time > 10.0][:, loadcells]
    assert np.abs(err).max() < 1.0


def test_lines_without_an_mrac_record_no_adapted_gains(hswl):
    """The adapted-gain signals exist only where a drive runs the MRAC: NaN in ``mrac_gains``
    and absent from the dataset otherwise."""
    result = webline.simulate(hswl, 0.5)
    assert np.isnan(result.mrac_gains).all() and not result.has_mrac.any()
    assert "mrac_bias" not in result.to_xarray()


def test_condition_6_69_is_the_certificate_of_the_reference_models(hswl):
    """(6.69) with the corrected terms on the idler-free HSWL: the MRAC's reference models
    are the state feedback's closed loops, so the ratios equal ``certificate``'s for that
    design (docs/decentralized.md §5: SI 0.0056 at the process section, fails; searched 1.33,
    holds); the interconnected reference model is Hurwitz (max Re λ ≈ -17 1/s), so K_m = 0."""
    from webline.analysis.certificate import certificate
    from webline.analysis.mrac import mrac_condition
    from webline.control.lumped import without_idlers

    line = without_idlers(with_controller(hswl, "mrac"))
    si = mrac_condition(line, scaling="si")
    assert not si.certificate.holds
    reference = certificate(without_idlers(with_controller(hswl, "state_feedback")),
                            scaling="si", plant=False)
    np.testing.assert_allclose([s.ratio for s in si.certificate.sections],
                               [s.ratio for s in reference.sections], rtol=1e-9)
    assert si.certificate.worst_ratio == pytest.approx(0.00565, rel=0.01)
    searched = mrac_condition(line)
    assert searched.certificate.holds and searched.certificate.worst_ratio > 1.3
    assert -17.5 < searched.reference_eigenvalues.real.max() < -16.5
    assert searched.reference_hurwitz and not searched.k_m.any()
