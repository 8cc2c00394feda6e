"""Traction rollers, nips and measured friction on a branched line (docs/branching.md, "Slip
and measured friction"): the node table's columns the compiled loop reads
(``loop.traction``) and the slip findings of a run's verdict."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from webline.physics.slip import slip_rate
from webline.sim.branches.loop import layout as B
from webline.spec.nip import shaft_terms
from webline.verdict import Finding

if TYPE_CHECKING:
    from webline.model.web_graph import BranchedLine


def traction_columns(line: BranchedLine, nodes: np.ndarray, si: np.ndarray, offsets: np.ndarray,
                     dt: float) -> None:
    """Fill the traction, nip and measured-friction columns of ``nodes`` (a nip's pressure
    roller reflected onto its roller's inertia and friction, ``spec.nip.shaft_terms``) and
    set ``offsets``' O_SLIP and O_FRICTION flags; control period ``dt`` [s]. A traction roller
    is on one web's path with one span in and one out (``spec.branched.traction``)."""
    nodes[:, B.N_SLIPFIRST] = math.nan
    nodes[:, B.N_STICKTAU] = dt
    for i, spec in enumerate(line.spec.rollers):
        nip = getattr(spec, "nip", None)
        if nip is not None:  # its pressure roller turns with it (own inertia, bearings)
            inertia, viscous, coulomb = shaft_terms(spec)
            nodes[i, B.N_JCONST] += inertia - spec.inertia  # type: ignore[operator]
            nodes[i, B.N_VISCOUS] += viscous - spec.friction
            nodes[i, B.N_COULOMB] += coulomb - spec.coulomb_friction
            nodes[i, B.N_INVJ] = 1.0 / nodes[i, B.N_JCONST]
        contact = getattr(spec, "contact", None)
        if contact is not None and contact.type == "traction":
            k_in = int(np.flatnonzero(si[:, B.S_B] == i)[0])
            k_out = int(np.flatnonzero(si[:, B.S_A] == i)[0])
            web = line.materials[int(si[k_out, B.S_WEB])]
            nodes[i, B.N_TRACTION] = 1.0
            nodes[i, B.N_WRAP] = spec.wrap  # type: ignore[union-attr]
            nodes[i, B.N_MU] = contact.friction
            nodes[i, B.N_MUK] = (contact.friction if contact.kinetic_friction is None
                                 else contact.kinetic_friction)
            nodes[i, B.N_SLIPB] = contact.viscous
            if nip is not None:
                nodes[i, B.N_NIPS], nodes[i, B.N_NIPK] = nip.capacity()
            nodes[i, B.N_RHOA] = web.density * web.thickness * web.width
            nodes[i, B.N_SPIN], nodes[i, B.N_SPOUT] = k_in, k_out
            offsets[B.O_SLIP] = 1
        if spec.friction_table is not None:
            speeds, torques = spec.friction_table.arrays()
            nodes[i, B.N_FRICN] = len(speeds)
            nodes[i, B.N_FRICW:B.N_FRICW + len(speeds)] = speeds
            nodes[i, B.N_FRICT:B.N_FRICT + len(speeds)] = torques
            offsets[B.O_FRICTION] = 1
        if spec.breakaway_torque > 0.0:
            nodes[i, B.N_BREAKAWAY] = spec.breakaway_torque
            offsets[B.O_FRICTION] = 1


def slip_rate_bound(line: BranchedLine, nodes: np.ndarray, sf: np.ndarray,
                    top_speed: float) -> float:
    """Fastest decay rate [1/s] the two spans round any slipping roller may have
    (``physics.slip.slip_rate`` at 1.1 x the ``top_speed`` [m/s], as the chain's
    ``sim.linear.fastest.slip_rates``): the stuck linear model does not see it, the RK4
    step must resolve it; 0 without a traction roller."""
    rate = 0.0
    for i in np.flatnonzero(nodes[:, B.N_TRACTION]):
        k_in, k_out = int(nodes[i, B.N_SPIN]), int(nodes[i, B.N_SPOUT])
        rate = max(rate, slip_rate(sf[k_in, B.SF_EA], nodes[i, B.N_SLIPB],
                                   sf[k_in, B.SF_LENGTH], sf[k_out, B.SF_LENGTH],
                                   nodes[i, B.N_MU], nodes[i, B.N_MUK], nodes[i, B.N_WRAP],
                                   1.1 * top_speed))
    return rate


def slip_findings(line: BranchedLine, nodes: np.ndarray, si: np.ndarray) -> list[Finding]:
    """One warning per traction roller the web slipped over in the run: the web or
    lane, the time it slipped, the break-aways, the first one's time and the largest slip
    speed at a tick (from a plan's node and span tables after its run, which
    ``loop.traction.update_slip`` filled)."""
    findings = []
    for i in np.flatnonzero(nodes[:, B.N_TRACTION]):
        if nodes[i, B.N_SLIPCOUNT] == 0.0:
            continue
        web = line.spec.webs[int(si[int(nodes[i, B.N_SPOUT]), B.S_WEB])].name
        roller = line.spec.rollers[i].name
        count = int(nodes[i, B.N_SLIPCOUNT])
        first, time, peak = (float(nodes[i, c]) for c in (B.N_SLIPFIRST, B.N_SLIPTIME,
                                                              B.N_SLIPPEAK))
        findings.append(Finding(
            "warning", "slip", web,
            f"{web} slips over {roller}: {time:.4g} s in {count} "
            f"break-away{'s' if count > 1 else ''}, the first at t = {first:.4g} s; slip "
            f"speed up to {peak:.3g} m/s", first,
            {"roller": roller, "slip_time": time, "breakaways": count, "peak_slip": peak}))
    return findings
