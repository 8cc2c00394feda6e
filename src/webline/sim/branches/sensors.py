"""Sensors on a branched line (``spec.sensors``; docs/branching.md, "Sensors"), as the chain's
``sim.elements.sensor_loop`` fills its drive table: the span table's loadcell gain and offset
columns the drives' tension loops read, each drive's encoder scale and the delays of its
zone's loadcells and of its encoder in whole controller samples; the delay buffers' start."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from webline.errors import LineFileError
from webline.model.web_graph import BranchedLine
from webline.sim.branches.loop import layout as B
from webline.sim.branches.loop.plant import rhs
from webline.sim.branches.loop.web_law import felt_view
from webline.sim.elements.sensor_loop import delay_samples, fill_buffers, late
from webline.spec.sensors import LoadcellSensor

if TYPE_CHECKING:
    from webline.sim.branches.plan import BranchPlan


def sensor_columns(line: BranchedLine, offsets: np.ndarray, sf: np.ndarray, di: np.ndarray,
                   df: np.ndarray, cells: list[tuple[int, int, int, int]], dt: float) -> None:
    """Each span's loadcell gain and offset (1, 0 where ideal) into ``sf``, each drive's
    encoder scale and the delays [controller periods ``dt`` s] of its loadcells and encoder
    into ``df``; ``O_SENSORS`` 1 where one is other than ideal. ``LineFileError`` where no
    tension loop reads the loadcell (a dancer's, an observer's or an open-loop winder's
    zone: its calibration would not act, and the operating point would hold the wrong
    tension), where one zone's loadcells have different delays (the loop delays their sum)
    and beyond ``MAX_DELAY`` samples."""
    sf[:, B.SF_TGAIN], sf[:, B.SF_TOFFSET] = 1.0, 0.0
    df[:, B.D_VSCALE], df[:, B.D_TDELAY], df[:, B.D_VDELAY] = 1.0, 0.0, 0.0
    spans = {span.name: span.index for span in line.spans}
    delayed_by: dict[int, str] = {}  # drive -> the sensor that set its loadcells' delay
    for s, sensor in enumerate(line.spec.sensors):
        samples = delay_samples(line.source, f"sensors[{s}].delay", sensor.delay, dt)
        if not isinstance(sensor, LoadcellSensor):
            d = line.drives.index(line.node_index[sensor.roller])
            df[d, B.D_VSCALE], df[d, B.D_VDELAY] = sensor.scale, samples
            continue
        k = spans[sensor.span]
        reader, d = _reader(line, k, di, cells)
        if reader:
            raise LineFileError(line.source, f"sensors[{s}].span",
                                f"{reader} controls span {sensor.span!r}, not its loadcell: "
                                "its calibration would not act")
        sf[k, B.SF_TGAIN], sf[k, B.SF_TOFFSET] = sensor.gain, sensor.offset
        if d in delayed_by and df[d, B.D_TDELAY] != samples:
            raise LineFileError(line.source, f"sensors[{s}].delay",
                                f"the zone of {line.spec.rollers[di[d, B.DI_NODE]].name!r} "
                                f"sums this loadcell with {delayed_by[d]!r}, whose delay "
                                "differs: give its loadcells one delay")
        delayed_by[d] = sensor.name
        df[d, B.D_TDELAY] = samples
    offsets[B.O_SENSORS] = int(np.any(sf[:, B.SF_TGAIN] != 1.0)
                               or np.any(sf[:, B.SF_TOFFSET] != 0.0)
                               or np.any(df[:, B.D_VSCALE] != 1.0)
                               or np.any(df[:, B.D_TDELAY:B.D_VDELAY + 1] != 0.0))


def _reader(line: BranchedLine, k: int, di: np.ndarray,
            cells: list[tuple[int, int, int, int]]) -> tuple[str, int]:
    """('', drive) where a drive's tension loop reads span ``k``'s loadcell, else (what holds
    it, -1)."""
    for d in range(di.shape[0]):
        first, count = di[d, B.DI_CELLS], di[d, B.DI_NCELLS]
        if not any(cell[0] == k for cell in cells[first:first + count]):
            continue
        name = repr(line.spec.rollers[di[d, B.DI_NODE]].name)
        if any(cell[2] >= 0 for cell in cells[first:first + count]):
            return f"the dancer of {name}", -1
        if getattr(getattr(line.spec.rollers[di[d, B.DI_NODE]], "controller", None),
                   "tension_feedback", "") == "observer":
            return f"the tension observer of {name}", -1
        if di[d, B.DI_WINDER] == B.WINDER_OPEN:
            return f"the open-loop winder {name}", -1
        return "", d
    return "no drive", -1


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
