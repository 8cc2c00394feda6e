"""Decentralized state-feedback gains: from and to closed-loop section matrices, into a line.

Conventions (webline's, E-6.3): every motor torque is positive in the web direction; a section
with state x_i = (T - T_ref, V - V_ref) [N, m/s] (x_i = V - V_ref for the master) gets
U_i = -K_iᵀ x_i with K_i = (K_T [N·m/N], K_V [N·m·s/m]) (K_T = 0 for the master), so the
closed-loop section matrix is Ā_i = A_i - B_i K_iᵀ with B_i = (0, n r / J) (6.43).
Conversely K_iᵀ = (A_i - Ā_i)[last row] / (n r / J), which requires every other row of Ā_i to
equal A_i's: state feedback through the motor changes only the speed row.

The thesis's gains (Sec. 6.2) are given as closed-loop matrices ("Choose Ā_i as") in its
units (tension lbf, speed ft/s, time s); ``thesis_closed_loops`` turns them into SI matrices
of webline's section models (docs/decentralized.md, docs/errata.md E-6.7).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from webline.control.decentralized import SectionDesign, design_section
from webline.control.sections import SectionModel, section_models
from webline.control.select import with_controller
from webline.line import Line
from webline.model.operating_point import OperatingPoint, operating_point
from webline.spec.schema import AdaptiveSpec, MRACSpec, StateFeedbackSpec

LBF, FT = 4.4482216152605, 0.3048  # [N], [m]
#: (ft/s²)/lbf -> (m/s²)/N: the unit of the tension entries C_i1 of the thesis's Ā_i
ACCEL_PER_TENSION = FT / LBF


def gains_from_closed(models: Sequence[SectionModel],
                      closed: Sequence[np.ndarray]) -> list[np.ndarray]:
    """K_i = (K_T, K_V) [N·m/N, N·m·s/m] with Ā_i = A_i - B_i K_iᵀ; ValueError if some Ā_i
    differs from A_i outside its speed row (not reachable through the motor torque)."""
    out = []
    for m, a_bar in zip(models, closed, strict=True):
        diff = m.a - np.asarray(a_bar, dtype=float)
        if not np.allclose(diff[:-1], 0.0, rtol=0.0, atol=1e-9 * np.abs(m.a).max()):
            raise ValueError(f"section {m.states}: Ā differs from A outside the speed row "
                             f"(by {diff[:-1].tolist()}); state feedback cannot change it")
        k = diff[-1] / m.b[-1, 0]
        out.append(np.r_[0.0, k] if len(k) == 1 else k)
    return out


def closed_from_gains(models: Sequence[SectionModel],
                      gains: Sequence[np.ndarray]) -> list[np.ndarray]:
    """Ā_i = A_i - B_i K_iᵀ [SI] for gains K_i = (K_T, K_V) (K_T ignored for the master)."""
    out = []
    for m, k in zip(models, gains, strict=True):
        k = np.asarray(k, dtype=float)[-m.a.shape[0]:]
        out.append(m.a - m.b @ k[None, :])
    return out


def fixed_gains(gains: Sequence[np.ndarray]) -> Callable[[list[SectionModel]], list[np.ndarray]]:
    """Closed loops for fixed gains K_i, for any section models (e.g. at other speeds)."""
    return lambda models: closed_from_gains(models, gains)


def with_gains(line: Line, gains: Sequence[np.ndarray], family: str = "state_feedback",
               **options: object) -> Line:
    """``line`` with every drive running ``family`` ("state_feedback", "adaptive", "mrac") with the
    gains K_i (section order = ``line.drives``) written into its line-file tables."""
    overrides = {line.node_name(i): {"tension_gain": float(k[0]), "speed_gain": float(k[1])}
                 for i, k in zip(line.drives, gains, strict=True)}
    return with_controller(line, family, overrides=overrides, **options)  # type: ignore[arg-type]


def section_designs(line: Line, op: OperatingPoint | None = None, *,
                    tension_weight: float | Sequence[float] = 1.0,
                    bandwidth_fraction: float = 1.0) -> list[SectionDesign]:
    """webline's LQ design of every section at ``op`` (default: the line's operating point), as
    the simulator makes it (``webline.sim.core.drive_table``): scales from the drive's controller
    table or the defaults (1 % of the tension reference, 1 % of the line speed, 10 % of the
    torque limit), fastest pole capped at min(0.2 / torque lag, 2π f_s / 20) [rad/s] times
    ``bandwidth_fraction``; gains given in the table replace the LQ ones. ``tension_weight``
    (per section or one for all) divides the tension scale, i.e. weights tension errors more.
    """
    op = op if op is not None else operating_point(line)
    models = section_models(line, op)
    weights = np.broadcast_to(np.asarray(tension_weight, dtype=float), len(models))
    out = []
    for d, (i, model) in enumerate(zip(line.drives, models, strict=True)):
        roller = line.spec.rollers[i]
        drive = roller.drive  # type: ignore[union-attr]
        c = getattr(roller, "controller", None)
        table = c if isinstance(c, StateFeedbackSpec | AdaptiveSpec | MRACSpec) else None
        z = line.controlled_zone(i)
        t_scale = (table and table.tension_scale) or (
            0.01 * op.tension[line.zones[z].loadcell] if z is not None else 1.0)
        v_scale = (table and table.speed_scale) or max(0.01 * abs(op.line_speed), 0.01)
        u_scale = (table and table.torque_scale) or 0.1 * drive.torque_limit
        cap = min(0.2 / drive.torque_lag, 2 * np.pi * line.spec.control.sample_rate / 20)
        design = design_section(model, t_scale / weights[d], v_scale, u_scale,
                                cap * bandwidth_fraction)
        if table is not None and (table.tension_gain is not None or table.speed_gain is not None):
            gain = design.gain.copy()
            gain[0] = gain[0] if table.tension_gain is None else table.tension_gain
            gain[1] = gain[1] if table.speed_gain is None else table.speed_gain
            design = dataclasses.replace(design, gain=gain,
                                         closed=closed_from_gains([model], [gain])[0])
        out.append(design)
    return out


@dataclass(frozen=True)
class ThesisGains:
    """The closed-loop constants of thesis Sec. 6.2 (after "Choose Ā_i as"), in its units:
    C_i1 [(ft/s²)/lbf], C_i2 and C11 [1/s]; ε_i [1/s² in lbf, ft/s coordinates]."""

    c01: float = 120.0
    c02: float = 200.0
    c11: float = 4000.0
    c21: float = 1500.0
    c22: float = 400.0
    c31: float = 15.0
    c32: float = 15.0
    epsilon: float = 10.0

    def closed_loops(self, models: Sequence[SectionModel]) -> list[np.ndarray]:
        """Ā_i [SI] of a 4-section line (unwind, master, process, rewind): the speed row of
        each A_i replaced by the thesis's (C_i1 [→ SI] , -C_i2); the first rows stay A_i's
        (the printed -v_r0/L1 of Ā_0 is -v_r1/L1, E-6.10). The unwind's tension entry is
        +C01 (tension accelerates the unwind), the others' -C_i1."""
        if len(models) != 4 or models[1].a.shape != (1, 1):
            raise ValueError("the thesis's gains are for unwind, master, process and rewind")
        rows = [(self.c01, -self.c02), (None, -self.c11), (-self.c21, -self.c22),
                (-self.c31, -self.c32)]
        out = []
        for m, (c1, c2) in zip(models, rows, strict=True):
            a = m.a.copy()
            if c1 is not None:
                a[1, 0] = c1 * ACCEL_PER_TENSION
            a[-1, -1] = c2
            out.append(a)
        return out


THESIS_GAINS = ThesisGains()
