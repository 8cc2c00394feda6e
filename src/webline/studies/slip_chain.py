"""A standalone reference model of web spans and rollers with slip (thesis 5.33, 5.44-5.47).

A *chain* is rollers 0..n joined by spans 1..n, fed with a prescribed tension upstream of
roller 0 and, if the last roller has a contact model, a prescribed tension after it. Each
roller has a prescribed surface speed (a stiff speed loop, as in Sec. 5.8) or is idle
(J dω/dt = R (t_out - t_in) - b_f ω - drag). A roller with a ``Contact`` lets the web slip
(``webline.physics.slip``); the web speed over roller r is v_r - s_r, and it is the exit speed
of the span before the roller and the entry speed of the span after it (5.33), so web is
conserved across a slipping roller.

Two integrators, built on the same right-hand side:

- ``simulate_fixed``: fixed-step RK4 at ``dt`` with the stick/slip state updated once per step
  by ``slip_state`` and held through the stages — the scheme the compiled kernel uses;
- ``slip_events.simulate_events``: scipy ``solve_ivp`` that locates every stick/slip switch as
  an event and restarts there — the reference that measures the fixed-step path's error.

Both also integrate the unstrained web that entered at roller 0 and left at roller n, the
slip power and the length slid at each roller, for the conservation and second-law checks.
Everything is SI.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from typing import Literal

import numpy as np
from scipy.optimize import fsolve

from webline.physics import slip as sl
from webline.physics import span as sp

Signal = Callable[[float], float]


def constant(value: float) -> Signal:
    """A signal that is ``value`` at all times."""
    return lambda t: value


@dataclass(frozen=True)
class Contact:
    """Web-roller contact: ``wrap`` α [rad], static ``mu`` μ0 [-], Coulomb ``mu_k`` μ' [-],
    ``viscous`` b [N·s/m], web ``mass_per_length`` ρA [kg/m] for the centrifugal term.
    ``law``: "webline" (``physics.slip``, general sign with stiction) or "printed" (thesis
    (5.47) as printed, always slipping, for comparison only)."""

    wrap: float
    mu: float
    mu_k: float
    viscous: float
    mass_per_length: float = 0.0
    law: Literal["webline", "printed"] = "webline"


@dataclass(frozen=True)
class Roller:
    """A roller: prescribed surface ``speed`` [m/s] signal, or idle (``speed`` None) with
    ``radius`` [m], ``inertia`` [kg·m²], bearing ``viscous`` [N·m·s] and extra ``drag`` [N·m]
    signal. ``contact`` None: the web never slips here."""

    speed: Signal | None = None
    radius: float = 0.1
    inertia: float = 0.0
    viscous: float = 0.0
    drag: Signal | None = None
    contact: Contact | None = None


@dataclass(frozen=True)
class Chain:
    """Rollers 0..n (web order) joined by spans of ``lengths`` [m]; web stiffness ``ea`` [N];
    ``tension_in`` [N] upstream of roller 0; ``tension_out`` [N] after roller n (needed only
    if roller n has a contact)."""

    ea: float
    lengths: tuple[float, ...]
    rollers: tuple[Roller, ...]
    tension_in: Signal
    tension_out: Signal | None = None

    def __post_init__(self) -> None:
        if len(self.rollers) != len(self.lengths) + 1:
            raise ValueError("a chain of n spans has n + 1 rollers")
        if self.rollers[-1].contact is not None and self.tension_out is None:
            raise ValueError("the last roller has a contact: give tension_out")

    @property
    def idle(self) -> tuple[int, ...]:
        return tuple(r for r, roller in enumerate(self.rollers) if roller.speed is None)

    @property
    def n_spans(self) -> int:
        return len(self.lengths)


def printed_slip_velocity(t_in: float, t_out: float, wrap: float, mu: float, mu_k: float,
                          viscous: float) -> float:
    """Thesis (5.47) as printed: s = (t_in/b)[1 - p(1 - e^{-μα}) - t_out/t_in], p = μ'/μ,
    applied whatever the sign (no stick test). For comparison only: it breaks the second law
    when 0 < t_in - t_out < p t_in (1 - e^{-μα}) (docs/errata.md, E-5.3)."""
    p = mu_k / mu
    return (t_in - t_out - p * t_in * (1.0 - math.exp(-mu * wrap))) / viscous


@dataclass
class _Layout:
    n: int  # spans
    idle: tuple[int, ...]
    n_rollers: int

    @property
    def q_in(self) -> int:
        return self.n + len(self.idle)

    @property
    def size(self) -> int:
        return self.q_in + 3 + self.n_rollers  # q_in, q_out, energy, slid per roller


@dataclass
class Point:
    """Everything the right-hand side computes at one instant."""

    tension: np.ndarray  # spans [N]
    t_up: np.ndarray  # per roller [N]
    t_down: np.ndarray  # per roller [N] (nan where none)
    surface: np.ndarray  # roller surface speed [m/s]
    slip: np.ndarray  # s = v_r - v [m/s]
    power: np.ndarray  # F s [W]


def evaluate(chain: Chain, t: float, y: np.ndarray, modes: np.ndarray,
             dy: np.ndarray | None = None) -> Point:
    """Right-hand side of the chain at time ``t`` [s], state ``y``, held stick/slip ``modes``;
    writes dy/dt into ``dy`` when given. State: span stretch forces [N], idle-roller speeds
    [rad/s], then unstrained web in and out [m], slip energy [J], length slid per roller [m]."""
    lay = chain_layout(chain)
    n, n_r = lay.n, lay.n_rollers
    tension = np.array([sp.tension(y[k]) for k in range(n)])
    t_up = np.empty(n_r)
    t_down = np.full(n_r, np.nan)
    surface = np.empty(n_r)
    slip = np.zeros(n_r)
    power = np.zeros(n_r)
    omega_index = {r: n + j for j, r in enumerate(lay.idle)}
    t_first = chain.tension_in(t)
    for r, roller in enumerate(chain.rollers):
        t_up[r] = t_first if r == 0 else tension[r - 1]
        if r < n:
            t_down[r] = tension[r]
        elif chain.tension_out is not None:
            t_down[r] = chain.tension_out(t)
        if roller.speed is not None:
            surface[r] = roller.speed(t)
        else:
            surface[r] = roller.radius * y[omega_index[r]]
        c = roller.contact
        if c is not None:
            if c.law == "printed":
                slip[r] = printed_slip_velocity(t_up[r], t_down[r], c.wrap, c.mu, c.mu_k,
                                                c.viscous)
            else:
                t_c = sl.centrifugal_tension(c.mass_per_length, surface[r])
                slip[r] = sl.slip_velocity(t_up[r], t_down[r], c.wrap, c.mu, c.mu_k,
                                           c.viscous, t_c, int(modes[r]))
            power[r] = sl.slip_power(t_up[r], t_down[r], slip[r])
    if dy is not None:
        web = surface - slip
        for k in range(n):
            dy[k] = sp.stretch_rate(chain.lengths[k], chain.ea, web[k], web[k + 1], t_up[k],
                                    tension[k])
        for r in lay.idle:
            roller = chain.rollers[r]
            torque = roller.radius * ((0.0 if math.isnan(t_down[r]) else t_down[r]) - t_up[r])
            torque -= roller.viscous * y[omega_index[r]]
            if roller.drag is not None:
                torque -= roller.drag(t)
            dy[omega_index[r]] = torque / roller.inertia
        q = lay.q_in
        dy[q] = web[0] * (1.0 - t_first / chain.ea)
        dy[q + 1] = web[-1] * (1.0 - tension[-1] / chain.ea)
        dy[q + 2] = power.sum()
        dy[q + 3:q + 3 + n_r] = slip
    return Point(tension, t_up, t_down, surface, slip, power)


def chain_layout(chain: Chain) -> _Layout:
    return _Layout(chain.n_spans, chain.idle, len(chain.rollers))


def next_modes(chain: Chain, point: Point, modes: np.ndarray) -> np.ndarray:
    """Stick/slip state of every roller for the next step (``physics.slip.slip_state``)."""
    new = modes.copy()
    for r, roller in enumerate(chain.rollers):
        c = roller.contact
        if c is None or c.law == "printed":
            continue
        t_c = sl.centrifugal_tension(c.mass_per_length, point.surface[r])
        new[r] = sl.slip_state(point.t_up[r], point.t_down[r], c.wrap, c.mu, c.mu_k, t_c,
                               int(modes[r]))
    return new


@dataclass
class Run:
    """A chain simulation: ``time`` [s] and, per sample, span ``tension`` [N], roller
    ``surface`` and web speed [m/s], ``slip`` velocity [m/s], ``state`` (0 stuck, 1 slipping),
    slip ``power`` [W]; ``balance`` [m] is unstrained web in - out - change stored (zero up to
    solver accuracy); ``switches`` the number of stick/slip switches per roller."""

    time: np.ndarray
    tension: np.ndarray
    surface: np.ndarray
    slip: np.ndarray
    state: np.ndarray
    power: np.ndarray
    balance: np.ndarray
    slid: np.ndarray
    energy: np.ndarray
    omega: np.ndarray
    switch_times: list[list[float]] = field(default_factory=list)

    @property
    def web_speed(self) -> np.ndarray:
        return self.surface - self.slip

    @property
    def switches(self) -> np.ndarray:
        return np.array([len(times) for times in self.switch_times])


def stored_web(chain: Chain, y: np.ndarray) -> float:
    """Unstrained web [m] in the spans (first order in strain, as 5.33 conserves it)."""
    return sum(sp.unstrained_length(chain.lengths[k], chain.ea, y[k]) for k in range(chain.n_spans))


def initial_state(chain: Chain, tensions: np.ndarray,
                  omegas: np.ndarray | None = None) -> np.ndarray:
    """State vector with span ``tensions`` [N], idle-roller ``omegas`` [rad/s], integrals 0."""
    lay = chain_layout(chain)
    y = np.zeros(lay.size)
    y[:lay.n] = tensions
    if omegas is not None:
        y[lay.n:lay.q_in] = omegas
    return y


def steady_state(chain: Chain, t: float, guess: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Span tensions and idle speeds with zero derivatives at time ``t`` [s] (inputs frozen
    there), and the consistent stick/slip state: all stuck if that equilibrium lies inside
    every stiction band, else the rollers outside it slipping (repeated until consistent).
    ``guess``: the state vector to start from. Returns (state vector, modes)."""
    lay = chain_layout(chain)
    modes = np.zeros(lay.n_rollers, dtype=int)
    y = guess.copy()
    for _ in range(len(chain.rollers) + 1):
        def residual(z: np.ndarray, modes: np.ndarray = modes) -> np.ndarray:
            full = y.copy()
            full[:lay.q_in] = z
            dy = np.zeros(lay.size)
            evaluate(chain, t, full, modes, dy)
            return dy[:lay.q_in]

        z = fsolve(residual, y[:lay.q_in], xtol=1e-13)
        y[:lay.q_in] = z
        point = evaluate(chain, t, y, modes)
        new = next_modes(chain, point, modes)
        new = np.maximum(new, modes)  # a stuck equilibrium outside its band is not one
        if np.array_equal(new, modes):
            return y, modes
        modes = new
    raise RuntimeError("no consistent stick/slip equilibrium found")


def _rk4_step(chain: Chain, t: float, y: np.ndarray, h: float, modes: np.ndarray) -> np.ndarray:
    k1 = np.empty_like(y)
    k2 = np.empty_like(y)
    k3 = np.empty_like(y)
    k4 = np.empty_like(y)
    evaluate(chain, t, y, modes, k1)
    evaluate(chain, t + 0.5 * h, y + 0.5 * h * k1, modes, k2)
    evaluate(chain, t + 0.5 * h, y + 0.5 * h * k2, modes, k3)
    evaluate(chain, t + h, y + h * k3, modes, k4)
    return y + h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4)


def record_run(chain: Chain, times: list[float], states: list[np.ndarray],
            modes: list[np.ndarray], y0: np.ndarray,
            switch_times: list[list[float]]) -> Run:
    lay = chain_layout(chain)
    pts = [evaluate(chain, t, y, m) for t, y, m in zip(times, states, modes, strict=True)]
    ys = np.array(states)
    stored0 = stored_web(chain, y0)
    stored = np.array([stored_web(chain, y) for y in states])
    q = lay.q_in
    balance = ys[:, q] - ys[:, q + 1] - (stored - stored0)
    return Run(
        time=np.array(times),
        tension=np.array([p.tension for p in pts]),
        surface=np.array([p.surface for p in pts]),
        slip=np.array([p.slip for p in pts]),
        state=np.array(modes),
        power=np.array([p.power for p in pts]),
        balance=balance,
        slid=ys[:, q + 3:q + 3 + lay.n_rollers],
        energy=ys[:, q + 2],
        omega=ys[:, lay.n:lay.q_in],
        switch_times=switch_times,
    )


def simulate_fixed(chain: Chain, y0: np.ndarray, modes0: np.ndarray, duration: float,
                   dt: float = 1e-3, t0: float = 0.0) -> Run:
    """Fixed-step RK4 at ``dt`` [s] for ``duration`` [s]: the stick/slip state is updated once
    per step from the state at its start (``slip_state``) and held through the four stages."""
    n_steps = round(duration / dt)
    y = y0.copy()
    modes = np.asarray(modes0, dtype=int).copy()
    times, states, mode_rec = [], [], []
    switch_times: list[list[float]] = [[] for _ in chain.rollers]
    for j in range(n_steps + 1):
        t = t0 + j * dt
        point = evaluate(chain, t, y, modes)
        new = next_modes(chain, point, modes)
        for r in np.nonzero(new != modes)[0]:
            switch_times[r].append(t)
        modes = new
        times.append(t)
        states.append(y.copy())
        mode_rec.append(modes.copy())
        if j == n_steps:
            break
        y = _rk4_step(chain, t, y, dt, modes)
    return record_run(chain, times, states, mode_rec, y0, switch_times)


def with_contact(chain: Chain, roller: int, contact: Contact | None) -> Chain:
    """The chain with roller ``roller``'s contact replaced."""
    rollers = list(chain.rollers)
    rollers[roller] = replace(rollers[roller], contact=contact)
    return replace(chain, rollers=tuple(rollers))
