"""Drive trains of a branched line (docs/branching.md, "Drive trains"): compliant transmissions
(belt, shaft, backlash) and drive brakes with the chain's keys and physics (docs/drivetrain.md;
the chain's ``sim.core.plan`` and ``drive_table``). Plan-side tables for the compiled
``sim.branches.loop.transmission``, the operating point's motor speeds and twists, and the
linear model's rows.
"""

from __future__ import annotations

import numpy as np

from webline.model.web_graph import BranchedLine
from webline.physics import roll
from webline.profiles import breakpoints
from webline.sim.branches.loop import layout as B
from webline.spec.schema import BeltSpec, DirectSpec, IdleSpec, ShaftSpec


def compliant_drives(line: BranchedLine) -> list[int]:
    """Drive numbers whose transmission is a belt or a shaft (not direct)."""
    return [d for d, i in enumerate(line.drives)
            if not isinstance(line.spec.rollers[i].drive.transmission,  # type: ignore[union-attr]
                              DirectSpec)]


def train_columns(line: BranchedLine, offsets: np.ndarray, nodes: np.ndarray, di: np.ndarray,
                  df: np.ndarray) -> None:
    """Fill the drive-train columns (``layout`` DI_TSTATE, D_KTRANS...D_FEEDBACK) and give
    each compliant drive two states (motor speed, twist) at the end of the state vector
    (``offsets[O_N]`` grows). Its node keeps the roller's inertia and friction without the
    motor's (the motor is on the far side of the compliance) and gets no torque directly
    (N_RATIO 0)."""
    di[:, B.DI_TSTATE] = -1
    for d, i in enumerate(line.drives):
        roller = line.spec.rollers[i]
        assert not isinstance(roller, IdleSpec)
        drive = roller.drive
        t = drive.transmission
        row = df[d]
        row[B.D_RATIO] = drive.ratio
        row[B.D_JMOTOR], row[B.D_BMOTOR] = drive.motor_inertia, drive.motor_friction
        row[B.D_FEEDBACK] = 1.0 if drive.feedback == "motor" else 0.0
        if isinstance(t, DirectSpec):
            continue
        if isinstance(t, BeltSpec):  # the tight side seen from the load shaft (2.10)
            row[B.D_KTRANS] = t.stiffness * t.load_pulley_radius**2
            row[B.D_CTRANS] = t.damping * t.load_pulley_radius**2
        else:
            assert isinstance(t, ShaftSpec)
            row[B.D_KTRANS], row[B.D_CTRANS] = t.stiffness, t.damping
        if t.backlash is not None:  # Remark 3.3.1: 2Δa backwards, 2Δ(1 - a) forwards
            row[B.D_GAPNEG] = 2.0 * t.backlash.gap * t.backlash.asymmetry
            row[B.D_GAPPOS] = 2.0 * t.backlash.gap * (1.0 - t.backlash.asymmetry)
        n = drive.ratio
        di[d, B.DI_TSTATE] = offsets[B.O_N]
        offsets[B.O_N] += 2
        nodes[i, B.N_RATIO] = 0.0
        nodes[i, B.N_JCONST] -= n * n * drive.motor_inertia
        nodes[i, B.N_VISCOUS] -= n * n * drive.motor_friction
        nodes[i, B.N_INVJ] = 1.0 / nodes[i, B.N_JCONST]


def brake_rows(line: BranchedLine, profiles: list[tuple[np.ndarray, np.ndarray]]) -> np.ndarray:
    """Disturbance rows (``layout`` DIST_DRAG) of the drives' brakes: a torque on the roller
    shaft opposing its rotation (thesis 4.12), acting as Coulomb friction does, as on a chain
    (``drive.brake``); each brake's profile is appended to ``profiles``."""
    rows = []
    for i in line.drives:
        brake = line.spec.rollers[i].drive.brake  # type: ignore[union-attr]
        if brake is not None:
            rows.append((B.DIST_DRAG, i, len(profiles), 0.0, 0.0))
            profiles.append(breakpoints(brake))
    return np.array(rows, dtype=float).reshape(-1, B.DS_COLS)


def steady_trains(x: np.ndarray, offsets: np.ndarray, di: np.ndarray, df: np.ndarray,
                  rolls: np.ndarray) -> None:
    """Set each compliant drive's motor speed n ω and the twist that passes the load-side
    torque n τ - n² (b_m ω + J_m dω/dt) (the chain's ``Plan._transmission_state``) in ``x``,
    the torques ``x``'s own; dω/dt of a roll drive = -ω dR/dt / R (it holds its surface
    speed as the radius changes), else 0. A twist past the dead zone on the loaded side."""
    off_w, off_r, off_tq = offsets[B.O_OMEGA], offsets[B.O_RADIUS], offsets[B.O_TORQUE]
    for d in range(di.shape[0]):
        state = int(di[d, B.DI_TSTATE])
        if state < 0:
            continue
        row = df[d]
        i, j = int(di[d, B.DI_NODE]), int(di[d, B.DI_ROLL])
        n, omega = row[B.D_RATIO], x[off_w + i]
        accel = 0.0
        if j >= 0:
            radius = x[off_r + j]
            rate = roll.radius_rate(radius * omega, radius, rolls[j, B.R_THICK],
                                    rolls[j, B.R_DIR])
            accel = -omega * rate / radius
        x[state] = n * omega
        load = n * x[off_tq + d] - n * n * (row[B.D_JMOTOR] * accel + row[B.D_BMOTOR] * omega)
        gap = row[B.D_GAPPOS] if load > 0 else (-row[B.D_GAPNEG] if load < 0 else 0.0)
        x[state + 1] = load / row[B.D_KTRANS] + gap


def train_states(line: BranchedLine, di: np.ndarray) -> list[tuple[int, str]]:
    """(state number, name) of each compliant drive's motor speed and twist."""
    out = []
    for d, i in enumerate(line.drives):
        state = int(di[d, B.DI_TSTATE])
        if state >= 0:
            name = line.spec.rollers[i].name
            out += [(state, f"{name}_motor_omega"), (state + 1, f"{name}_twist")]
    return out


def tuning_inertia(di: np.ndarray, df: np.ndarray, d: int,
                   inertia: float) -> tuple[float, float]:
    """(inertia the speed PI is tuned for, inertia its crossover sees above the transmission's
    resonance) [kg·m²] of drive ``d`` given its node's ``inertia``: the chain's rule
    (``drive_table._pi_columns``): the reflected motor n² J_m adds across a compliant
    transmission, and a motor-side loop sees only it."""
    row = df[d]
    if di[d, B.DI_TSTATE] < 0:
        return inertia, inertia
    motor = row[B.D_RATIO] ** 2 * row[B.D_JMOTOR]
    return inertia + motor, motor if row[B.D_FEEDBACK] > 0 else inertia + motor


def train_motor_omega(offsets: np.ndarray, di: np.ndarray, df: np.ndarray,
                      x: np.ndarray) -> np.ndarray:
    """A run's motor speed / n [rad/s] per drive (at the load shaft: the roller's own for a
    direct drive), records x drives, from the records ``x``. The twist θ_m/n - θ_L is
    ``sim.results.derived_signals.transmission_twist``."""
    omega = np.empty((len(x), di.shape[0]))
    for d in range(di.shape[0]):
        state, i = int(di[d, B.DI_TSTATE]), int(di[d, B.DI_NODE])
        omega[:, d] = (x[:, offsets[B.O_OMEGA] + i] if state < 0
                       else x[:, state] / df[d, B.D_RATIO])
    return omega
