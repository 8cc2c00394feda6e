"""Equivalent inertia/damping and PI tuning by pole placement (thesis 2.1-2.9)."""

from __future__ import annotations

import numpy as np
import pytest

from webline.analysis.drivetrain import belt
from webline.analysis.drivetrain import equivalent as eq
from webline.analysis.drivetrain.params import BeltDrive, SpeedPI, hswl_unwind_belt_drive
from webline.analysis.drivetrain.singular_perturbation import split_eigenvalues

DRIVE = BeltDrive(j_motor=0.3, j_load=1.7, b_motor=0.02, b_load=0.15, r_motor=0.11,
                  r_load=0.06, stiffness=4e4)


def test_equivalent_quantities_refer_energy_to_one_shaft():
    """(2.1), (2.6): ½ Jeq,m ωm² = ½ Jm ωm² + ½ JL ωL² with ωL = (R1/R2) ωm, and likewise on the
    load side; the two equivalents differ by the squared ratio."""
    wm = 3.0
    wl = DRIVE.r_motor / DRIVE.r_load * wm
    kinetic = DRIVE.j_motor * wm**2 + DRIVE.j_load * wl**2
    assert eq.inertia_motor_side(DRIVE) * wm**2 == pytest.approx(kinetic)
    assert eq.inertia_load_side(DRIVE) * wl**2 == pytest.approx(kinetic)
    dissipation = DRIVE.b_motor * wm**2 + DRIVE.b_load * wl**2
    assert eq.damping_motor_side(DRIVE) * wm**2 == pytest.approx(dissipation)
    assert eq.damping_load_side(DRIVE) * wl**2 == pytest.approx(dissipation)


@pytest.mark.parametrize("feedback", ["motor", "load"])
def test_pole_placement_puts_the_rigid_poles_where_asked(feedback):
    """(2.4)-(2.5), (2.8)-(2.9): the gains give s² + 2ζω s + ω², checked on the coefficients
    and on a direct rigid-body model Jeq,m ω̇m + beq,m ωm = τ with the PI closed around it."""
    omega, zeta = 12.0, 0.8
    tune = eq.pi_motor_side if feedback == "motor" else eq.pi_load_side
    gains = tune(DRIVE, omega, zeta)
    poly = (eq.rigid_poly_motor_feedback if feedback == "motor"
            else eq.rigid_poly_load_feedback)(DRIVE, gains)
    assert poly == (pytest.approx(2 * zeta * omega), pytest.approx(omega**2))
    # rigid model [θm, ωm] with τ = -Kp ω_fb - Ki θ_fb, ω_fb = g ωm
    g = 1.0 if feedback == "motor" else DRIVE.r_motor / DRIVE.r_load
    j, b = eq.inertia_motor_side(DRIVE), eq.damping_motor_side(DRIVE)
    a = np.array([[0.0, 1.0], [-g * gains.ki / j, -(b + g * gains.kp) / j]])
    expected = np.roots([1.0, 2 * zeta * omega, omega**2])
    assert np.sort_complex(np.linalg.eigvals(a)) == pytest.approx(np.sort_complex(expected))
    again = eq.pi_from_poles(DRIVE, tuple(expected), feedback)
    assert (again.kp, again.ki) == (pytest.approx(gains.kp), pytest.approx(gains.ki))


@pytest.mark.parametrize("feedback", ["motor", "load"])
def test_rigid_poles_are_the_stiff_belt_limit(feedback):
    """The rigid model is the Kb → ∞ limit of (2.17)/(2.19): the two slow roots of the full
    4th-order loop tend to the roots of (2.4)/(2.8) (here within 1e-5 at Kb = 1e10 N/m)."""
    gains = SpeedPI(kp=0.8, ki=4.0)
    stiff = DRIVE.with_stiffness(1e10)
    slow, _ = split_eigenvalues(belt.homogeneous_matrix(stiff, gains, feedback), 2)
    a1, a0 = (eq.rigid_poly_motor_feedback if feedback == "motor"
              else eq.rigid_poly_load_feedback)(stiff, gains)
    rigid = np.sort_complex(np.roots([1.0, a1, a0]))
    assert np.max(np.abs(np.sort_complex(slow) - rigid)) < 1e-5 * np.max(np.abs(rigid))


def test_pi_from_poles_rejects_non_conjugate_pairs_and_unknown_feedback():
    with pytest.raises(ValueError, match="conjugate"):
        eq.pi_from_poles(DRIVE, (-1 + 1j, -2 + 1j))
    with pytest.raises(ValueError, match="feedback"):
        eq.pi_from_poles(DRIVE, (-1.0, -2.0), "both")


def test_hswl_speed_loop_gains_from_the_data_file():
    """The data file's speed loop (10 rad/s, ζ = 1) gives Kpm = 2ωJeq,m - beq,m, Kim = ω²Jeq,m."""
    drive = hswl_unwind_belt_drive("36mm")
    gains = eq.pi_motor_side(drive, 10.0, 1.0)
    jeq = drive.j_motor + 4.0 * drive.j_load  # (R1/R2)² = 4
    assert gains.ki == pytest.approx(100.0 * jeq, rel=1e-4)
    assert gains.kp == pytest.approx(20.0 * jeq - (drive.b_motor + 4.0 * drive.b_load), rel=1e-4)
