"""Finite-difference helpers shared by the linearization tests (not a test module)."""

from __future__ import annotations

import numpy as np

import webline
from webline.sim.core import kernel
from webline.sim.core.plan import compile_plan


def plant_derivative(line: webline.Line, op: webline.OperatingPoint):
    """f(z, u) on the linear model's states z = (tensions, speeds, torques, transmissions,
    dancers), radii frozen."""
    plan = compile_plan(line)
    x_op, _ = plan.initial_state(op)
    off = plan.offsets
    n_s, n_n, n_d = line.n_spans, line.n_nodes, len(line.drives)
    n_c = sum(name.endswith(".twist") for name in plan.state_names)  # compliant drives
    n_dn = sum(name.endswith(".velocity") for name in plan.state_names)  # dancers follow
    index = np.r_[0:n_s, off[1]:off[1] + n_n, off[3]:off[3] + n_d,
                  off[8]:off[8] + 2 * n_c + 2 * n_dn]
    work = np.empty(3 * n_n)
    drag = np.zeros(3 * n_n)
    slipping = np.zeros(n_n, dtype=np.int64)

    def f(z: np.ndarray, u: np.ndarray) -> np.ndarray:
        x = x_op.copy()
        x[index] = z
        dx = np.empty_like(x)
        t0 = kernel.wound_in(op.time, plan.web, plan.wound_ripple)
        kernel.rhs(t0, x, u, drag, slipping, *plan.structure(), plan.nodes, plan.spans,
                   plan.drives, plan.web, dx, work)
        return dx[index]

    return f, x_op[index], plan


def jacobian(f, z0: np.ndarray, u0: np.ndarray, scale: np.ndarray) -> np.ndarray:
    """Central differences with steps relative to each state's scale."""
    cols = []
    for j in range(len(z0)):
        h = 1e-6 * scale[j]
        e = np.zeros_like(z0)
        e[j] = h
        cols.append((f(z0 + e, u0) - f(z0 - e, u0)) / (2 * h))
    return np.array(cols).T
