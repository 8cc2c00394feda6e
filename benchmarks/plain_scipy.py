"""The benchmark line written plainly: numpy right-hand side, continuous controllers, LSODA.

This is the "what an engineer would write without webline" baseline of the benchmark
(``bench_hswl.py``) and the independent check of its physics
(``tests/validation/test_benchmark_equations.py``). It deliberately does not import webline's
kernel or physics functions: the equations below are written out again from the model
description. Only *numbers* are taken from webline: parameters from the compiled plan's
arrays (``webline.sim.core.plan.compile_plan``), controller gains from ``plan.gains`` and the
initial
state from ``webline.operating_point``.

Model (SI). Nodes i = 0..N in web order (0 unwind roll, N rewind roll); span k joins node k to
node k + 1 and has length L_k.

* web speed            v_i = r_i w_i   (r_i the radius state of a roll, else the roller radius)
* span tension         L_k dT_k/dt = EA (v_{k+1} - v_k) + T_{k-1} v_k - T_k v_{k+1},
                       T_{-1} = wound-in tension t0 + sum A sin(2 pi f t + phase)
* node speed           J_i dw_i/dt = r_i (T_i - T_{i-1}) + n_i tau_i - b_i w_i
                       (no tension upstream of the unwind, none downstream of the rewind;
                       n_i tau_i only on driven nodes); a roll's J = J_const + (pi/2) w rho
                       (R^4 - Rcore^4)
* roll radii           dR_0/dt = -h v_0 / (2 pi R_0),   dR_N/dt = +h v_N / (2 pi R_N)
* motor torque         dtau/dt = (u - tau) / lag
* cascaded PI (continuous-time, no torque clipping), per drive d on node i:
    v_ff = v_line(t) (EA - T_ref,up(master)) / (EA - T_ref,up(i))
    tension drives: e_t = T_ref - T_loadcell, trim = sigma (kp_t e_t + I_t), dI_t/dt = ki_t e_t
    e_v = v_ff + trim - v_i,  u = g kp_s e_v + I_s,  dI_s/dt = g ki_s e_v
    g = (J_i / (n_i r_i)) / gain_norm for inertia-adaptive drives, else 1.

Tensions stay positive in the benchmark scenario, so spans are not allowed to go slack here.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np
from scipy.integrate import solve_ivp

import webline
from webline.sim.core.plan import compile_plan
from webline.sim.elements import layout as C  # column indices of the plan tables numbers only

#: Benchmark scenario of issue 2: 200 -> 1000 ft/min ramp from t = 1 s over 5 s, plus a 1 Hz,
#: 1 lbf wound-in tension ripple, on the built-in HSWL line (1 kHz control in webline).
SPEED_RAMP = {"type": "ramp", "initial": "200 ft/min", "final": "1000 ft/min",
              "start": 1.0, "duration": 5.0}
RIPPLE = [{"type": "wound_in_ripple", "amplitude": "1 lbf", "frequency": "1 Hz"}]


def benchmark_line() -> webline.Line:
    """The HSWL line with the benchmark's speed ramp and wound-in ripple."""
    return webline.load_line("hswl").replace(speed=SPEED_RAMP, disturbances=RIPPLE)


@dataclass(frozen=True)
class PlainModel:
    """Parameters of the plain model, as plain numpy arrays."""

    n_spans: int
    n_nodes: int
    ea: float
    thickness: float
    roll_k: float  #: (pi/2) width density [kg/m^3 * m]
    length: np.ndarray  #: per span [m]
    radius: np.ndarray  #: per node, roller radius (initial radius for rolls) [m]
    core: np.ndarray  #: per node, core radius of the rolls [m]
    j_const: np.ndarray  #: per node, inertia without web [kg m^2]
    viscous: np.ndarray  #: per node [N m s/rad]
    t0: float  #: nominal wound-in tension [N]
    ripple: np.ndarray  #: rows (amplitude [N], frequency [Hz], phase [rad])
    v_line_t: np.ndarray  #: line-speed reference breakpoints [s]
    v_line_v: np.ndarray  #: [m/s]
    # per drive
    node: np.ndarray  #: node index of each drive
    ratio: np.ndarray
    is_tension: np.ndarray  #: bool
    loadcell: np.ndarray  #: span index (0 for the master, unused there)
    t_ref: np.ndarray  #: tension reference of the regulated zone [N] (0 for the master)
    t_up_ref: np.ndarray  #: reference tension upstream of the node [N] (t0 for the unwind)
    t_master_up: float  #: reference tension upstream of the master [N]
    sigma: np.ndarray
    kp_s: np.ndarray
    ki_s: np.ndarray
    kp_t: np.ndarray
    ki_t: np.ndarray
    lag: np.ndarray
    adaptive: np.ndarray  #: bool
    gain_norm: np.ndarray
    y0: np.ndarray  #: initial state [T, w, R0, RN, tau, I_s, I_t]

    # slices of the state vector
    @property
    def s_t(self) -> slice:
        return slice(0, self.n_spans)

    @property
    def s_w(self) -> slice:
        return slice(self.n_spans, self.n_spans + self.n_nodes)

    @property
    def i_r0(self) -> int:
        return self.n_spans + self.n_nodes

    @property
    def s_tau(self) -> slice:
        a = self.n_spans + self.n_nodes + 2
        return slice(a, a + len(self.node))

    @property
    def s_is(self) -> slice:
        a = self.s_tau.stop
        return slice(a, a + len(self.node))

    @property
    def s_it(self) -> slice:
        a = self.s_is.stop
        return slice(a, a + len(self.node))


def _constant_profile(plan, p: int) -> float:
    """Value of reference profile ``p`` of the plan, which must be constant."""
    a, b = plan.prof_off[p], plan.prof_off[p + 1]
    values = plan.prof_v[a:b]
    if not np.all(values == values[0]):
        raise NotImplementedError("the plain model supports constant tension references only")
    return float(values[0])


def build(line: webline.Line) -> PlainModel:
    """Read the numbers of ``line`` into a ``PlainModel`` (initial state at its equilibrium)."""
    plan = compile_plan(line)
    nodes, drives, web = plan.nodes, plan.drives, plan.web
    if np.any(nodes[:, C.N_COULOMB] != 0.0) or np.any(nodes[:, C.N_ECC] != 0.0):
        raise NotImplementedError("the plain model has no Coulomb friction or eccentricity")
    if plan.speed_ripple.shape[0]:
        raise NotImplementedError("the plain model has no speed ripple")
    n_spans, n_nodes = plan.spans.shape[0], nodes.shape[0]
    node = drives[:, C.D_NODE].astype(int)
    is_tension = drives[:, C.D_ROLE] == C.ROLE_TENSION
    t0 = float(web[C.W_T0])

    def ref_or(p: float, default: float) -> float:
        return default if p < 0 else _constant_profile(plan, int(p))

    t_ref = np.array([ref_or(p, 0.0) for p in drives[:, C.D_REF]])
    t_up_ref = np.array([ref_or(p, t0) for p in drives[:, C.D_UPREF]])
    t_master_up = _constant_profile(plan, int(plan.offsets[6]))
    a, b = plan.prof_off[0], plan.prof_off[1]
    v_line_t, v_line_v = plan.prof_t[a:b].copy(), plan.prof_v[a:b].copy()

    # initial state: the equilibrium at t = 0
    op = webline.operating_point(line)
    ea = float(web[C.W_EA])
    v_ff0 = float(np.interp(0.0, v_line_t, v_line_v)) * (ea - t_master_up) / (ea - t_up_ref)
    sigma = drives[:, C.D_SIGMA].copy()
    tau0 = np.asarray(op.torque, float)
    i_t0 = sigma * (op.speed[node] - v_ff0)  # trim = sigma^2 I_t = v_i - v_ff at e_t = 0
    y0 = np.concatenate([op.tension, op.omega, [op.radius[0], op.radius[-1]], tau0, tau0, i_t0])

    return PlainModel(
        n_spans=n_spans, n_nodes=n_nodes, ea=ea, thickness=float(web[C.W_THICK]),
        roll_k=0.5 * math.pi * float(web[C.W_WIDTH]) * float(web[C.W_DENSITY]),
        length=plan.spans[:, C.S_LENGTH].copy(), radius=nodes[:, C.N_RADIUS].copy(),
        core=nodes[:, C.N_CORE].copy(), j_const=nodes[:, C.N_JCONST].copy(),
        viscous=nodes[:, C.N_VISCOUS].copy(), t0=t0, ripple=plan.wound_ripple.copy(),
        v_line_t=v_line_t, v_line_v=v_line_v,
        node=node, ratio=nodes[node, C.N_RATIO].copy(), is_tension=is_tension,
        loadcell=np.where(is_tension, drives[:, C.D_LOADCELL], 0).astype(int),
        t_ref=t_ref, t_up_ref=t_up_ref, t_master_up=t_master_up, sigma=sigma,
        kp_s=np.array([g.speed_kp for g in plan.gains], float),
        ki_s=np.array([g.speed_ki for g in plan.gains], float),
        kp_t=np.array([g.tension_kp for g in plan.gains], float),
        ki_t=np.array([g.tension_ki for g in plan.gains], float),
        lag=drives[:, C.D_LAG].copy(), adaptive=drives[:, C.D_ADAPTIVE] > 0.0,
        gain_norm=drives[:, C.D_GAINNORM].copy(), y0=y0,
    )


def make_rhs(m: PlainModel):
    """dy/dt of the plain model as a function ``f(t, y)`` for ``solve_ivp``."""
    nn = m.n_nodes
    assert m.n_spans == nn - 1
    s_t, s_w, i_r0, s_tau, s_is, s_it = m.s_t, m.s_w, m.i_r0, m.s_tau, m.s_is, m.s_it
    roll = np.zeros(nn, bool)
    roll[[0, nn - 1]] = True
    draw = (m.ea - m.t_master_up) / (m.ea - m.t_up_ref)
    two_pi = 2.0 * math.pi

    def rhs(t: float, y: np.ndarray) -> np.ndarray:
        tension = y[s_t]
        omega = y[s_w]
        r_unwind, r_rewind = y[i_r0], y[i_r0 + 1]
        tau, i_s, i_t = y[s_tau], y[s_is], y[s_it]

        r = m.radius.copy()
        r[0], r[-1] = r_unwind, r_rewind
        v = r * omega
        inertia = m.j_const + np.where(roll, m.roll_k * (r**4 - m.core**4), 0.0)
        wound_in = m.t0 + np.sum(m.ripple[:, 0] * np.sin(two_pi * m.ripple[:, 1] * t
                                                         + m.ripple[:, 2]))

        # spans
        t_upstream = np.concatenate(([wound_in], tension[:-1]))
        d_tension = (m.ea * (v[1:] - v[:-1]) + t_upstream * v[:-1] - tension * v[1:]) / m.length

        # continuous cascaded PI
        v_ff = np.interp(t, m.v_line_t, m.v_line_v) * draw
        e_t = np.where(m.is_tension, m.t_ref - tension[m.loadcell], 0.0)
        trim = m.sigma * (m.kp_t * e_t + i_t)
        j_d, r_d = inertia[m.node], r[m.node]
        g = np.where(m.adaptive, j_d / (m.ratio * r_d) / m.gain_norm, 1.0)
        e_v = v_ff + trim - r_d * omega[m.node]
        u = g * m.kp_s * e_v + i_s

        # nodes
        t_out = np.concatenate((tension, [0.0]))
        t_in = np.concatenate(([0.0], tension))
        shaft = np.zeros(nn)
        shaft[m.node] = m.ratio * tau  # n_i tau_i on driven nodes
        d_omega = (r * (t_out - t_in) + shaft - m.viscous * omega) / inertia

        dy = np.empty_like(y)
        dy[s_t] = d_tension
        dy[s_w] = d_omega
        dy[i_r0] = -m.thickness * v[0] / (two_pi * r_unwind)
        dy[i_r0 + 1] = m.thickness * v[-1] / (two_pi * r_rewind)
        dy[s_tau] = (u - tau) / m.lag
        dy[s_is] = g * m.ki_s * e_v
        dy[s_it] = m.ki_t * e_t
        return dy

    return rhs


def simulate(m: PlainModel, duration: float, dt: float = 1e-3, rtol: float = 1e-6):
    """Integrate the plain model over ``duration`` [s] with LSODA (``rtol``, default atol),
    the solution reported on the grid of step ``dt`` [s]. Returns the ``OdeResult``."""
    n = round(duration / dt)
    t_eval = np.arange(n + 1) * dt
    sol = solve_ivp(make_rhs(m), (0.0, duration), m.y0, method="LSODA", rtol=rtol,
                    t_eval=t_eval, dense_output=False)
    if not sol.success:
        raise RuntimeError(f"LSODA failed: {sol.message}")
    return sol


def span_tensions(m: PlainModel, sol) -> np.ndarray:
    """Span tensions [N] of a solution, shape (time, span)."""
    return sol.y[m.s_t].T


if __name__ == "__main__":
    model = build(benchmark_line())
    t = time.perf_counter()
    solution = simulate(model, 60.0)
    print(f"plain scipy LSODA, 60 s: {time.perf_counter() - t:.3f} s, "
          f"{solution.nfev} rhs evaluations")
