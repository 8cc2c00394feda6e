"""Singular perturbation of the PI-controlled belt drive (thesis 2.26-2.34), with ε = 1/√Kb.

With zero reference the PI's integral is minus the fed-back angle, so the loop is the 4-state
system ``belt.homogeneous_matrix``. The coordinates of (2.27),
    θc = (Jm θm + JL r θL)/J0,  θs = θm - r θL,  r = R2/R1, J0 = Jm + JL,
with x = [θc, θ̇c] (slow) and z = [θs/ε², θ̇s/ε] = [Kb θs, √Kb θ̇s] (fast), put it in the standard
form (2.26) with A22(0) nonsingular. ``belt_sp_form`` builds the blocks by applying this change of
variables to the physical matrix (so it holds for either feedback); ``thesis_blocks_2_28`` is the
printed (2.28) for the motor-side PI, which the tests show to be right.

The fast characteristic polynomial to first order in ε, derived (E-2.3, E-2.4):
    ψf(p) = p² + a1 p + a0 + O(ε²),  a0 = Jeq/(Jm JL) = R1²/Jm + R2²/JL,
    a1 = ε [R1² JL² (bm + Kpm) + R2² Jm² bL - R1 R2 JL Jm KpL] / (Jm JL Jeq),
(Kpm = 0 for load-side feedback, KpL = 0 for motor-side), Jeq = R2² Jm + R1² JL. The same a1
follows from the modal damping of the two-inertia belt mode, in which the motor moves as
-R1/Jm and the load as +R2/JL per unit of belt force. The printed (2.32) and (2.34) swap R1 and
R2 in a0 and in the gain terms, drop the friction from (2.32) and give the friction the wrong
sign in (2.34).

Consequences: with motor-side PI the belt mode decays at -a1/(2ε) = -[R1² JL² (bm + Kpm) +
R2² Jm² bL]/(2 Jm JL Jeq) for any Kpm > -bm; with load-side PI it is unstable as soon as
KpL > bm R1 JL/(R2 Jm) + bL R2 Jm/(R1 JL) (``load_feedback_threshold``): for all KpL > 0
only without friction, as the thesis finds.
"""

from __future__ import annotations

import numpy as np

from webline.analysis.drivetrain.belt import homogeneous_matrix
from webline.analysis.drivetrain.params import BeltDrive, SpeedPI
from webline.analysis.drivetrain.singular_perturbation import SingularlyPerturbed


def _coordinates(drive: BeltDrive) -> np.ndarray:
    """T0 with [θc, θ̇c, θs, θ̇s] = T0 [θm, ωm, θL, ωL] (2.27)."""
    jm, jl = drive.j_motor, drive.j_load
    j0, r = jm + jl, drive.speed_ratio
    return np.array([[jm / j0, 0.0, jl * r / j0, 0.0],
                     [0.0, jm / j0, 0.0, jl * r / j0],
                     [1.0, 0.0, -r, 0.0],
                     [0.0, 1.0, 0.0, -r]])


def _spring_part(drive: BeltDrive) -> np.ndarray:
    """dA/dKb of the physical matrix (the belt force terms of 2.10 per unit Kb)."""
    r1, r2, jm, jl = drive.r_motor, drive.r_load, drive.j_motor, drive.j_load
    out = np.zeros((4, 4))
    out[1, 0], out[1, 2] = -r1 * r1 / jm, r1 * r2 / jm
    out[3, 0], out[3, 2] = r1 * r2 / jl, -r2 * r2 / jl
    return out


def belt_sp_form(drive: BeltDrive, gains: SpeedPI, feedback: str = "motor") -> SingularlyPerturbed:
    """The PI loop ('motor' 2.3 or 'load' 2.7) in the standard form (2.26), ε = 1/√Kb [√(m/N)]."""
    t0 = _coordinates(drive)
    t0_inv = np.linalg.inv(t0)
    spring = _spring_part(drive)
    rest = homogeneous_matrix(drive.with_stiffness(0.0), gains, feedback)
    m0, ms = t0 @ rest @ t0_inv, t0 @ spring @ t0_inv
    eps = 1.0 / np.sqrt(drive.stiffness)
    # [x, z] = S [θc, θ̇c, θs, θ̇s], S = diag(1, 1, 1/ε², 1/ε); then the fast rows times ε.
    scale = np.array([1.0, 1.0, eps**-2, eps**-1])
    m = scale[:, None] * (m0 + ms / eps**2) / scale[None, :]
    a11, a12 = m[:2, :2], m[:2, 2:]
    a21, a22 = eps * m[2:, :2], eps * m[2:, 2:]
    return SingularlyPerturbed(a11=a11, a12=a12, a21=a21, a22=a22, eps=float(eps))


def thesis_blocks_2_28(drive: BeltDrive, gains: SpeedPI) -> SingularlyPerturbed:
    """The blocks exactly as printed in (2.28) for the motor-side PI (they are correct)."""
    jm, jl, bm, bl = drive.j_motor, drive.j_load, drive.b_motor, drive.b_load
    r1, r2 = drive.r_motor, drive.r_load
    kp, ki = gains.kp, gains.ki
    j0 = jm + jl
    eps = 1.0 / np.sqrt(drive.stiffness)
    f1, f21, f22 = -ki / j0, -ki * jl / j0**2, (r2**2 - r1**2) / j0
    f3, f4 = -(kp + bm + bl) / j0, (bl * jm - bm * jl - kp * jl) / j0**2
    g1, g21 = -ki / jm, -ki * jl**2 / (jm * jl * j0)
    g22 = -(r1**2 * jl + r2**2 * jm) / (jm * jl)
    g3 = (bl * jm - bm * jl - kp * jl) / (jm * jl)
    g4 = -(kp * jl**2 + bm * jl**2 + bl * jm**2) / (jm * jl * j0)
    return SingularlyPerturbed(
        a11=np.array([[0.0, 1.0], [f1, f3]]),
        a12=np.array([[0.0, 0.0], [eps**2 * f21 + f22, eps * f4]]),
        a21=np.array([[0.0, 0.0], [g1, g3]]),
        a22=np.array([[0.0, 1.0], [eps**2 * g21 + g22, eps * g4]]),
        eps=float(eps),
    )


def _gain_terms(gains: SpeedPI, feedback: str) -> tuple[float, float]:
    if feedback not in ("motor", "load"):
        raise ValueError(f"feedback must be 'motor' or 'load', got {feedback!r}")
    return (gains.kp, 0.0) if feedback == "motor" else (0.0, gains.kp)


def fast_poly_first_order(drive: BeltDrive, gains: SpeedPI,
                          feedback: str = "motor") -> tuple[float, float]:
    """(a1, a0) of ψf(p) = p² + a1 p + a0 + O(ε²), derived (module docstring; E-2.3, E-2.4).

    Replaces the printed (2.32) (α'1, α'2) and (2.34) (-β'1, β'0). In the stretched scale
    p = ε s with ε = 1/√Kb (Kb in N/m): a1/ε is in 1/s and a0/ε² in 1/s².
    """
    kpm, kpl = _gain_terms(gains, feedback)
    jm, jl, r1, r2 = drive.j_motor, drive.j_load, drive.r_motor, drive.r_load
    eps = 1.0 / np.sqrt(drive.stiffness)
    damping = (r1**2 * jl**2 * (drive.b_motor + kpm) + r2**2 * jm**2 * drive.b_load
               - r1 * r2 * jl * jm * kpl)
    return float(eps * damping / (jm * jl * drive.j_sum)), drive.j_sum / (jm * jl)


def printed_fast_poly(drive: BeltDrive, gains: SpeedPI,
                      feedback: str = "motor") -> tuple[float, float]:
    """(a1, a0) of the fast polynomial p² + a1 p + a0 exactly as printed: (2.32) for 'motor'
    (a1 = α'1, a0 = α'2), (2.34) for 'load' (a1 = -β'1, a0 = β'0)."""
    jm, jl, bm, bl = drive.j_motor, drive.j_load, drive.b_motor, drive.b_load
    r1, r2 = drive.r_motor, drive.r_load
    eps = 1.0 / np.sqrt(drive.stiffness)
    jeq = r2**2 * jm + r1**2 * jl
    a0 = (r2**2 * jl + r1**2 * jm) / (jm * jl)
    if feedback == "motor":
        return float(r2**2 * gains.kp * jl * eps / (jm * jeq)), a0
    _gain_terms(gains, feedback)
    return float(-(r2**2 * bm + r1**2 * bl + r2**2 * gains.kp) * eps / jeq), a0


def belt_mode_decay_rate(drive: BeltDrive, gains: SpeedPI, feedback: str = "motor") -> float:
    """Real part [1/s] of the belt-mode poles for a stiff belt, -a1/(2ε): finite as Kb → ∞.

    Negative: the belt mode decays; positive: the loop destabilises it.
    """
    a1, _ = fast_poly_first_order(drive, gains, feedback)
    return -0.5 * a1 * np.sqrt(drive.stiffness)


def load_feedback_threshold(drive: BeltDrive) -> float:
    """KpL [N·m·s] above which load-side PI makes the belt mode unstable (first order in ε):
    bm R1 JL/(R2 Jm) + bL R2 Jm/(R1 JL). Zero without friction: the thesis's 'for all KpL > 0'.
    """
    jm, jl, r1, r2 = drive.j_motor, drive.j_load, drive.r_motor, drive.r_load
    return drive.b_motor * r1 * jl / (r2 * jm) + drive.b_load * r2 * jm / (r1 * jl)
