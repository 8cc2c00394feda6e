"""Deviation models of the sections of a line (thesis 6.23-6.38, for any number of sections).

A *section* is one driven node with the tension zone its drive regulates (none for the master):
its state is x_i = (T_i - T_i^ref, V_i - V_i^ref) — the zone's loadcell tension and the node's web
speed — or x_i = (V_i - V_i^ref) for the master. As in the thesis (Ch. 4: "the length of web
between two driven rollers is considered a single span"), a zone is lumped into one span of
its total length: idle rollers are taken as massless and frictionless here (the full
``webline.linearize`` keeps them).

With v = r ω and the roll's velocity-squared term cancelled by the controller (the f_i of
6.39, 6.42), linearising the span equation in the thesis's first-order form (6.8; also on a
line in exact transport: a design model, docs/errata.md E-6.6) and the node's torque balance
at the operating point gives dx_i/dt = A_i x_i + B_i U_i + Σ_j A_ij x_j, with B_i = (0, n r/J)
(motor torque positive in the web direction, E-6.3).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from webline.line import Line
from webline.model.operating_point import OperatingPoint, operating_point
from webline.spec.nip import shaft_terms


@dataclass(frozen=True)
class SectionModel:
    """Linear deviation model of one section at an operating point (SI).

    ``a``: A_i; ``b``: B_i (column); ``coupling[j]``: A_ij for every other section j;
    ``node``: the driven node; ``zone``: the regulated zone or None (master); ``states``:
    names of the state components.
    """

    node: int
    zone: int | None
    a: np.ndarray
    b: np.ndarray
    coupling: dict[int, np.ndarray]
    states: tuple[str, ...]


def section_models(line: Line, op: OperatingPoint | None = None) -> list[SectionModel]:
    """Section deviation models of ``line`` at ``op`` (default: its operating point at t = 0),
    one per drive, in the order of ``line.drives``."""
    op = op if op is not None else operating_point(line)
    ea = line.ea
    sections = line.drives
    tension_of: dict[int, int] = {}  # zone -> section index holding its tension state
    zone_of: dict[int, int | None] = {}
    for s, i in enumerate(sections):
        zone_of[s] = line.controlled_zone(i)
        if zone_of[s] is not None:
            tension_of[zone_of[s]] = s  # type: ignore[index]
    section_of_node = {i: s for s, i in enumerate(sections)}

    def zone_tension(z: int) -> float:
        return float(op.tension[line.zones[z].loadcell])

    def upstream_tension(zone: int) -> tuple[float, int | None]:
        """Tension entering a zone (wound-in at the unwind) and the zone it belongs to."""
        first = line.zones[zone].first
        if first == 0:
            return line.unwind.wound_in_tension, None
        up = line.zone_of_span(first - 1)
        return zone_tension(up), up

    # Build the full lumped A (states: zone tensions, then driven-node speeds) and slice it.
    n_z, n_d = len(line.zones), len(sections)
    full = np.zeros((n_z + n_d, n_z + n_d))
    b_full = np.zeros(n_z + n_d)
    for z, zone in enumerate(line.zones):
        length = sum(line.spec.spans[k].length for k in zone.spans)
        t_in, up = upstream_tension(z)
        t = zone_tension(z)
        v_first, v_last = op.speed[zone.first], op.speed[zone.last]
        # L dT/dt = EA (v_last - v_first) + T_in v_first - T v_last
        full[z, z] = -v_last / length
        full[z, n_z + section_of_node[zone.last]] = (ea - t) / length
        full[z, n_z + section_of_node[zone.first]] = -(ea - t_in) / length
        if up is not None:
            full[z, up] = v_first / length
    for s, i in enumerate(sections):
        r, inertia = op.radius[i], op.inertia[i]
        roller = line.spec.rollers[i]
        row = n_z + s
        # (J/r) dV/dt = r (T_out - T_in) + n u - (b/r) V
        for z, zone in enumerate(line.zones):
            if zone.first == i:
                full[row, z] += r**2 / inertia
            if zone.last == i:
                full[row, z] -= r**2 / inertia
        full[row, row] = -shaft_terms(roller)[1] / inertia  # a nip's bearing included
        b_full[row] = roller.drive.ratio * r / inertia  # type: ignore[union-attr]

    index = [[z, n_z + s] if z is not None else [n_z + s] for s, z in zone_of.items()]
    models = []
    for s, i in enumerate(sections):
        rows = index[s]
        coupling = {j: full[np.ix_(rows, index[j])] for j in range(n_d) if j != s}
        names = (([f"{line.span_name(line.zones[zone_of[s]].loadcell)}_tension"]  # type: ignore[index]
                  if zone_of[s] is not None else []) + [f"{line.node_name(i)}_speed"])
        models.append(SectionModel(i, zone_of[s], full[np.ix_(rows, rows)],
                                   b_full[rows].reshape(-1, 1), coupling, tuple(names)))
    return models


def assemble(models: list[SectionModel]) -> tuple[np.ndarray, np.ndarray]:
    """The interconnected system (A, block-diagonal B) of all sections."""
    sizes = [m.a.shape[0] for m in models]
    starts = np.concatenate(([0], np.cumsum(sizes)))
    a = np.zeros((starts[-1], starts[-1]))
    b = np.zeros((starts[-1], len(models)))
    for s, m in enumerate(models):
        block = slice(starts[s], starts[s + 1])
        a[block, block] = m.a
        b[block, s] = m.b[:, 0]
        for j, coupling in m.coupling.items():
            a[block, starts[j]:starts[j + 1]] = coupling
    return a, b
