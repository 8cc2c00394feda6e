"""Rigid-belt (equivalent inertia) analysis and PI tuning by pole placement (thesis 2.1-2.9).

With a rigid belt R1 θm = R2 θL, so the kinetic energy ½ Jm θ̇m² + ½ JL θ̇L² is
½ (Jm + (R1/R2)² JL) θ̇m² = ½ (JL + (R2/R1)² Jm) θ̇L², and likewise the dissipation: the
equivalent inertia and damping referred to the motor side (2.1) or the load side (2.6).

* Motor-side PI (2.3), τm = Kpm (ωdm - ωm) + Kim ∫(ωdm - ωm), on Jeq,m ω̇m + beq,m ωm = τm:
  Jeq,m s² + (beq,m + Kpm) s + Kim = 0, i.e. (2.4)-(2.5) once multiplied through by R2².
* Load-side PI (2.7), τm = KpL (ωdL - ωL) + KiL ∫(ωdL - ωL) with ωL = (R1/R2) ωm:
  Jeq,m s² + (beq,m + (R1/R2) KpL) s + (R1/R2) KiL = 0, which is (2.8)-(2.9).

Gains follow by matching s² + 2ζω s + ω² (or any two poles). Chapter 2's point is that these
rigid models hide the belt mode: see ``belt`` and ``singular_perturbation``.
"""

from __future__ import annotations

from webline.analysis.drivetrain.params import BeltDrive, SpeedPI


def inertia_motor_side(drive: BeltDrive) -> float:
    """Jeq,m [kg·m²] of (2.1): Jm + (R1/R2)² JL."""
    return drive.j_motor + (drive.r_motor / drive.r_load) ** 2 * drive.j_load


def damping_motor_side(drive: BeltDrive) -> float:
    """beq,m [N·m·s] of (2.1): bm + (R1/R2)² bL."""
    return drive.b_motor + (drive.r_motor / drive.r_load) ** 2 * drive.b_load


def inertia_load_side(drive: BeltDrive) -> float:
    """Jeq,L [kg·m²] of (2.6): JL + (R2/R1)² Jm."""
    return drive.j_load + (drive.r_load / drive.r_motor) ** 2 * drive.j_motor


def damping_load_side(drive: BeltDrive) -> float:
    """beq,L [N·m·s] of (2.6): bL + (R2/R1)² bm."""
    return drive.b_load + (drive.r_load / drive.r_motor) ** 2 * drive.b_motor


def rigid_poly_motor_feedback(drive: BeltDrive, gains: SpeedPI) -> tuple[float, float]:
    """(α1 [1/s], α0 [1/s²]) of (2.5): s² + α1 s + α0 with the motor-side PI (2.3).

    α1 = (R2² bm + R1² bL + Kpm R2²)/(R1² JL + R2² Jm), α0 = Kim R2²/(R1² JL + R2² Jm).
    """
    r1, r2 = drive.r_motor, drive.r_load
    j = drive.j_sum
    return ((r2**2 * drive.b_motor + r1**2 * drive.b_load + gains.kp * r2**2) / j,
            gains.ki * r2**2 / j)


def rigid_poly_load_feedback(drive: BeltDrive, gains: SpeedPI) -> tuple[float, float]:
    """(β1 [1/s], β0 [1/s²]) of (2.9): s² + β1 s + β0 with the load-side PI (2.7).

    β1 = (R2² bm + R1² bL + KpL R1 R2)/(R1² JL + R2² Jm), β0 = KiL R1 R2/(R1² JL + R2² Jm).
    """
    r1, r2 = drive.r_motor, drive.r_load
    j = drive.j_sum
    return ((r2**2 * drive.b_motor + r1**2 * drive.b_load + gains.kp * r1 * r2) / j,
            gains.ki * r1 * r2 / j)


def _gains_for(j_eq: float, b_eq: float, gain: float, sum_poles: float,
               product_poles: float) -> SpeedPI:
    # j s² + (b + g kp) s + g ki = j (s² - sum s + product)
    return SpeedPI(kp=(-j_eq * sum_poles - b_eq) / gain, ki=j_eq * product_poles / gain)


def pi_motor_side(drive: BeltDrive, bandwidth: float, damping: float = 1.0) -> SpeedPI:
    """Motor-side PI gains (2.3) that put the rigid poles (2.4) at s² + 2ζω s + ω².

    ``bandwidth`` ω [rad/s], ``damping`` ζ [-]: Kpm = 2ζω Jeq,m - beq,m, Kim = ω² Jeq,m.
    A negative Kpm means the friction alone damps more than asked for.
    """
    return _gains_for(inertia_motor_side(drive), damping_motor_side(drive), 1.0,
                      -2.0 * damping * bandwidth, bandwidth**2)


def pi_load_side(drive: BeltDrive, bandwidth: float, damping: float = 1.0) -> SpeedPI:
    """Load-side PI gains (2.7) that put the rigid poles (2.8) at s² + 2ζω s + ω².

    KpL = (R1/R2)(2ζω Jeq,L - beq,L) = (R2/R1)(2ζω Jeq,m - beq,m), KiL = (R2/R1) ω² Jeq,m.
    """
    return _gains_for(inertia_motor_side(drive), damping_motor_side(drive),
                      drive.r_motor / drive.r_load, -2.0 * damping * bandwidth, bandwidth**2)


def pi_from_poles(drive: BeltDrive, poles: tuple[complex, complex],
                  feedback: str = "motor") -> SpeedPI:
    """PI gains that put the rigid poles at ``poles`` [1/s] (a real pair or a conjugate pair),
    for ``feedback`` 'motor' (2.3)-(2.5) or 'load' (2.7)-(2.9)."""
    p1, p2 = poles
    total, product = p1 + p2, p1 * p2
    if abs(total.imag if isinstance(total, complex) else 0.0) > 1e-9 * (1 + abs(total)):
        raise ValueError(f"poles must be real or a conjugate pair, got {poles}")
    gain = 1.0 if feedback == "motor" else drive.r_motor / drive.r_load
    if feedback not in ("motor", "load"):
        raise ValueError(f"feedback must be 'motor' or 'load', got {feedback!r}")
    return _gains_for(inertia_motor_side(drive), damping_motor_side(drive), gain,
                      complex(total).real, complex(product).real)
