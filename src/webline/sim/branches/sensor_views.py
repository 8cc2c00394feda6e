"""What a branched line's plan makes of its sensors (``sim.branches.sensors`` fills the
tables; docs/branching.md, "Sensors"): the master encoder's scale the operating point holds,
the controller memory a run starts with, and what the sensors show in a result."""

from __future__ import annotations

import numpy as np

from webline.sim.branches.loop import layout as B
from webline.sim.branches.loop.plant import rhs
from webline.sim.branches.loop.web_law import felt_view
from webline.sim.branches.plan import BranchPlan
from webline.sim.elements.sensor_loop import fill_buffers, late


def master_scale(plan: BranchPlan) -> float:
    """The master's encoder scale [-]: its speed loop holds scale x its surface speed on the
    line reference, so the line runs at the reference / scale (1 without an encoder)."""
    return float(plan.df[plan.line.drives.index(plan.line.master), B.D_VSCALE])


def start_sensors(plan: BranchPlan, torque: np.ndarray, x: np.ndarray,
                  istate: np.ndarray) -> None:
    """The sensors' part of the controller memory a run starts with at the steady state
    ``x`` (motor torques ``torque`` [N·m]), as the chain's ``Plan.initial_state``: each
    delay buffer (``I_TBUF``, ``I_VBUF``) full of the drive's readings there (the sum of
    its loadcells' gain T + offset of the tensions the rollers feel, its encoder's scale x
    its surface speed at the radius its controller uses), and a PI tension drive's
    integrator at the trim that holds its encoder's reading on its feedforward (scale x
    v - v_line x ratio, the ratio's master scale included; 0 with ideal encoders)."""
    if not plan.offsets[B.O_SENSORS]:
        return
    n_s, n_n = len(plan.line.spans), plan.nodes.shape[0]
    dx, work = np.zeros(plan.n_x), plan.scratch()
    rhs(x, torque.copy(), plan.held(0.0), *plan.tables(), dx, work)
    felt = felt_view(work, n_s, n_n, plan.lawi.shape[0] > 0, plan.kv.shape[0] > 0)
    off_w, off_r = plan.offsets[B.O_OMEGA], plan.offsets[B.O_RADIUS]
    tension, speed = np.zeros(plan.di.shape[0]), np.zeros(plan.di.shape[0])
    v_line = plan.profile(0, 0.0)
    for d in range(plan.di.shape[0]):
        first, count = plan.di[d, B.DI_CELLS], plan.di[d, B.DI_NCELLS]
        for k, _, dancer, *_ in plan.cells[first:first + count]:
            if dancer < 0:
                tension[d] += plan.sf[k, B.SF_TGAIN] * felt[k] + plan.sf[k, B.SF_TOFFSET]
        i, j = plan.di[d, B.DI_NODE], plan.di[d, B.DI_ROLL]
        arm = x[off_r + j] if j >= 0 else plan.nodes[i, B.N_RADIUS]
        used = plan.radius0[d] if plan.df[d, B.D_DCALC] != B.DCALC_NONE else arm
        speed[d] = used * x[off_w + i]
        if (plan.di[d, B.DI_FAMILY] == B.FAMILY_PI and plan.di[d, B.DI_WINDER] != B.WINDER_OPEN
                and plan.df[d, B.D_SIGMA] != 0.0):
            istate[d, B.I_TENSION] = plan.df[d, B.D_SIGMA] * (
                plan.df[d, B.D_VSCALE] * arm * x[off_w + i] - v_line * plan.df[d, B.D_FF])
    fill_buffers(istate, B.I_TBUF, B.I_VBUF, tension, plan.df[:, B.D_VSCALE] * speed)


def measured_signals(plan: BranchPlan, time: np.ndarray, tension: np.ndarray,
                     speed: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """What the sensors show over ``time`` [s] (records), without their noise, as the
    chain's ``sensor_loop.measured_tensions`` and ``measured_speeds``: span tensions [N]
    (records x spans), gain T + offset its drive's loadcell delay late on a loadcell span;
    surface speeds [m/s] (records x nodes), scale x speed its encoder's delay late on a
    driven node; the true values elsewhere."""
    shown_t = plan.sf[:, B.SF_TGAIN] * tension + plan.sf[:, B.SF_TOFFSET]
    shown_v = np.array(speed, dtype=float, copy=True)
    for d in range(plan.di.shape[0]):
        first, count = plan.di[d, B.DI_CELLS], plan.di[d, B.DI_NCELLS]
        for k, _, dancer, *_ in plan.cells[first:first + count]:
            if dancer < 0:
                shown_t[:, k] = late(time, shown_t[:, k], plan.df[d, B.D_TDELAY] * plan.dt)
        i = plan.di[d, B.DI_NODE]
        shown_v[:, i] = late(time, plan.df[d, B.D_VSCALE] * speed[:, i],
                             plan.df[d, B.D_VDELAY] * plan.dt)
    return shown_t, shown_v
