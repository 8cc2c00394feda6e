"""Gain and phase margins of each drive's loop, broken at its torque command, the other
loops closed (loop-at-a-time margins).

The closed loop of ``sim.linear.linearize`` is z' = A_cl z with z = (plant states, controller
integrators) and the first rows A_cl[:n] = [A + B Kx, B Ki]: so B K = A_cl[:n] - [A, 0]
gives every drive's feedback row K_d = (Kx_d, Ki_d) exactly (B has one independent column
per drive: each torque command enters its own lag). Cutting drive d's command leaves
A_cut = A_cl - b_d K_d, and the return ratio for negative feedback is
L_d(s) = -K_d (sI - A_cut)^-1 b_d. The controllers are sampled: the zero-order hold delays
the command by half a period on average, a phase lag ωT/2 added to L_d (the continuous
model leaves it out). Margins follow from L_d(jω) on a logarithmic grid up to the Nyquist
frequency: the gain margin 1/|L| where L crosses the negative real axis, the phase margin
180° - |∠L| where |L| crosses 1 (the smallest of each), and where L crosses the
negative real axis outside the unit circle (a conditionally stable loop, as a dancer's
position loop is) the factor the gain may fall by.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from webline.sim.core.plan import Plan
from webline.sim.linear.linearize import plan_linear_model

#: frequency points per decade of the margin grid
POINTS_PER_DECADE = 80
#: the grid starts here [rad/s]: below the slowest loop a line is tuned for
LOWEST = 0.01


@dataclass(frozen=True)
class LoopMargin:
    """Margins of one drive's loop: ``gain_margin`` [1], the factor the loop gain may grow by
    before L reaches -1 (inf: it never crosses the negative real axis inside the unit
    circle); ``reduction_margin`` [1], the factor it may shrink by (inf: no crossing outside
    the unit circle; finite in conditionally stable loops); ``phase_margin`` [deg] (inf:
    |L| never reaches 1); ``crossover`` [rad/s] of the smallest phase margin (NaN if none);
    ``open_unstable``: poles of the loop with this drive cut in the right half plane (the
    classic margins then do not judge stability)."""

    drive: str
    gain_margin: float
    reduction_margin: float
    phase_margin: float
    crossover: float
    open_unstable: int

    @property
    def gain_margin_db(self) -> float:
        return 20.0 * math.log10(self.gain_margin)

    @property
    def reduction_margin_db(self) -> float:
        return 20.0 * math.log10(self.reduction_margin)

    def as_dict(self) -> dict[str, object]:
        return {"drive": self.drive, "gain_margin_db": self.gain_margin_db,
                "reduction_margin_db": self.reduction_margin_db,
                "phase_margin_deg": self.phase_margin, "crossover_rad_s": self.crossover,
                "open_loop_unstable_poles": self.open_unstable}


def feedback_rows(plan: Plan) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(A_cl, the torque-command columns b of the plant padded to A_cl's size, K): the
    closed loop of ``plan`` at its operating point and each drive's feedback row."""
    open_ = plan_linear_model(plan, loop="open")
    closed = plan_linear_model(plan, loop="closed")
    n_d = len(plan.line.drives)
    a_cl = np.asarray(closed.a)
    b_full, k = split_feedback(np.asarray(open_.a), np.asarray(open_.b)[:, :n_d], a_cl)
    return a_cl, b_full, k


def loop_margins(plan: Plan) -> list[LoopMargin]:
    """``LoopMargin`` of every drive of ``plan`` (module docstring)."""
    a_cl, b_full, k = feedback_rows(plan)
    return margins_of(a_cl, b_full, k, float(plan.dt),
                      [plan.line.node_name(i) for i in plan.line.drives])


def split_feedback(a: np.ndarray, b: np.ndarray, a_cl: np.ndarray
                   ) -> tuple[np.ndarray, np.ndarray]:
    """(b padded to A_cl's size, K) from an open loop (``a``, ``b``: one torque-command
    column per drive) and its closed loop ``a_cl`` whose first rows are [A + B Kx, B Ki]
    (module docstring; any line's linear model of that form, a branched line's too)."""
    n, n_z, n_d = a.shape[0], a_cl.shape[0], b.shape[1]
    feedback = a_cl[:n].copy()
    feedback[:, :n] -= a
    k, *_ = np.linalg.lstsq(b, feedback, rcond=None)
    b_full = np.zeros((n_z, n_d))
    b_full[:n] = b
    return b_full, k


def margins_of(a_cl: np.ndarray, b_full: np.ndarray, k: np.ndarray, period: float,
               drives: list[str]) -> list[LoopMargin]:
    """``LoopMargin`` of each drive (names ``drives``, one column of ``b_full`` and row of
    ``k`` each) of the closed loop ``a_cl``, controllers sampled every ``period`` [s]."""
    nyquist = math.pi / period
    decades = math.log10(nyquist / LOWEST)
    omega = np.logspace(math.log10(LOWEST), math.log10(nyquist),
                        max(2, int(POINTS_PER_DECADE * decades)))
    # with R = (sI - A_cl)⁻¹ and g_d = K_d R b_d, Sherman-Morrison gives
    # K_d (sI - A_cut)⁻¹ b_d = g_d / (1 + g_d): one batched solve serves every drive
    eye = np.eye(a_cl.shape[0])
    resolvent = np.linalg.solve(1j * omega[:, None, None] * eye[None] - a_cl[None],
                                np.broadcast_to(b_full, (len(omega), *b_full.shape)))
    g = np.einsum("dn,wnd->wd", k, resolvent)
    delay = np.exp(-0.5j * omega * period)
    out = []
    for d, name in enumerate(drives):
        a_cut = a_cl - np.outer(b_full[:, d], k[d])
        unstable = int(np.sum(np.linalg.eigvals(a_cut).real > 1e-9))
        loop = -g[:, d] / (1.0 + g[:, d]) * delay
        gm, down, pm, wc = _margins(omega, loop)
        out.append(LoopMargin(name, gm, down, pm, wc, unstable))
    return out


def _margins(omega: np.ndarray, loop: np.ndarray) -> tuple[float, float, float, float]:
    """(gain margin, gain-reduction margin, phase margin [deg], its crossover [rad/s]) of
    the return ratio
    ``loop`` sampled at ``omega``, interpolating linearly between grid points."""
    gm, down = math.inf, math.inf
    im, re = loop.imag, loop.real
    for j in np.flatnonzero(np.sign(im[:-1]) * np.sign(im[1:]) < 0):
        w = im[j] / (im[j] - im[j + 1])
        x = -(re[j] + w * (re[j + 1] - re[j]))
        if 0.0 < x <= 1.0:  # raising the gain by 1/x reaches -1
            gm = min(gm, 1.0 / x)
        elif x > 1.0:  # lowering it by x does (a conditionally stable loop)
            down = min(down, x)
    pm, crossover = math.inf, math.nan
    mag = np.log(np.abs(loop))
    for j in np.flatnonzero(np.sign(mag[:-1]) * np.sign(mag[1:]) < 0):
        w = mag[j] / (mag[j] - mag[j + 1])
        value = loop[j] + w * (loop[j + 1] - loop[j])
        margin = 180.0 - abs(math.degrees(float(np.angle(value))))
        if margin < pm:
            pm, crossover = margin, float(omega[j] + w * (omega[j + 1] - omega[j]))
    return gm, down, pm, crossover
