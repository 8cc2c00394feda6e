"""Reference path: the same plant and sampled controllers, the plant integrated by scipy's
adaptive-step solvers between controller ticks. Slow (one solver restart per tick); it exists
to measure the accuracy of the compiled fixed-step path. A web break (docs/winder.md W5) is
applied at the tick the kernel applies it, and the break monitor runs in the same
controller tick."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from scipy.integrate import solve_ivp

from webline.line import Line, load_line
from webline.sim.core import kernel
from webline.sim.core.plan import compile_plan, equilibrium_plan_state
from webline.sim.drives.controllers import control_tick
from webline.sim.drives.dancer_taper import load_factor
from webline.sim.elements import layout as L
from webline.sim.elements.break_hold import brake_drag
from webline.sim.elements.signals import profile_at
from webline.sim.elements.splice import apply_splices
from webline.sim.results.result import Result
from webline.sim.simulate import _result


def simulate_reference(line: Line | str | Path, duration: float, *, scenario: str | None = None,
                       sample_rate: float | None = None, method: str = "DOP853",
                       rtol: float = 1e-10, atol: float = 1e-10) -> Result:
    """Simulate like ``webline.simulate`` but with ``scipy.integrate.solve_ivp`` (``method``,
    tolerances ``rtol``/``atol``) over each controller period [s]."""
    line = load_line(line)
    if scenario is not None:
        line = line.with_scenario(scenario)
    plan = compile_plan(line, sample_rate=sample_rate)
    nodes, spans, drives, web, wound, ripple, prof_t, prof_v, prof_off = plan.params()
    ns, ds, offsets = plan.structure()
    n_ticks = max(1, round(duration / plan.dt))
    x, istate = equilibrium_plan_state(plan)
    slipping = kernel.initial_slip(plan, x)
    n_d = drives.shape[0]
    out = np.zeros((4, n_d))
    cmd = out[0]
    refs = np.empty(len(prof_off) - 1)
    span_ref = np.empty(spans.shape[0])
    v_ref = np.empty(nodes.shape[0])
    a_ref = np.empty(nodes.shape[0])
    work = np.empty(3 * nodes.shape[0])
    drag = np.zeros(3 * nodes.shape[0])
    rows = []

    def derivative(t: float, y: np.ndarray) -> np.ndarray:
        dy = np.empty_like(y)
        kernel.rhs(kernel.wound_in(t, web, wound), y, cmd, drag, slipping, ns, ds, offsets,
                   nodes, spans, drives, web, dy, work)
        return dy

    n_s = spans.shape[0]
    saved = np.empty(n_s)
    for j in range(n_ticks + 1):
        t = j * plan.dt
        for k in range(n_s if offsets[L.O_BREAK] else 0):  # as the kernel: a broken span
            if t >= spans[k, L.S_BREAK] and drag[2 * nodes.shape[0] + k] == 0.0:
                drag[2 * nodes.shape[0] + k], x[k] = 1.0, 0.0  # no tension, web lost
        if offsets[L.O_SPLICE]:  # as the kernel: a new roll takes over the web
            apply_splices(j, plan.dt, x, istate, ns, offsets, nodes, spans, drives, web, prof_t,
                          prof_v, prof_off)
        if offsets[L.O_KV]:  # as the kernel: controllers measure the felt tension
            kernel.felt_tensions(kernel.wound_in(t, web, wound), x, cmd, drag, slipping, ns,
                                 ds, offsets, nodes, spans, drives, web, np.empty_like(x),
                                 work, saved)
        control_tick(j, plan.dt, x, istate, ns, ds, offsets, nodes, drives, web, prof_t,
                     prof_v, prof_off, ripple, out, refs, span_ref, v_ref, a_ref, None, None)
        if offsets[L.O_KV]:
            x[:n_s] = saved
        kernel.update_slip(x, slipping, ns, offsets, nodes, web)
        rows.append(np.concatenate(([t], x, out.ravel(), istate[:, L.I_FRICTION],
                                     istate[:, L.I_RADIUS], slipping,
                                     istate[:, [L.I_KT, L.I_KV, L.I_BIAS]].ravel())))
        if j == n_ticks:
            break
        for i in range(nodes.shape[0]):
            p = int(ns[i, L.NS_DRAG])
            drag[i] = profile_at(p, t, prof_t, prof_v, prof_off) if p >= 0 else 0.0
            if ns[i, L.NS_DANCER] >= 0:  # the dancer's load, held like the drag
                drag[nodes.shape[0] + i] = profile_at(int(nodes[i, L.N_DLOAD]), t, prof_t,
                                                      prof_v, prof_off) * load_factor(
                    i, istate, ds, drives, prof_t, prof_v, prof_off)  # a taper through it
            if offsets[L.O_BREAK] and ns[i, L.NS_DRIVE] >= 0:  # as the kernel: a set brake
                drag[nodes.shape[0] + i] = brake_drag(i, t, istate, ns, drives, web)
        sol = solve_ivp(derivative, (t, t + plan.dt), x, method=method, rtol=rtol, atol=atol)
        x = sol.y[:, -1].copy()
    return _result(plan, np.array(rows), None,
                   {"duration": duration, "dt": plan.dt, "substeps": 0, "record_every": 1},
                   (float(istate[0, L.I_DETECT]), int(istate[0, L.I_METHOD])))
