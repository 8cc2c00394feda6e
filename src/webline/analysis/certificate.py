"""The decentralized stability certificate of thesis Theorem 6.2.1 for a line (6.43-6.54).

The sections of a line (``webline.control.sections``) under decentralized state feedback form
dx_i/dt = Ā_i x_i + Σ_{j≠i} A_ij x_j (6.43). With V = Σ x_iᵀ P_i x_i (6.45) and Young's
inequality applied to each of the terms of Σ_{j≠i} (6.46-6.47), V̇ < 0 if for every section

    Ā_i is Hurwitz   and   δs(Ā_i)² - N_i ξ_i² > 0                       (6.44, 6.54)

with ξ_i² = Σ_{j≠i} σ_max(A_ji)² (the couplings *from* section i) and N_i the number of terms
Young's inequality was applied to in row i: N = (number of sections) - 1 in the thesis (its
sections are numbered 0..N, so the sum over j ≠ i has N terms), or, sharper and equally valid,
the number of sections j with A_ij ≠ 0 (``n_rule="neighbours"``). Then P_i solves the ARE
(6.49) with q = ξ_i² + ε_i, ε_i = (δs² - N ξ²)/(2N) by default (γ = 1/2 of the thesis).

The condition depends on the coordinates (units) of the states; ``scaling`` chooses them:
"si", "thesis" (lbf and ft/s, the thesis's units) or "optimize" (``webline.analysis.scaling``).
For comparison the certificate also reports the largest real part of the eigenvalues of the
interconnected section model it is about, and of the full linearized plant (torque lag, idle
rollers) closed with the same gains — continuously and with the controllers sampled at the
line's rate (a section model knows neither the lag nor the sampling).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Literal

import numpy as np

from webline.analysis import scaling as sc
from webline.analysis.stability import instability_distance, solve_bounded_real_are
from webline.line import Line
from webline.model.operating_point import OperatingPoint, operating_point

if TYPE_CHECKING:
    from webline.control.sections import SectionModel

NRule = Literal["thesis", "neighbours"]
Scaling = Literal["si", "thesis", "optimize"] | np.ndarray
ClosedLoops = Callable[[list["SectionModel"]], Sequence[np.ndarray]]
LBF, FT_PER_S = 4.4482216152605, 0.3048  # the thesis's units of tension [N] and speed [m/s]


@dataclass(frozen=True)
class Interconnection:
    """Interconnection bounds: ``eta[j, i]`` = σ_max(A_ji) (section i's effect on section j),
    ``xi[i]`` = (Σ_{j≠i} eta[j, i]²)^½, and ``neighbours[i]`` = #{j ≠ i: A_ij ≠ 0}."""

    eta: np.ndarray
    xi: np.ndarray
    neighbours: np.ndarray


def interconnection_bounds(models: Sequence[SectionModel],
                           units: np.ndarray | None = None) -> Interconnection:
    """η, ξ (6.44) of section models [their SI units, or in the coordinates x̃ = x / units
    with ``units`` per state in section order]."""
    sizes = [m.a.shape[0] for m in models]
    starts = np.concatenate(([0], np.cumsum(sizes)))
    units = np.ones(starts[-1]) if units is None else np.asarray(units, dtype=float)
    n = len(models)
    eta = np.zeros((n, n))
    neighbours = np.zeros(n, dtype=int)
    for j, m in enumerate(models):
        uj = units[starts[j]:starts[j + 1]]
        for i, a_ji in m.coupling.items():
            ui = units[starts[i]:starts[i + 1]]
            eta[j, i] = np.linalg.norm(a_ji * (ui[None, :] / uj[:, None]), 2)
            neighbours[j] += bool(np.any(a_ji))
    return Interconnection(eta, np.sqrt((eta**2).sum(axis=0)), neighbours)


@dataclass(frozen=True)
class SectionCertificate:
    """Theorem 6.2.1 for one section, in the certificate's coordinates. ``closed`` Ā_i [SI];
    ``delta`` δs(Ā_i), ``xi`` ξ_i [1/s]; ``n`` N_i; ``margin`` δs² - N ξ² [1/s²];
    ``riccati`` P_i of (6.49) for ``epsilon`` ε_i [1/s²] (None if it does not exist) with
    its relative ``residual``."""

    name: str
    states: tuple[str, ...]
    closed: np.ndarray
    hurwitz: bool
    delta: float
    xi: float
    n: int
    margin: float
    epsilon: float
    riccati: np.ndarray | None
    residual: float | None

    @property
    def holds(self) -> bool:
        return self.hurwitz and self.margin > 0.0

    @property
    def ratio(self) -> float:
        """δs / (√N ξ): the certificate holds for this section iff > 1 (and Hurwitz)."""
        bound = np.sqrt(self.n) * self.xi
        return self.delta / bound if bound > 0 else np.inf


@dataclass(frozen=True)
class Certificate:
    """Theorem 6.2.1 for every section of a line at one operating point (see module doc).

    ``units``: SI value of one coordinate unit of each state (section order); ``max_real``:
    largest real part of the eigenvalues of the interconnected section model (6.43) [1/s];
    ``max_real_plant``: same for the full linearized plant (torque lag, idlers) closed with
    these gains; ``sampled_radius``: spectral radius of that loop with the controllers
    sampled (zero-order hold) at the line's rate, stable iff < 1 (both None when not
    computed)."""

    line_speed: float
    n_rule: str
    scaling: str
    units: np.ndarray
    sections: tuple[SectionCertificate, ...]
    max_real: float
    max_real_plant: float | None
    sampled_radius: float | None

    @property
    def holds(self) -> bool:
        return all(s.holds for s in self.sections)

    @property
    def worst_ratio(self) -> float:
        """min over sections of δs/(√N ξ) (holds iff > 1)."""
        return min(s.ratio if s.hurwitz else 0.0 for s in self.sections)

    def rows(self) -> list[dict[str, object]]:
        """One plain-data row per section (for tables and JSON)."""
        return [{"section": s.name, "speed_m_per_s": self.line_speed, "delta_s": s.delta,
                 "xi": s.xi, "N": s.n, "margin": s.margin, "ratio": s.ratio,
                 "holds": s.holds, "epsilon": s.epsilon,
                 "riccati_residual": s.residual} for s in self.sections]


def section_counts(models: Sequence[SectionModel], n_rule: NRule) -> np.ndarray:
    """N_i of every section (module docstring)."""
    if n_rule == "thesis":
        return np.full(len(models), len(models) - 1)
    if n_rule == "neighbours":
        return interconnection_bounds(models).neighbours
    raise ValueError(f"n_rule must be 'thesis' or 'neighbours', got {n_rule!r}")


def thesis_units(models: Sequence[SectionModel]) -> np.ndarray:
    """Units of the thesis: tensions in lbf, speeds in ft/s (SI per unit, section order)."""
    return np.array([LBF if name.endswith("_tension") else FT_PER_S
                     for m in models for name in m.states])


def certificate(line: Line, closed: Sequence[np.ndarray] | ClosedLoops | None = None, *,
                unwind_radius: float | None = None, rewind_radius: float | None = None,
                n_rule: NRule = "thesis", scaling: Scaling = "optimize",
                epsilon: float | Sequence[float] | None = None,
                plant: bool = True) -> Certificate:
    """Theorem 6.2.1 for ``line`` at its operating point (roll radii [m] as given).

    ``closed``: the closed-loop section matrices Ā_i [SI] (or a function of the section
    models giving them); default: webline's LQ design as the simulator makes it
    (``webline.control.gains.section_designs``).
    ``epsilon`` ε_i [1/s² in the certificate's coordinates]. ``plant``: also close the full
    linearized plant with the gains that give Ā_i (their first rows must equal the A_i's),
    continuously and sampled at the line's controller rate.
    """
    from webline.control.sections import section_models

    at = line_at_radii(line, unwind_radius, rewind_radius)
    op = operating_point(at)
    models = section_models(at, op)
    bars = _closed(at, op, models, closed)
    plant_real, sampled = _plant_check(at, models, bars) if plant else (None, None)
    return certificate_of(models, bars, [at.node_name(m.node) for m in models],
                          op.line_speed, n_rule=n_rule, scaling=scaling, epsilon=epsilon,
                          plant=(plant_real, sampled))


def certificate_of(models: Sequence[SectionModel], bars: Sequence[np.ndarray],
                   names: Sequence[str], line_speed: float, *, n_rule: NRule = "thesis",
                   scaling: Scaling = "optimize", epsilon: float | Sequence[float] | None = None,
                   plant: tuple[float | None, float | None] = (None, None)) -> Certificate:
    """Theorem 6.2.1 for section ``models`` (A_i, B_i and the couplings A_ij, SI) closed to
    ``bars`` (Ā_i), sections named ``names``, at ``line_speed`` [m/s]; ``plant``: the full
    plant's largest Re λ [1/s] and sampled spectral radius, where computed (``certificate``
    of a line; a branched line's: ``analysis.branch_certificate``)."""
    from webline.control.sections import assemble

    models, bars = list(models), list(bars)
    counts = section_counts(models, n_rule)
    units, label = _units(models, bars, counts, scaling)
    bounds = interconnection_bounds(models, units)
    sections = []
    for i, (m, a_bar) in enumerate(zip(models, bars, strict=True)):
        u = units[_block(models, i)]
        scaled = a_bar * (u[None, :] / u[:, None])
        hurwitz = bool(np.linalg.eigvals(a_bar).real.max() < 0.0)
        d = instability_distance(scaled).value
        x, n = float(bounds.xi[i]), int(counts[i])
        margin = d * d - n * x * x
        eps = (margin / (2 * max(n, 1)) if margin > 0 else 0.0) if epsilon is None else float(
            np.broadcast_to(epsilon, len(models))[i])
        sol = solve_bounded_real_are(scaled, n, x * x + eps) if hurwitz and eps > 0 else None
        sections.append(SectionCertificate(
            names[i], m.states, a_bar, hurwitz, d, x, n, margin, eps,
            None if sol is None else sol.p, None if sol is None else sol.residual))
    a, _ = assemble(models)
    full = a.copy()
    for i, a_bar in enumerate(bars):
        full[_block(models, i), _block(models, i)] = a_bar
    return Certificate(line_speed, n_rule, label, units, tuple(sections),
                       float(np.linalg.eigvals(full).real.max()), plant[0], plant[1])


@dataclass(frozen=True)
class SpeedRange:
    """Certificates over line speeds [m/s] and where they hold."""

    speeds: np.ndarray
    certificates: tuple[Certificate, ...]

    @property
    def holds(self) -> np.ndarray:
        return np.array([c.holds for c in self.certificates])

    def ranges(self) -> list[tuple[float, float]]:
        """Contiguous (first, last) speeds [m/s] of the grid where the certificate holds."""
        out, start = [], None
        for k, ok in enumerate(self.holds):
            if ok and start is None:
                start = k
            if start is not None and (not ok or k == len(self.speeds) - 1):
                last = k if ok else k - 1
                out.append((float(self.speeds[start]), float(self.speeds[last])))
                start = None
        return out


def certificate_speed_range(line: Line, speeds: Sequence[float],
                            closed: ClosedLoops | None = None, **options: object) -> SpeedRange:
    """``certificate`` at each line speed in ``speeds`` [m/s] with the same gains.

    ``closed`` gives Ā_i from the section models at each speed; default: the fixed gains of
    webline's LQ design at the line's own speed. ``options`` go to ``certificate``; with
    ``scaling="optimize"`` the coordinates found at one speed are tried first at the next.
    """
    if closed is None:
        from webline.control.gains import fixed_gains, section_designs

        closed = fixed_gains([d.gain for d in section_designs(line)])
    out: list[Certificate] = []
    for v in speeds:
        at = line.replace(speed=float(v))
        if options.get("scaling", "optimize") == "optimize" and out:
            # the previous speed's coordinates first: if they certify, that is a certificate
            reused = certificate(at, closed, **{**options, "scaling": out[-1].units})  # type: ignore[arg-type]
            if reused.holds:
                out.append(reused)
                continue
        out.append(certificate(at, closed, **options))  # type: ignore[arg-type]
    return SpeedRange(np.asarray(speeds, dtype=float), tuple(out))


def line_at_radii(line: Line, unwind_radius: float | None, rewind_radius: float | None) -> Line:
    """The line with its rolls starting at the given radii (so that drive gains normalised
    to the initial roll are the designed ones)."""
    if unwind_radius is None and rewind_radius is None:
        return line
    rollers = line.spec.model_dump(exclude_none=True)["rollers"]
    if unwind_radius is not None:
        rollers[0]["radius"] = unwind_radius
    if rewind_radius is not None:
        rollers[-1]["radius"] = rewind_radius
    return line.replace(rollers=rollers)


def _closed(line: Line, op: OperatingPoint, models: list[SectionModel],
            closed: Sequence[np.ndarray] | ClosedLoops | None) -> list[np.ndarray]:
    if closed is None:
        from webline.control.gains import section_designs

        return [d.closed for d in section_designs(line, op)]
    bars = closed(models) if callable(closed) else closed
    bars = [np.asarray(b, dtype=float) for b in bars]
    if [b.shape for b in bars] != [m.a.shape for m in models]:
        raise ValueError(f"closed-loop matrices of shapes {[b.shape for b in bars]} do not "
                         f"match the sections {[m.a.shape for m in models]}")
    return bars


def _block(models: Sequence[SectionModel], i: int) -> slice:
    start = sum(m.a.shape[0] for m in models[:i])
    return slice(start, start + models[i].a.shape[0])


def _units(models: list[SectionModel], bars: list[np.ndarray], counts: np.ndarray,
           scaling: Scaling) -> tuple[np.ndarray, str]:
    n_x = sum(m.a.shape[0] for m in models)
    if isinstance(scaling, np.ndarray):
        if scaling.shape != (n_x,) or np.any(scaling <= 0):
            raise ValueError(f"scaling must be {n_x} positive state units, got {scaling!r}")
        return scaling.astype(float), "given"
    if scaling == "si":
        return np.ones(n_x), "si"
    if scaling == "thesis":
        return thesis_units(models), "thesis"
    if scaling != "optimize":
        raise ValueError(f"scaling must be 'si', 'thesis', 'optimize' or units, got {scaling!r}")
    structure = structure_of(models, counts)
    full = structure.coupling.copy()
    for i, b in enumerate(bars):
        full[_block(models, i), _block(models, i)] = b
    starts = [np.ones(n_x), thesis_units(models), sc.balanced_units(full)]
    return sc.best_units(structure, [[b] for b in bars], starts), "optimize"


def structure_of(models: Sequence[SectionModel], counts: np.ndarray) -> sc.Structure:
    """Block structure and couplings of the section models, for the scaling search."""
    from webline.control.sections import assemble

    a, _ = assemble(list(models))
    starts = np.concatenate(([0], np.cumsum([m.a.shape[0] for m in models])))
    coupling = a.copy()
    for i in range(len(models)):
        coupling[starts[i]:starts[i + 1], starts[i]:starts[i + 1]] = 0.0
    return sc.Structure(starts, coupling, np.asarray(counts))


def _plant_check(line: Line, models: list[SectionModel],
                 bars: list[np.ndarray]) -> tuple[float | None, float | None]:
    """Largest real part of the linearized plant (torque lag, idlers) closed with the gains
    that give ``bars``, and the spectral radius of the same loop sampled with a zero-order hold
    at the line's controller rate; (None, None) if some Ā_i is not reachable by state
    feedback."""
    import scipy.linalg

    from webline.control.gains import gains_from_closed, with_gains
    from webline.sim.core.plan import compile_plan
    from webline.sim.linear.linear_plant import plant_matrices
    from webline.sim.linear.linearize import controller_matrices, linear_model

    try:
        gains = gains_from_closed(models, bars)
    except ValueError:
        return None, None
    closed_line = with_gains(line, gains)
    a_closed = linear_model(closed_line, loop="closed").a
    op = operating_point(closed_line)
    a, b, _, _ = plant_matrices(closed_line, op)
    kx = controller_matrices(compile_plan(closed_line), op)[0]
    n, m = b.shape
    dt = 1.0 / line.spec.control.sample_rate
    block = scipy.linalg.expm(np.block([[a, b], [np.zeros((m, n + m))]]) * dt)
    sampled = block[:n, :n] + block[:n, n:] @ kx
    return (float(np.linalg.eigvals(a_closed).real.max()),
            float(np.abs(np.linalg.eigvals(sampled)).max()))
