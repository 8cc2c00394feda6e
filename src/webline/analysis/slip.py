"""Slip analyses: how much wrap or friction a roller needs, the slip arc, and the
slowly-varying condition (thesis 5.12-5.13, 5.45; docs/slip.md).

A roller holds the web without gross slip while the tensions on its two sides satisfy the
capstan relation with the centrifugal term (5.12):

    (T_high - t_c) / (T_low - t_c) <= e^{μα},   t_c = ρA v²,

so the product μα it needs is ln((T_high - t_c)/(T_low - t_c)) — the slip-arc angle (5.13)
times μ. With that, the web adheres at entry and the whole tension change happens on an exit
slip arc φ <= α (Sec. 5.2-5.3). The arc stays at the exit only while the entering tension
varies slowly (5.45): |dT_in/dt| <= μ ω (T_in - t_c), ω = v/R; a faster change opens an
entry slip region too (``webline.analysis.slip_regions``).

Vectorised numpy versions of the scalar laws in ``webline.physics.slip`` plus line-level
tables built on ``operating_point`` and on simulation results.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from webline.line import Line
from webline.model.operating_point import OperatingPoint
from webline.sim.results.result import Result


def required_mu_wrap(t_in: ArrayLike, t_out: ArrayLike, t_c: ArrayLike = 0.0) -> np.ndarray:
    """Product μα [rad] needed to hold ``t_in`` and ``t_out`` [N] without gross slip (5.13 × μ):
    |ln((t_out - t_c)/(t_in - t_c))|; ``t_c`` [N] the centrifugal tension. Infinite if a side
    is at or below t_c (lift-off) while the tensions differ."""
    a = np.asarray(t_in, float) - t_c
    b = np.asarray(t_out, float) - t_c
    with np.errstate(divide="ignore", invalid="ignore"):
        out = np.abs(np.log(b / a))
    out = np.where((a <= 0) | (b <= 0), np.inf, out)
    return np.where(np.asarray(t_in) == np.asarray(t_out), 0.0, out)


def min_wrap(t_in: ArrayLike, t_out: ArrayLike, mu: float, t_c: ArrayLike = 0.0) -> np.ndarray:
    """Smallest wrap angle [rad] that holds the tensions [N] with friction ``mu`` [-]."""
    return required_mu_wrap(t_in, t_out, t_c) / mu


def min_friction(t_in: ArrayLike, t_out: ArrayLike, wrap: float,
                 t_c: ArrayLike = 0.0) -> np.ndarray:
    """Smallest friction coefficient [-] that holds the tensions [N] over ``wrap`` [rad]."""
    return required_mu_wrap(t_in, t_out, t_c) / wrap


def slip_arc(t_in: ArrayLike, t_out: ArrayLike, mu: float, t_c: ArrayLike = 0.0) -> np.ndarray:
    """Exit slip-arc angle φ [rad] (5.13) for either sign of t_out - t_in (``physics.slip``)."""
    return required_mu_wrap(t_in, t_out, t_c) / mu


def slowly_varying_ratio(rate: ArrayLike, t_in: ArrayLike, speed: ArrayLike, radius: float,
                         mu: float, t_c: ArrayLike = 0.0) -> np.ndarray:
    """|dT_in/dt| over its limit in (5.45): |rate| R / (μ v (T_in - t_c)).

    ``rate`` [N/s] of the entering tension ``t_in`` [N], roller surface ``speed`` [m/s],
    ``radius`` [m], ``mu`` [-], ``t_c`` [N]. Below 1 the tension frozen into the adhered web at
    the entry never exceeds the friction cone, so the only slip arc is at the exit (the
    condition is local; ``slip_regions`` checks the whole arc). The thesis's (5.45) has
    t_c = 0 and v = R ω.
    """
    limit = mu * np.asarray(speed, float) * (np.asarray(t_in, float) - t_c) / radius
    with np.errstate(divide="ignore"):
        return np.where(limit > 0, np.abs(np.asarray(rate, float)) / limit, np.inf)


@dataclass(frozen=True)
class RollerNeed:
    """What one roller needs to hold the web: tensions in/out [N], centrifugal t_c [N], the
    product μα [rad], and for the given wrap [rad] and friction [-] the smallest friction and
    wrap, the slip arc [rad] and the margin e^{μα}/ratio - 1 [-] (negative: it slips)."""

    roller: str
    t_in: float
    t_out: float
    t_c: float
    mu_wrap: float
    wrap: float
    mu: float
    min_mu: float
    min_wrap: float
    slip_arc: float
    margin: float

    def as_row(self) -> dict[str, object]:
        return {
            "roller": self.roller, "t_in_N": self.t_in, "t_out_N": self.t_out,
            "t_c_N": self.t_c, "mu_wrap_rad": self.mu_wrap,
            "min_mu_at_wrap": self.min_mu,
            "min_wrap_deg_at_mu": float(np.degrees(self.min_wrap)),
            "slip_arc_deg": float(np.degrees(self.slip_arc)), "margin": self.margin,
        }


def roller_need(name: str, t_in: float, t_out: float, speed: float, wrap: float, mu: float,
                mass_per_length: float) -> RollerNeed:
    """``RollerNeed`` of one roller at surface ``speed`` [m/s] for a web of
    ``mass_per_length`` [kg/m]."""
    t_c = mass_per_length * speed**2
    need = float(required_mu_wrap(t_in, t_out, t_c))
    margin = float(np.exp(mu * wrap - need) - 1.0) if np.isfinite(need) else -1.0
    return RollerNeed(name, t_in, t_out, t_c, need, wrap, mu, need / wrap, need / mu,
                      need / mu, margin)


def mass_per_length(line: Line) -> float:
    """ρA [kg/m] of the line's web."""
    web = line.spec.web
    return web.density * web.width * web.thickness


def operating_needs(line: Line, op: OperatingPoint, wraps: dict[str, float],
                    mu: dict[str, float] | float) -> list[RollerNeed]:
    """Needs of each roller (not the rolls) of ``line`` at operating point ``op``; ``wraps``
    [rad] and ``mu`` [-] by roller name (rollers without a wrap are skipped)."""
    rho_a = mass_per_length(line)
    out = []
    for i in range(1, line.n_nodes - 1):
        name = line.node_name(i)
        if name not in wraps:
            continue
        m = mu if isinstance(mu, float) else mu[name]
        out.append(roller_need(name, float(op.tension[i - 1]), float(op.tension[i]),
                               float(op.speed[i]), wraps[name], m, rho_a))
    return out


def needs_along(result: Result, wraps: dict[str, float]) -> dict[str, np.ndarray]:
    """μα [rad] each roller named in ``wraps`` needs at each sample of a (no-slip) run: the
    a-posteriori slip check of a simulation that assumed adhesion. Uses the recorded span
    tensions and the roller surface speeds (centrifugal term)."""
    line = result.line
    rho_a = mass_per_length(line)
    tension = result.tension
    speed = result.speed
    out = {}
    for i in range(1, line.n_nodes - 1):
        name = line.node_name(i)
        if name in wraps:
            out[name] = required_mu_wrap(tension[:, i - 1], tension[:, i],
                                         rho_a * speed[:, i] ** 2)
    return out


def slowly_varying_along(result: Result, mu: dict[str, float] | float) -> dict[str, np.ndarray]:
    """(5.45) ratio at each sample for every roller (entering tension rate by central
    differences of the recorded tension)."""
    line = result.line
    rho_a = mass_per_length(line)
    out = {}
    for i in range(1, line.n_nodes - 1):
        name = line.node_name(i)
        m = mu if isinstance(mu, float) else mu.get(name)
        if m is None:
            continue
        t_in = result.tension[:, i - 1]
        rate = np.gradient(t_in, result.time)
        speed = result.speed[:, i]
        out[name] = slowly_varying_ratio(rate, t_in, speed, line.spec.rollers[i].radius, m,
                                         rho_a * speed**2)
    return out
