"""Belt drive with a compliant belt: state space, transfer functions, characteristic polynomials,
sensitivities to the belt stiffness, natural frequencies and the Lyapunov function of Theorem
2.2.1 (thesis 2.10-2.25, 2.35-2.41).

Model (2.10), from the Lagrangian of (2.11)-(2.13):
    Jm ω̇m = τm - bm ωm - R1 Kb (R1 θm - R2 θL),
    JL ω̇L = τL - bL ωL + R2 Kb (R1 θm - R2 θL).
Eliminating the angles (θ = ω/s) gives (2.14)-(2.15) with D(s) = s⁻¹ det(...):
    D(s) = Jm JL s³ + (bL Jm + bm JL) s² + (Kb Jeq + bm bL) s + Kb beq,
    Jeq = R2² Jm + R1² JL,  beq = R2² bm + R1² bL   (the printed 2.15b has JL for bL: E-2.1).

With a PI on the motor speed (2.3) the closed-loop polynomial is s D(s) + N(s)(Kp s + Ki),
N(s) = JL s² + bL s + R2² Kb, which divided by Jm JL is (2.19) = (2.40); with a PI on the load
speed (2.7) it is s D(s) + R1 R2 Kb (Kp s + Ki), i.e. (2.17).

State vector [θm, ωm, θL, ωL] ([rad, rad/s, rad, rad/s]); with a PI controller its integral
ξ = ∫(ω_ref - ω_fb) [rad] is appended.
"""

from __future__ import annotations

from dataclasses import dataclass

import control
import numpy as np

from webline.analysis.drivetrain.params import BeltDrive, SpeedPI

STATES = ("theta_m", "omega_m", "theta_l", "omega_l")


def _check_feedback(feedback: str) -> None:
    if feedback not in ("motor", "load"):
        raise ValueError(f"feedback must be 'motor' or 'load', got {feedback!r}")


def open_loop_matrices(drive: BeltDrive) -> tuple[np.ndarray, np.ndarray]:
    """(A, B) of (2.10): states [θm, ωm, θL, ωL], inputs [τm, τL] [N·m]."""
    jm, jl, bm, bl = drive.j_motor, drive.j_load, drive.b_motor, drive.b_load
    r1, r2, kb = drive.r_motor, drive.r_load, drive.stiffness
    a = np.array([
        [0.0, 1.0, 0.0, 0.0],
        [-kb * r1 * r1 / jm, -bm / jm, kb * r1 * r2 / jm, 0.0],
        [0.0, 0.0, 0.0, 1.0],
        [kb * r1 * r2 / jl, 0.0, -kb * r2 * r2 / jl, -bl / jl],
    ])
    b = np.array([[0.0, 0.0], [1.0 / jm, 0.0], [0.0, 0.0], [0.0, 1.0 / jl]])
    return a, b


def open_loop_ss(drive: BeltDrive) -> control.StateSpace:
    """(2.10) as a named python-control system: inputs tau_m, tau_l [N·m]; outputs omega_m,
    omega_l [rad/s]."""
    a, b = open_loop_matrices(drive)
    c = np.array([[0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 0.0, 1.0]])
    return control.ss(a, b, c, np.zeros((2, 2)), states=list(STATES),
                      inputs=["tau_m", "tau_l"], outputs=["omega_m", "omega_l"],
                      name="belt_drive")


def d_poly(drive: BeltDrive) -> np.ndarray:
    """Coefficients (highest power first) of D(s) of (2.15c), corrected beq (E-2.1)."""
    jm, jl, bm, bl = drive.j_motor, drive.j_load, drive.b_motor, drive.b_load
    kb = drive.stiffness
    return np.array([jm * jl, bl * jm + jl * bm, kb * drive.j_sum + bm * bl, kb * drive.b_sum])


def open_loop_tf(drive: BeltDrive) -> tuple[control.TransferFunction, control.TransferFunction]:
    """(ωm/τm, ωL/τm) of (2.14a), (2.14b) [rad/(N·m·s)]."""
    den = d_poly(drive)
    num_m = [drive.j_load, drive.b_load, drive.r_load**2 * drive.stiffness]
    num_l = [drive.r_motor * drive.r_load * drive.stiffness]
    return (control.tf(num_m, den, inputs="tau_m", outputs="omega_m", name="G_tau_omega_m"),
            control.tf(num_l, den, inputs="tau_m", outputs="omega_l", name="G_tau_omega_l"))


def closed_loop_matrices(drive: BeltDrive, gains: SpeedPI,
                         feedback: str = "motor") -> tuple[np.ndarray, np.ndarray]:
    """(A, B) of (2.10) with the PI (2.3) ('motor') or (2.7) ('load').

    States [θm, ωm, θL, ωL, ξ], ξ̇ = ω_ref - ω_fb; input ω_ref [rad/s] (ωdm for 'motor',
    ωdL for 'load'). The positions enter only through the stretch, so A has one zero
    eigenvalue (the rigid rotation) besides the four roots of (2.17)/(2.19).
    """
    _check_feedback(feedback)
    a4, b4 = open_loop_matrices(drive)
    k = 1 if feedback == "motor" else 3  # index of the fed-back speed
    a = np.zeros((5, 5))
    a[:4, :4] = a4
    a[:4, k] -= b4[:, 0] * gains.kp
    a[:4, 4] = b4[:, 0] * gains.ki
    a[4, k] = -1.0
    b = np.zeros(5)
    b[:4] = b4[:, 0] * gains.kp
    b[4] = 1.0
    return a, b


def homogeneous_matrix(drive: BeltDrive, gains: SpeedPI, feedback: str = "motor") -> np.ndarray:
    """4x4 A of the loop with zero reference, the integral acting on the angle:
    τm = -Kp ω_fb - Ki θ_fb (the device behind 2.27-2.28). Its eigenvalues are the roots of
    (2.19) ('motor') or (2.17) ('load')."""
    _check_feedback(feedback)
    a, b = open_loop_matrices(drive)
    k = 1 if feedback == "motor" else 3
    a = a.copy()
    a[:, k] -= b[:, 0] * gains.kp
    a[:, k - 1] -= b[:, 0] * gains.ki
    return a


def closed_loop_ss(drive: BeltDrive, gains: SpeedPI, feedback: str = "motor") -> control.StateSpace:
    """Closed loop as a named system: input omega_ref, outputs omega_m, omega_l [rad/s]."""
    a, b = closed_loop_matrices(drive, gains, feedback)
    c = np.zeros((2, 5))
    c[0, 1] = c[1, 3] = 1.0
    return control.ss(a, b[:, None], c, np.zeros((2, 1)), states=[*STATES, "xi"],
                      inputs=["omega_ref"], outputs=["omega_m", "omega_l"],
                      name=f"belt_drive_pi_{feedback}")


def char_poly(drive: BeltDrive, gains: SpeedPI, feedback: str = "motor") -> np.ndarray:
    """Monic closed-loop polynomial [1, c3, c2, c1, c0]: (2.19)/(2.40) for 'motor', (2.17) for
    'load' (units 1/s, 1/s², 1/s³, 1/s⁴)."""
    _check_feedback(feedback)
    jm, jl, bm, bl = drive.j_motor, drive.j_load, drive.b_motor, drive.b_load
    r1, r2, kb = drive.r_motor, drive.r_load, drive.stiffness
    kp, ki = gains.kp, gains.ki
    j = jm * jl
    base = [1.0, (bm * jl + jm * bl) / j, (kb * drive.j_sum + bm * bl) / j,
            kb * drive.b_sum / j, 0.0]
    if feedback == "load":
        add = [0.0, 0.0, 0.0, r1 * r2 * kb * kp / j, r1 * r2 * kb * ki / j]
    else:
        add = [0.0, kp * jl / j, (kp * bl + ki * jl) / j, (r2**2 * kb * kp + ki * bl) / j,
               r2**2 * kb * ki / j]
    return np.array(base) + np.array(add)


def closed_loop_tf(drive: BeltDrive, gains: SpeedPI,
                   feedback: str = "motor") -> control.TransferFunction:
    """ωL/ω_ref: (2.18) = (2.39) for 'motor' (ω_ref = ωdm), (2.16) for 'load' (ωdL) [-]."""
    k = drive.r_motor * drive.r_load * drive.stiffness / (drive.j_motor * drive.j_load)
    return control.tf([k * gains.kp, k * gains.ki], char_poly(drive, gains, feedback),
                      inputs="omega_ref", outputs="omega_l", name=f"omega_l_per_ref_{feedback}")


def velocity_mode_tf(drive: BeltDrive) -> control.TransferFunction:
    """T(s) = ωL/ωm of (2.36) with the motor in perfect velocity control [-]."""
    kb, r1, r2 = drive.stiffness, drive.r_motor, drive.r_load
    return control.tf([kb * r1 * r2], [drive.j_load, drive.b_load, kb * r2**2],
                      inputs="omega_m", outputs="omega_l", name="T_velocity_mode")


def velocity_mode_sensitivity(drive: BeltDrive) -> control.TransferFunction:
    """S_Kb^T = (∂T/∂Kb)(Kb/T) of (2.38) = s(s + bL/JL)/(s² + (bL/JL)s + Kb R2²/JL) [-]."""
    jl, bl = drive.j_load, drive.b_load
    return control.tf([jl, bl, 0.0], [jl, bl, drive.stiffness * drive.r_load**2],
                      name="S_T_Kb")


def torque_mode_sensitivity(drive: BeltDrive, gains: SpeedPI) -> control.TransferFunction:
    """S_Kb^G1 of (2.41) for G1 = ωL/ωdm (2.39) with the motor in torque mode [-].

    = (s⁴ + α3 s³ + γ2 s² + γ1 s)/ψm(s): ψm minus the terms proportional to Kb.
    """
    psi = char_poly(drive, gains, "motor")
    stiff = char_poly(drive.with_stiffness(0.0), gains, "motor")  # the Kb-free part
    return control.tf(stiff, psi, name="S_G1_Kb")


@dataclass(frozen=True)
class NaturalFrequencies:
    """Belt-mode frequencies [rad/s]; ``*_hz`` give them in Hz.

    velocity_mode: ωn of (2.37), sqrt(Kb R2²/JL) (motor held at its speed).
    torque_mode: sqrt(Kb (R1²/Jm + R2²/JL)), the two-inertia mode (motor torque held).
    velocity_mode_damped, torque_mode_damped: imaginary part of the lightly damped poles of
    (2.36) and of D(s) (2.15c) with the friction.
    """

    velocity_mode: float
    torque_mode: float
    velocity_mode_damped: float
    torque_mode_damped: float

    @property
    def velocity_mode_hz(self) -> float:
        return self.velocity_mode / (2.0 * np.pi)

    @property
    def torque_mode_hz(self) -> float:
        return self.torque_mode / (2.0 * np.pi)


def natural_frequencies(drive: BeltDrive) -> NaturalFrequencies:
    """Natural frequencies of the belt mode, motor in velocity mode and in torque mode."""
    kb, r1, r2 = drive.stiffness, drive.r_motor, drive.r_load
    jm, jl = drive.j_motor, drive.j_load
    vel = np.roots([jl, drive.b_load, kb * r2**2])
    tor = np.roots(d_poly(drive))
    return NaturalFrequencies(
        velocity_mode=float(np.sqrt(kb * r2**2 / jl)),
        torque_mode=float(np.sqrt(kb * (r1**2 / jm + r2**2 / jl))),
        velocity_mode_damped=float(np.max(np.abs(vel.imag))),
        torque_mode_damped=float(np.max(np.abs(tor.imag))),
    )


def _accelerations(drive: BeltDrive, gains: SpeedPI, omega_ref: float,
                   x: np.ndarray) -> tuple[float, float]:
    a, b = closed_loop_matrices(drive, gains, "motor")
    dx = a @ x + b * omega_ref
    return float(dx[1]), float(dx[3])


def lyapunov(drive: BeltDrive, gains: SpeedPI, omega_ref: float, x: np.ndarray) -> float:
    """V of (2.23) at the state x = [θm, ωm, θL, ωL, ξ] of the motor-side PI loop and constant
    reference ωdm = ``omega_ref`` [rad/s]:

    V = ½ [Jm ėm² + JL ėL² + Kb (R1 em - R2 eL)² + Kim em²],
    em = ωm - ωdm, eL = ωL - (R1/R2) ωdm, ė = the accelerations from (2.10) [J/s²].
    """
    em = x[1] - omega_ref
    stretch_rate = drive.r_motor * x[1] - drive.r_load * x[3]  # = R1 em - R2 eL
    dem, del_ = _accelerations(drive, gains, omega_ref, x)
    return 0.5 * (drive.j_motor * dem**2 + drive.j_load * del_**2
                  + drive.stiffness * stretch_rate**2 + gains.ki * em**2)


def lyapunov_rate(drive: BeltDrive, gains: SpeedPI, omega_ref: float, x: np.ndarray) -> float:
    """dV/dt of (2.24): -(bm + Kpm) ėm² - bL ėL² [J/s³] (<= 0 for Kpm >= -bm)."""
    dem, del_ = _accelerations(drive, gains, omega_ref, x)
    return -(drive.b_motor + gains.kp) * dem**2 - drive.b_load * del_**2
