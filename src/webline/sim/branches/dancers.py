"""Dancers of a branched line in its plan (docs/branching.md, "Dancers"; the chain's
``sim.core.dancer``): which spans each carriage joins, its columns, its load, the position
loop of its zone's drive and the carriage's place at the operating point.

A dancer roller on node i carries two states after every other block, its carriage position
y [m] and speed [m/s]; the span into it and the span out of it (on the one web that wraps
it) are L + g (y - y_set) long (D0). Its zone is the tension zone that holds those spans; by
its ``use`` the zone's drive trims its speed on y - y_set (``"position"``) or on the
reference less the tension the carriage's balance reads (``"tension"``) instead of its
loadcells' tension error; ``"none"``: the carriage moves passively, the loadcells measure.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np

from webline.control.zone_tuning import KP_SPANS, tension_gains
from webline.errors import LineFileError
from webline.model.web_graph import BranchedLine, Zone
from webline.profiles import breakpoints
from webline.sim.branches.loop import layout as B
from webline.spec.schema import CascadedPISpec, DancerSpec

#: damping ratio of an end stop while the carriage presses on it (the chain's
#: ``sim.core.dancer.STOP_DAMPING_RATIO``: a rubber buffer)
STOP_DAMPING_RATIO = 0.7


def dancer_nodes(line: BranchedLine) -> list[int]:
    """Nodes of the dancer rollers of ``line``, in file order (their states' order)."""
    return [i for i, r in enumerate(line.spec.rollers) if isinstance(r, DancerSpec)]


def dancer_spans(line: BranchedLine, i: int) -> tuple[int, int]:
    """(span into, span out of) the dancer on node ``i``."""
    into = next(s.index for s in line.spans if s.b == i)
    out = next(s.index for s in line.spans if s.a == i)
    return into, out


def dancer_zone(line: BranchedLine, i: int) -> Zone:
    """The tension zone holding the spans the dancer on node ``i`` joins; ``LineFileError``
    where none does (nothing would move the web through it)."""
    into, out = dancer_spans(line, i)
    for zone in line.zones.values():
        if into in zone.spans and out in zone.spans:
            return zone
    raise LineFileError(line.source, f"rollers[{i}].dancer", "the dancer's two spans lie in "
                        "no single drive's tension zone (a dancer must sit between a tension "
                        "drive and the master, or the next driven roller)")


def _carriage(line: BranchedLine, i: int) -> Any:
    roller = line.spec.rollers[i]
    assert isinstance(roller, DancerSpec)
    return roller.dancer


def dancer_columns(line: BranchedLine, offsets: np.ndarray, nodes: np.ndarray, si: np.ndarray,
                   sf: np.ndarray) -> None:
    """Fill the dancer columns of the node and span tables (``layout``: N_D*, S_DANCE*,
    SF_GAIN*); every other node's state column is -1. ``LineFileError`` where a span is too
    short for the carriage's set position."""
    nodes[:, B.N_DSTATE] = -1.0
    si[:, B.S_DANCEA] = si[:, B.S_DANCEB] = si[:, B.S_DOUT] = -1
    for n, i in enumerate(dancer_nodes(line)):
        c = _carriage(line, i)
        state = int(offsets[B.O_DANCER]) + 2 * n
        into, out = dancer_spans(line, i)
        g_in, g_out = c.gains
        for k, gain in ((into, g_in), (out, g_out)):
            if sf[k, B.SF_LENGTH] <= gain * c.position:
                span = line.spans[k]
                raise LineFileError(line.source, f"webs[{span.web}].spans[{span.k}].length",
                                    f"must exceed {gain * c.position:g} m, what the dancer "
                                    f"{line.spec.rollers[i].name!r} takes from it between "
                                    f"its set position and y = 0 (D0)")
        mass = c.moving_mass
        row = nodes[i]
        row[B.N_DSTATE], row[B.N_DINVM] = state, 1.0 / mass
        row[B.N_DK], row[B.N_DC] = c.stiffness, c.damping
        row[B.N_DSET], row[B.N_DTRAVEL] = c.position, c.travel
        row[B.N_DSTOP] = c.stop_stiffness
        row[B.N_DSTOPC] = 2.0 * STOP_DAMPING_RATIO * math.sqrt(c.stop_stiffness * mass)
        row[B.N_DGSUM] = g_in + g_out
        si[into, B.S_DANCEB], si[into, B.S_DOUT], sf[into, B.SF_GAINB] = state, out, g_in
        si[out, B.S_DANCEA], sf[out, B.SF_GAINA] = state, g_out


def zone_cells(line: BranchedLine, zone: Zone | None,
               ref_of: dict[int, int]) -> list[tuple[int, int, int, int]]:
    """The ``cells`` rows (span, reference profile, dancer node, 1 for a tension sensor) of
    the drive of ``zone``: its loadcells (dancer -1), or one row reading the zone's dancer in
    position control or as tension sensor (with the loadcell span whose reference sets the
    dancer's default load and, for a sensor, the loop's reference). A passive dancer (``use =
    "none"``) leaves the loadcells to the loop."""
    if zone is None:
        return []
    dancers = [i for i in dancer_nodes(line) if dancer_zone(line, i).node == zone.node
               and _carriage(line, i).use != "none"]
    if len(dancers) > 1:
        raise LineFileError(line.source, f"rollers[{dancers[1]}].dancer.use", "a second "
                            f"dancer read by the drive of {line.spec.rollers[zone.node].name!r}"
                            " (its loop reads one dancer; make the others use = 'none')")
    if dancers:
        i = dancers[0]
        use = _carriage(line, i).use
        drive = line.spec.rollers[zone.node]
        winder = getattr(drive, "winder", None)
        if not isinstance(getattr(drive, "controller", None), CascadedPISpec) or (
                winder is not None and winder.mode == "open_loop"):
            raise LineFileError(line.source, f"rollers[{i}].dancer.use", f"{use} control "
                                f"trims the speed of a cascaded PI; {drive.name!r} runs "
                                "another controller or open-loop tension")
        k = _zone_loadcell(line, zone, i)  # (its reference: the default load's, D2)
        return [(k, ref_of[k], i, int(use == "tension"))]
    return [(k, ref_of[k], -1, 0) for k in zone.loadcells]


def _zone_loadcell(line: BranchedLine, zone: Zone, i: int) -> int:
    """The loadcell span of ``zone`` whose reference sets the default load of the dancer on
    ``i``: the one on the dancer's web, else the first."""
    web = line.spans[dancer_spans(line, i)[0]].web
    return next((k for k in zone.loadcells if line.spans[k].web == web), zone.loadcells[0])


def load_rows(line: BranchedLine, first_slot: int, profiles: list[Any],
              ref_of: dict[int, int]) -> np.ndarray:
    """Disturbance-table rows (``DIST_DANCER_LOAD``) of each dancer's load [N]: held slot,
    profile, factor; the load as given (a new profile) or (g_in + g_out) x its zone's
    tension reference (the set position is then an equilibrium)."""
    rows = []
    for n, i in enumerate(dancer_nodes(line)):
        c = _carriage(line, i)
        if c.load is not None:
            rows.append((B.DIST_DANCER_LOAD, first_slot + n, len(profiles), 1.0, 0.0))
            profiles.append(breakpoints(c.load))
        else:
            zone = dancer_zone(line, i)
            rows.append((B.DIST_DANCER_LOAD, first_slot + n,
                         ref_of[_zone_loadcell(line, zone, i)], sum(c.gains), 0.0))
    return np.array(rows, dtype=float).reshape(-1, B.DS_COLS)


def zone_gains(line: BranchedLine, di: np.ndarray, df: np.ndarray, cells: np.ndarray,
               zone_compliance: Callable[[BranchedLine, int], float]) -> None:
    """The tension loops' PI gains in the drive table ``df`` of every zone with a dancer,
    for the stiffness the loop works against (the chain's Z1-Z4, ``control.zone_tuning``;
    C_s the zone's spans' L/EA [m/N], ``zone_compliance``; G = g_in + g_out):

    - position control: the zone's tension gains scaled by (1/C_s)/G_p, G_p = 1/(G + k C/G)
      the carriage travel per metre of web stored, C = C_s plus the passive dancers' G²/k
      (Z2), unless the file gives ``position_kp`` / ``position_ki``;
    - tension sensor (Z1): placed on K = 1/C, C = C_s + Σ G²/k over the zone's dancers;
    - a loadcell beside passive dancers (Z4): on K = 1/C and their dampers c_e = K² Σ G² c /
      k², kp within ``KP_SPANS`` x the spans' own design;

    the file's tension gains are kept where it gives them; a zone with an air-loaded passive
    dancer (k = 0: its load sets the tension) keeps the spans' design."""
    for d, i in enumerate(line.drives):
        if i not in line.zones or di[d, B.DI_NCELLS] == 0 or df[d, B.D_SIGMA] == 0.0:
            continue
        mine = [n for n in dancer_nodes(line) if dancer_zone(line, n).node == i]
        if not mine:
            continue
        first = int(di[d, B.DI_CELLS])
        reader = int(cells[first, B.CELL_DANCER])
        spans = zone_compliance(line, i)
        others = spans + sum(_stored_per_newton(line, n) for n in mine if n != reader)
        row = df[d]
        if reader >= 0 and not cells[first, B.CELL_SENSOR]:  # position control (Z2)
            c = _carriage(line, reader)
            g = sum(c.gains)
            scale = (g + c.stiffness * others / g) / spans
            if math.isfinite(scale):
                row[B.D_KPT] = scale * row[B.D_KPT] if c.position_kp is None else c.position_kp
                row[B.D_KIT] = scale * row[B.D_KIT] if c.position_ki is None else c.position_ki
            continue
        controller = line.spec.rollers[i].controller  # type: ignore[union-attr]
        if not isinstance(controller, CascadedPISpec):
            continue
        compliance = others + (_stored_per_newton(line, reader) if reader >= 0 else 0.0)
        if not math.isfinite(compliance):
            continue  # an air-loaded dancer sets the tension: the spans' design stays
        bandwidth, damping = controller.tension_bandwidth, controller.damping
        if reader >= 0:  # the sensor reads its spring's force only (Z1)
            kp, ki = tension_gains(1.0 / compliance, 0.0, bandwidth, damping)
        else:  # a loadcell feels the passive carriages' dampers too (Z4)
            damper = sum(sum(_carriage(line, n).gains) ** 2 * _carriage(line, n).damping
                         / _carriage(line, n).stiffness ** 2 for n in mine) / compliance**2
            kp, ki = tension_gains(1.0 / compliance, damper, bandwidth, damping,
                                   KP_SPANS * 2.0 * damping * bandwidth * spans)
        if controller.tension_kp is None:
            row[B.D_KPT] = kp
        if controller.tension_ki is None:
            row[B.D_KIT] = ki


def _stored_per_newton(line: BranchedLine, i: int) -> float:
    """G²/k [m/N] of the dancer on node ``i`` (Z1): the web its carriage stores per newton
    of tension lost, G = g_in + g_out; inf on an air-loaded one (k = 0)."""
    c = _carriage(line, i)
    return math.inf if c.stiffness == 0.0 else sum(c.gains) ** 2 / c.stiffness
