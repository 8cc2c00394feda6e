"""Solid-motion analysis of backlash (thesis 3.1-3.10, Figs 3.4-3.8) and a direct simulation with
plastic impacts to check it.

Two masses, no friction, plastic impacts, a force F cos ωt on the motor mass Mm (Fig. 3.4).
Summing (3.1)/(3.2) removes the contact force: the centre of mass y = (Mm xm + ML xL)/M,
M = Mm + ML, moves as a free solid (3.3)-(3.5), ÿ = F cos(ωt)/M. In the periodic state with
zero mean speed ẏ = V sin ωt, y = -Y cos ωt, V = F/(Mω), Y = V/ω. The deviations
zm = xm - y, zL = xL - y obey Mm zm + ML zL = 0 (3.7)-(3.8), so xm - xL = -(M/Mm) zL and the gap
2Δ in xm - xL is a gap br = 2Δ Mm/M in zL (3.10, the reduced gap).

Construction (Fig. 3.5): zL lives in [-br/2, br/2]. At zL = -br/2 (xm - xL = +Δ) the motor
pushes the load forward, possible while ÿ >= 0; at +br/2 it pushes it back, while ÿ <= 0. In
contact the load moves with the solid (vL = ẏ); the contact ends when ÿ changes sign (at a
peak or a trough of ẏ) and the load then coasts at constant speed until zL reaches the other
wall, where a plastic impact gives both masses the solid's speed ẏ (momentum is conserved and
the centre of mass moves with ẏ). The motor follows from (3.6)-(3.7):
vm = ẏ - (ML/Mm)(vL - ẏ).

The harmonic gain M = |vL,1|/V and phase φL = arg vL,1 - arg ẏ1 of the load speed's
fundamental (end of Sec. 3.2) depend only on ρ = br/Y = 2Δ Mm ω²/F; they are computed here by
exact integration over the segments.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from webline.analysis.drivetrain.params import load_parameter_set

_FWD, _BWD, _FREE = "forward contact", "backward contact", "free"


@dataclass(frozen=True)
class SolidMotionCase:
    """Fig. 3.4: masses m_motor, m_load [kg], half gap Δ [m] (clearance 2Δ), force amplitude
    [N] and angular frequency omega [rad/s] of F cos ωt on the motor."""

    m_motor: float
    m_load: float
    half_gap: float
    force: float
    omega: float

    @property
    def mass(self) -> float:
        return self.m_motor + self.m_load

    @property
    def speed_amplitude(self) -> float:
        """V = F/(M ω) [m/s] of the solid speed ẏ = V sin ωt."""
        return self.force / (self.mass * self.omega)

    @property
    def period(self) -> float:
        return 2.0 * math.pi / self.omega


def thesis_example() -> SolidMotionCase:
    """The example of Sec. 3.2 (data file solid_motion_sec3_2)."""
    c = load_parameter_set("solid_motion_sec3_2")["case"]
    return SolidMotionCase(c["motor_mass"], c["load_mass"], 0.5 * c["backlash_gap"],
                           c["force_amplitude"], 2.0 * math.pi * c["frequency"])


def reduced_gap(m_motor: float, m_load: float, half_gap: float) -> float:
    """br [m] of (3.10): 2Δ Mm/(Mm + ML) = 2Δ/(1 + ML/Mm)."""
    return 2.0 * half_gap * m_motor / (m_motor + m_load)


def gap_ratio(case: SolidMotionCase) -> float:
    """ρ = br/Y = 2Δ Mm ω²/F [-], the one parameter the gain and phase depend on."""
    return reduced_gap(case.m_motor, case.m_load, case.half_gap) * case.mass * case.omega**2 \
        / case.force


@dataclass(frozen=True)
class Segment:
    """[t0, t1] [s] in one contact state; ``z0`` [m] and ``v`` [m/s]: zL and vL at t0."""

    t0: float
    t1: float
    kind: str
    z0: float
    v: float


def _solid(case: SolidMotionCase, t: float | np.ndarray) -> tuple:
    w = case.omega
    vamp = case.speed_amplitude
    return -vamp / w * np.cos(w * t), vamp * np.sin(w * t)


def _next_zero(case: SolidMotionCase, t: float, phase: float) -> float:
    """First time > t with ωt = phase (mod 2π)."""
    w = case.omega
    k = math.floor((w * t - phase) / (2.0 * math.pi)) + 1
    return (phase + 2.0 * math.pi * k) / w


def _free_flight_end(case: SolidMotionCase, t0: float, z0: float, v: float,
                     t_end: float, half_br: float) -> tuple[float, float] | None:
    """(time, wall) at which the coasting load reaches a wall, or None before t_end."""
    y0 = float(_solid(case, t0)[0])

    def z(t: float) -> float:
        return z0 + v * (t - t0) - (float(_solid(case, t)[0]) - y0)

    h = case.period / 400.0
    a = t0
    while a < t_end:
        b = min(a + h, t_end)
        for wall in (-half_br, half_br):
            fa, fb = z(a) - wall, z(b) - wall  # leaving a wall gives fa = 0 exactly: no hit
            if fa * fb < 0.0:
                return brentq(lambda t, w=wall: z(t) - w, a, b, xtol=1e-15, rtol=1e-15), wall
        a = b
    return None


def construct(case: SolidMotionCase, periods: float = 6.0) -> list[Segment]:
    """Segments of the load's motion from forward contact at the trough of ẏ (ωt = -π/2),
    over ``periods`` periods, by the solid-motion construction (module docstring)."""
    half_br = 0.5 * reduced_gap(case.m_motor, case.m_load, case.half_gap)
    t = -0.25 * case.period
    t_end = t + periods * case.period
    kind, z0, v = _FWD, -half_br, float(_solid(case, t)[1])
    if half_br == 0.0:  # no gap: the masses move as one solid
        return [Segment(t, t_end, _FWD, 0.0, v)]
    out: list[Segment] = []
    while t < t_end:
        if kind in (_FWD, _BWD):
            t1 = min(_next_zero(case, t, 0.5 * math.pi if kind == _FWD else 1.5 * math.pi), t_end)
            out.append(Segment(t, t1, kind, z0, float(_solid(case, t)[1])))
            kind, v, t = _FREE, float(_solid(case, t1)[1]), t1
            continue
        hit = _free_flight_end(case, t, z0, v, t_end, half_br)
        t1 = t_end if hit is None else hit[0]
        out.append(Segment(t, t1, _FREE, z0, v))
        if hit is None:
            break
        t, z0 = t1, hit[1]
        v = float(_solid(case, t)[1])  # plastic impact: both take the solid's speed
        accel = math.cos(case.omega * t + 2e-9 * math.pi)  # just after the impact
        if z0 < 0.0 and accel > 0.0:
            kind = _FWD
        elif z0 > 0.0 and accel < 0.0:
            kind = _BWD
    return out


@dataclass(frozen=True)
class Motion:
    """Sampled motion [s, m, m/s]: solid (y, ẏ), load (xL, vL), motor (xm, vm), deviations."""

    t: np.ndarray
    y: np.ndarray
    solid_velocity: np.ndarray
    x_load: np.ndarray
    load_velocity: np.ndarray
    x_motor: np.ndarray
    motor_velocity: np.ndarray

    @property
    def load_deviation_velocity(self) -> np.ndarray:
        """żL = vL - ẏ (Fig. 3.6)."""
        return self.load_velocity - self.solid_velocity

    @property
    def motor_deviation_velocity(self) -> np.ndarray:
        """żm = vm - ẏ = -(ML/Mm) żL (3.7, Fig. 3.6)."""
        return self.motor_velocity - self.solid_velocity


def sample(case: SolidMotionCase, segments: list[Segment], t: np.ndarray) -> Motion:
    """Evaluate the constructed motion at times ``t`` [s] (Figs 3.5-3.8)."""
    y, ydot = _solid(case, t)
    z = np.zeros_like(t)
    v = np.array(ydot, copy=True)
    for s in segments:
        inside = (t >= s.t0) & (t <= s.t1)
        if s.kind == _FREE:
            y0 = float(_solid(case, s.t0)[0])
            z[inside] = s.z0 + s.v * (t[inside] - s.t0) - (y[inside] - y0)
            v[inside] = s.v
        else:
            z[inside] = s.z0
    ratio = case.m_load / case.m_motor
    return Motion(t, y, ydot, y + z, v, y - ratio * z, ydot - ratio * (v - ydot))


def harmonic_gain_phase(case: SolidMotionCase, periods: int = 8,
                        window: int = 1) -> tuple[float, float]:
    """(M [-], φL [rad]) of the load speed's fundamental relative to the solid speed V sin ωt,
    over the last ``window`` of ``periods`` constructed periods (exact segment integrals).

    For ρ < π (``gap_ratio``) the motion is T-periodic from the first cycle, one impact per
    half period, and this equals ``harmonic_gain_phase_closed_form``. For ρ >= π the load
    coasts for more than half a period, the motion is not T-periodic (subharmonic or
    irregular) and the result depends on the window.
    """
    segments = construct(case, periods)
    w = case.omega
    a_win = segments[-1].t1 - window * case.period
    coef = 0j
    for s in segments:
        a, b = max(s.t0, a_win), s.t1
        if b <= a:
            continue
        ea, eb = np.exp(-1j * w * a), np.exp(-1j * w * b)
        if s.kind == _FREE:
            coef += s.v * (eb - ea) / (-1j * w)
        else:  # vL = V sin ωt
            e2 = (np.exp(-2j * w * b) - np.exp(-2j * w * a)) / (-2j * w)
            coef += case.speed_amplitude * ((b - a) - e2) / 2j
    coef *= 2.0 / (window * case.period)
    solid = case.speed_amplitude / 1j
    return float(abs(coef) / case.speed_amplitude), float(np.angle(coef / solid))


def impact_angle(rho: float) -> float:
    """ωt [rad] of the impact after the separation at ωt = π/2, for 0 <= ρ < π: the coasting
    load gains Y[(θ - π/2) + cos θ] on the solid, which must equal br = ρ Y."""
    if not 0.0 <= rho < math.pi:
        raise ValueError(f"one impact per half period needs 0 <= rho < pi, got {rho}")
    if rho == 0.0:
        return 0.5 * math.pi
    return brentq(lambda th: th - 0.5 * math.pi + math.cos(th) - rho, 0.5 * math.pi,
                  1.5 * math.pi, xtol=1e-15)


def harmonic_gain_phase_closed_form(rho: float) -> tuple[float, float]:
    """(M, φL) for the T-periodic motion, 0 <= ρ < π, in closed form.

    Over the half period θ = ωt ∈ [π/2, 3π/2] the load coasts at V up to the impact angle θi
    and then moves with the solid, V sin θ; the other half is the mirror image. Hence
    c1 = (2V/π)[∫_{π/2}^{θi} e^{-iθ} dθ + ∫_{θi}^{3π/2} sin θ e^{-iθ} dθ] and M = |c1|/V,
    φL = arg(c1/(-iV)). Limits: M = 1, φL = 0 at ρ = 0; M → 4/π, φL → -π/2 as ρ → π.
    """
    th = impact_angle(rho)
    coast = (np.exp(-1j * th) - np.exp(-0.5j * math.pi)) / (-1j)
    tail = ((1.5 * math.pi - th) - (np.exp(-3j * math.pi) - np.exp(-2j * th)) / (-2j)) / 2j
    c1 = 2.0 / math.pi * (coast + tail)
    return float(abs(c1)), float(np.angle(c1 * 1j))


def _event(func: Callable[[float, np.ndarray], float], direction: float):
    """Mark ``func`` as a terminal solve_ivp event crossing in ``direction``."""
    setattr(func, "terminal", True)  # noqa: B010 (solve_ivp reads these attributes)
    setattr(func, "direction", direction)  # noqa: B010
    return func


def _contact_phase(case: SolidMotionCase, t: float, t_end: float, state: np.ndarray,
                   side: float, rtol: float) -> tuple[np.ndarray, np.ndarray]:
    """Masses moving together (xm - xL = side·Δ) until the contact force changes sign."""
    m, f, w = case.mass, case.force, case.omega
    release = _event(lambda t_, s: math.cos(w * t_), -side)
    sol = solve_ivp(lambda t_, s: [s[1], f * math.cos(w * t_) / m], (t, t_end),
                    [state[2], state[3]], events=release, rtol=rtol, atol=1e-14,
                    max_step=case.period / 50)
    xl, vl = sol.y
    return sol.t, np.vstack([xl + side * case.half_gap, vl, xl, vl])


def _free_phase(case: SolidMotionCase, t: float, t_end: float, state: np.ndarray,
                rtol: float) -> tuple[np.ndarray, np.ndarray, float]:
    """Masses apart until xm - xL reaches ±Δ; returns the wall hit (+1, -1) or 0 at t_end."""
    mm, delta, f, w = case.m_motor, case.half_gap, case.force, case.omega
    hit_fwd = _event(lambda t_, s: s[0] - s[2] - delta, 1.0)
    hit_bwd = _event(lambda t_, s: s[0] - s[2] + delta, -1.0)
    sol = solve_ivp(lambda t_, s: [s[1], f * math.cos(w * t_) / mm, s[3], 0.0], (t, t_end),
                    state, events=(hit_fwd, hit_bwd), rtol=rtol, atol=1e-14,
                    max_step=case.period / 50)
    if sol.status != 1:
        return sol.t, sol.y, 0.0
    return sol.t, sol.y, 1.0 if sol.t_events[0].size else -1.0


def simulate_plastic(case: SolidMotionCase, periods: float = 6.0,
                     rtol: float = 1e-11) -> list[tuple[np.ndarray, np.ndarray]]:
    """Direct simulation of (3.1)-(3.2) in xm, xL with plastic impacts (solve_ivp with events).

    Starts like ``construct`` (forward contact at ωt = -π/2, centre of mass at the origin).
    Returns pieces (t [s], [xm, vm, xL, vL] [m, m/s]) at the solver's steps.
    """
    mm, ml, delta = case.m_motor, case.m_load, case.half_gap
    t = -0.25 * case.period
    t_end = t + periods * case.period
    v0 = float(_solid(case, t)[1])
    state = np.array([ml / case.mass * delta, v0, -mm / case.mass * delta, v0])  # y = 0
    side = 1.0  # +1 forward contact (xm - xL = Δ), -1 backward, 0 apart
    pieces: list[tuple[np.ndarray, np.ndarray]] = []
    ahead = 1e-9 * case.period  # decide sticking just after the impact (cos ωt may be ~0 at it)
    for _ in range(int(100 * periods) + 10):
        if t >= t_end - 1e-12:
            return pieces
        if side != 0.0:
            times, states = _contact_phase(case, t, t_end, state, side, rtol)
            wall = side = 0.0
        else:
            times, states, wall = _free_phase(case, t, t_end, state, rtol)
        pieces.append((times, states))
        t, state = float(times[-1]), states[:, -1].copy()
        if wall != 0.0:  # plastic impact: both take the centre of mass's speed
            state[1] = state[3] = (mm * state[1] + ml * state[3]) / case.mass
            side = wall if wall * math.cos(case.omega * (t + ahead)) > 0.0 else 0.0
    raise RuntimeError("simulate_plastic: more than 100 contact changes per period")
