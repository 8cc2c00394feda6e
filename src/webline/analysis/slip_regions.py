"""Entry-slip, adhesion and exit-slip regions of the web on a roller (thesis 5.19-5.22, Fig.
5.9 and 5.15; the thesis leaves them as future work). docs/slip.md, E-5.6.

Model. The roller turns at constant surface speed v = R ω; the web on it is quasi-static and
massless in the tangential direction, its normal force per radian is T - t_c (5.10), and Coulomb
friction μ limits the tangential traction. In log-tension g = ln(T - t_c) the friction cone
is a Lipschitz bound, |∂g/∂θ| <= μ, and:

- where the web adheres, its material does not move relative to the roller, its strain (hence
  T) is frozen and is carried round at ω (5.20-5.21);
- where it slips, the bound is active: g = g_in ∓ μθ from the entry (5.19) or
  g = g_out ∓ μ(α - θ) from the exit (5.22).

Well-posed form: the set of admissible profiles with the boundary tensions T_in(t), T_out(t)
is C(t) = {g : |g'| <= μ, g(0) = g_in, g(α) = g_out}, non-empty iff |g_out - g_in| <= μα (the
capstan limit; beyond it the web slides over the whole wrap, ``physics.slip``). Every g in C
lies pointwise between L = max(g_in - μθ, g_out - μ(α - θ)) and U = min(g_in + μθ,
g_out + μ(α - θ)), so the projection of the carried-round profile onto C — in any pointwise
norm — is the clip between L and U. One step of the evolution (Moreau's catching-up scheme for
this sweeping process): carry the profile one cell round (h = Δθ/ω, exact transport), then
clip. Material the clip changes has slipped this step; the rest adhered. The result is unique,
stays μ-Lipschitz, and reproduces the exit slip arc (5.13) in steady state, and (5.45) as the
local condition for an entry slip region to open. Any number of slip and adhesion regions may
coexist (a tension that oscillates leaves a wavy frozen profile).

The web speed where it enters and leaves follows from conservation of the unstrained web
on the arc, with the flux through an adhered station equal to v / (1 + ε) there.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

Signal = Callable[[float], float]


@dataclass(frozen=True)
class Arc:
    """A web on a roller: ``wrap`` α [rad], ``radius`` R [m], surface ``speed`` v [m/s],
    friction ``mu`` [-], centrifugal tension ``t_c`` [N], web stiffness ``ea`` [N], grid of
    ``cells`` cells over the wrap."""

    wrap: float
    radius: float
    speed: float
    mu: float
    ea: float
    t_c: float = 0.0
    cells: int = 400

    @property
    def theta(self) -> np.ndarray:
        return np.linspace(0.0, self.wrap, self.cells + 1)

    @property
    def step(self) -> float:
        """Time step [s]: the time the roller takes to turn one cell."""
        return self.wrap / self.cells * self.radius / self.speed

    def envelopes(self, t_in: float, t_out: float) -> tuple[np.ndarray, np.ndarray]:
        """Lower and upper bounds L, U of admissible log-tension profiles (module doc)."""
        th = self.theta
        g0 = math.log(t_in - self.t_c)
        ga = math.log(t_out - self.t_c)
        lower = np.maximum(g0 - self.mu * th, ga - self.mu * (self.wrap - th))
        upper = np.minimum(g0 + self.mu * th, ga + self.mu * (self.wrap - th))
        return lower, upper

    def gross_slip(self, t_in: float, t_out: float) -> bool:
        """True where the capstan limit is exceeded (no admissible profile)."""
        return abs(math.log((t_out - self.t_c) / (t_in - self.t_c))) > self.mu * self.wrap

    def steady_profile(self, t_in: float, t_out: float) -> np.ndarray:
        """Tension profile [N] of steady operation: T_in, then the exit slip arc (5.12)."""
        lower, upper = self.envelopes(t_in, t_out)
        g = np.clip(np.full(self.cells + 1, math.log(t_in - self.t_c)), lower, upper)
        return np.exp(g) + self.t_c


@dataclass(frozen=True)
class Regions:
    """Slip/adhesion layout of one profile: ``entry`` γ [rad] (end of the entry slip region,
    0 if none), ``exit`` β [rad] (start of the exit slip region), ``inner`` number of slip
    regions between them, ``adhered`` whether a region of adhesion exists (if not, the entry
    and exit slip regions meet at γ = β), ``gross`` capstan exceeded."""

    entry: float
    exit: float
    inner: int
    adhered: bool
    gross: bool


def classify(arc: Arc, carried: np.ndarray, new: np.ndarray, tol: float = 1e-13,
             gross: bool = False) -> tuple[Regions, int]:
    """Regions from the carried-round and the clipped log-tension profiles (node 0, the entry
    point, is ignored): a node the clip moved by more than ``tol`` slipped. Also returns the
    anchor node that moved with the roller: the first adhered node or, where none adheres,
    the extremum where the entry and exit slip regions meet (friction, hence the sliding
    direction, reverses there: web slides backwards where tension falls along the wrap)."""
    th = arc.theta
    n = arc.cells
    if gross:
        return Regions(arc.wrap, 0.0, 0, False, True), -1
    slipped = np.abs(new - carried) > tol
    inside = slipped[1:n]
    if inside.all():
        pick = np.argmax if new[1] < carried[1] else np.argmin
        k = int(pick(new[1:n])) + 1
        return Regions(float(th[k]), float(th[k]), 0, False, False), k
    adhered = np.nonzero(~inside)[0] + 1
    first, last = int(adhered[0]), int(adhered[-1])
    entry = float(th[first - 1]) if first > 1 else 0.0
    exit_ = float(th[last + 1]) if last < n - 1 else arc.wrap
    middle = slipped[first:last + 1].astype(int)
    inner = int(np.sum(np.diff(middle) == 1))
    return Regions(entry, exit_, inner, True, False), first


@dataclass
class ArcRun:
    """Evolution of the contact: ``time`` [s]; per sample the ``entry`` γ and ``exit`` β
    [rad], number of ``inner`` slip regions, ``gross`` slip flag, web speed where the web
    enters (``v_in``) and leaves (``v_out``) [m/s], unstrained web on the arc ``stored`` [m];
    ``profile`` the last tension profile [N] on ``theta`` [rad]."""

    time: np.ndarray
    entry: np.ndarray
    exit: np.ndarray
    inner: np.ndarray
    gross: np.ndarray
    v_in: np.ndarray
    v_out: np.ndarray
    stored: np.ndarray
    theta: np.ndarray
    profile: np.ndarray


def _unstrained(arc: Arc, tension: np.ndarray) -> np.ndarray:
    """Unstrained web [m] on each cell (trapezoid), to first order as (5.33): R Δθ (1 - ε)."""
    w = arc.radius * arc.wrap / arc.cells * (1.0 - tension / arc.ea)
    return 0.5 * (w[:-1] + w[1:])


def simulate_arc(arc: Arc, t_in: Signal, t_out: Signal, duration: float, *,
                 t0: float = 0.0, initial: np.ndarray | None = None,
                 tol: float = 1e-13) -> ArcRun:
    """Carry-and-clip evolution of the tension on the arc for ``duration`` [s] with the
    boundary tensions ``t_in(t)``, ``t_out(t)`` [N]; starts from ``initial`` [N] (default: the
    steady profile at ``t0``). A node whose log-tension the clip moves by more than ``tol``
    slipped during the step. Under gross slip the profile is reset to the capstan from the
    entry (5.40) and the speeds are NaN (the lumped law of ``physics.slip`` applies there)."""
    h = arc.step
    n_steps = max(1, round(duration / h))
    tension = (arc.steady_profile(t_in(t0), t_out(t0)) if initial is None
               else np.asarray(initial, float).copy())
    g = np.log(tension - arc.t_c)
    th = arc.theta
    out = {k: np.empty(n_steps) for k in ("entry", "exit", "inner", "gross", "v_in", "v_out",
                                           "stored")}
    times = t0 + h * np.arange(1, n_steps + 1)
    a_prev, b_prev = t_in(t0), t_out(t0)
    for j, t in enumerate(times):
        a, b = t_in(t), t_out(t)
        old_cells = _unstrained(arc, np.exp(g) + arc.t_c)
        carried = np.empty_like(g)
        carried[1:] = g[:-1]
        carried[0] = math.log(a - arc.t_c)
        gross = arc.gross_slip(a, b)
        if gross:
            s = 1.0 if a > b else -1.0
            new = carried[0] - s * arc.mu * th
        else:
            lower, upper = arc.envelopes(a, b)
            new = np.clip(carried, lower, upper)
        reg, k = classify(arc, carried, new, tol, gross)
        new_tension = np.exp(new) + arc.t_c
        new_cells = _unstrained(arc, new_tension)
        if k > 0:
            # the anchor node k moved with the roller (exactly one cell), so the web that
            # crossed the fixed station theta_k during the step is what lay in cell (k-1, k)
            crossed = old_cells[k - 1]
            q_in = (new_cells[:k].sum() - old_cells[:k].sum() + crossed) / h
            q_out = (crossed - (new_cells[k:].sum() - old_cells[k:].sum())) / h
            # fluxes are step averages: divide by the strain at mid-step
            out["v_in"][j] = q_in / (1.0 - 0.5 * (a + a_prev) / arc.ea)
            out["v_out"][j] = q_out / (1.0 - 0.5 * (b + b_prev) / arc.ea)
        else:
            out["v_in"][j] = out["v_out"][j] = math.nan
        out["entry"][j], out["exit"][j] = reg.entry, reg.exit
        out["inner"][j], out["gross"][j] = reg.inner, reg.gross
        out["stored"][j] = new_cells.sum()
        g = new
        a_prev, b_prev = a, b
    return ArcRun(time=times, entry=out["entry"], exit=out["exit"], inner=out["inner"],
                  gross=out["gross"].astype(bool), v_in=out["v_in"], v_out=out["v_out"],
                  stored=out["stored"], theta=th, profile=np.exp(g) + arc.t_c)


def only_exit_arc(history: np.ndarray, dt: float, arc: Arc, t_out: float) -> bool:
    """Whether a steady web that saw entering tensions ``history`` [N] (oldest first, spaced
    ``dt`` [s], the last the present) has only an exit slip arc now: the frozen profile of the
    adhered part, T_in(t - θ/ω) for θ up to α - φ, must stay inside the friction cone of the
    present entry tension, |g_in(t) - g_in(t - τ)| <= μ ω τ for every τ of the window (5.45 is
    its limit τ -> 0, with φ the present exit slip arc of (5.13))."""
    g = np.log(np.asarray(history, float) - arc.t_c)
    phi = abs(math.log((t_out - arc.t_c) / (history[-1] - arc.t_c))) / arc.mu
    window = max(arc.wrap - phi, 0.0) * arc.radius / arc.speed
    n = min(len(g) - 1, int(window / dt))
    tau = dt * np.arange(1, n + 1)
    past = g[-2::-1][:n]
    return bool(np.all(np.abs(g[-1] - past) <= arc.mu * arc.speed / arc.radius * tau + 1e-12))
