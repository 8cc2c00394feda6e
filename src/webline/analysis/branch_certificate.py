"""Thesis Theorem 6.2.1 on a branched line (docs/branching.md, "The decentralized
certificate"): the chain's certificate (``analysis.certificate``) over the sections of a tree.

The theorem's assumptions are structural: the line splits into sections x_i with their own
inputs, dx_i/dt = A_i x_i + B_i u_i + Σ_{j≠i} A_ij x_j, closed by local state feedback
u_i = -K_i x_i. Its proof (V = Σ x_iᵀ P_i x_i, Young's inequality on each coupling term) uses
nothing of a chain's order: any graph of couplings will do, each A_ij counted once in ξ_i
and N_i. What a tree adds are the couplings themselves, derived here on the lumped model of
the chain's ``control.sections`` (each drive's zone lumped per loadcell web into one span of
its total length L_c; states S_i, the zone's loadcell tension or sum, and V_i, the drive's
measured surface speed), linearized from (B1)-(B4):

    L_c dT_c/dt = (EA_c - T_c) v_b - (EA_c - T_in,c) v_a - v_b T_c + v_a T_in,c
    dV_i/dt = (r_i / J_i) (n_i u_i - b_i V_i / r_i + Σ_leaving a_k T_k - Σ_entering a_k T_k)

with v at a node = (a / r_j) V_j (the span's arm a on the node, r_j the drive's measuring
arm), each span's tension that of its web's loadcell c in the zone z it lies in (one lumped
span per web), T_c = (T*_c / S*_z) S_z (the lanes' split at the operating point; 1 with one
loadcell, so each section is the one its drive is designed on, ``decentral.section_model``).
The couplings a chain has not:

- **the nip** (lamination, B2): the laminate zone's T_in is the sum of its layers' zone
  tensions, so A_{laminate, layer} = v_nip / L for every layer's section; the nip's own speed
  row reads every zone on it: -r a / J from each arriving layer's, +r a / J from the
  laminate's;
- **the knife** (slit, B3): a lane zone's T_in = (EA_lane/EA_base) T_base, a coupling v_a
  share / L from the base web's zone.

This carries over where every span that a section's equations read lies in some drive's zone
and every zone ends at drives' nodes (the laminator, with its driven nip). It does not where
a junction is an idle roller (the slitter's knife, an idle roller between zones): the
knife's speed and the spans between the pull roll and it belong to no section, so no
decomposition into sections with their own inputs holds them (as a section without input,
its Ā would be the knife's open span mode, ζ ~ 0.003, against couplings of EA/L ~ 1e5 N/m
per m/s): refused, naming the node.
"""

from __future__ import annotations

import numpy as np

from webline.analysis.certificate import Certificate, NRule, Scaling, certificate_of
from webline.control.sections import SectionModel
from webline.errors import ArgumentError, LineFileError
from webline.model.web_graph import BranchedLine, load_branched
from webline.sim.branches.drives.decentral import design, design_time
from webline.sim.branches.equilibrium import BranchPoint, operating_point
from webline.sim.branches.linear import branch_linear_model, sampled_closed_loop
from webline.sim.branches.loop import layout as B
from webline.sim.branches.loop.plant import node_inertia
from webline.sim.branches.plan import BranchPlan, compile_branches
from webline.spec.load import branched_from_dict


class NotCertifiable(ArgumentError):
    """The line's sections do not hold all its states (module docstring): why, in one line."""


def _arm(plan: BranchPlan, x: np.ndarray, k: int, node: int) -> float:
    """Span ``k``'s arm [m] on ``node`` (its roll's radius there, else the roller's)."""
    end = B.S_ARMA if plan.si[k, B.S_A] == node else B.S_ARMB
    roll = int(plan.si[k, end])
    return float(x[plan.offsets[B.O_RADIUS] + roll]) if roll >= 0 else float(
        plan.nodes[node, B.N_RADIUS])


def _measuring_arm(plan: BranchPlan, x: np.ndarray, d: int) -> float:
    roll, node = int(plan.di[d, B.DI_ROLL]), int(plan.di[d, B.DI_NODE])
    return float(x[plan.offsets[B.O_RADIUS] + roll]) if roll >= 0 else float(
        plan.nodes[node, B.N_RADIUS])


def lumped_tree(plan: BranchPlan, point: BranchPoint) -> list[SectionModel]:
    """The sections of ``plan`` at ``point`` (module docstring): per drive its A_i, B_i and
    couplings A_ij (SI; states S [N] where it has a zone, V [m/s]), in drive order.
    ``NotCertifiable`` where a span a section reads, or a zone's end, belongs to no drive."""
    line, x = plan.line, point.x
    names = [r.name for r in line.spec.rollers]
    drives = list(line.drives)
    drive_of = {i: d for d, i in enumerate(drives)}
    zone_of_span = {k: i for i, z in line.zones.items() for k in z.spans}
    zoned = [d for d, i in enumerate(drives) if i in line.zones]
    s_index = {d: n for n, d in enumerate(zoned)}  # S states first, then every V
    n_s, n_d = len(zoned), len(drives)
    full, b_full = np.zeros((n_s + n_d, n_s + n_d)), np.zeros(n_s + n_d)

    def zone_total(i: int) -> float:
        return float(sum(x[k] for k in line.zones[i].loadcells))

    def tension_row(k: int, why: str) -> tuple[int, float]:
        """(S column, T*_k / S*) of span ``k``; refused if it lies in no zone."""
        if k not in zone_of_span:
            span = line.spans[k]
            raise NotCertifiable(
                f"{line.name}: span {span.name} ({why}) lies in no drive's zone, so no section "
                f"holds its tension (an idle junction such as "
                f"{names[int(plan.si[k, B.S_B])]} between zones): thesis Thm 6.2.1's "
                "decomposition into sections with their own inputs does not cover it")
        owner = zone_of_span[k]
        web = line.spans[k].web  # the lump: every span of a web in the zone at its loadcell's
        cell = next((c for c in line.zones[owner].loadcells if line.spans[c].web == web), k)
        return s_index[drive_of[owner]], float(x[cell]) / zone_total(owner)

    def speed_column(node: int, k: int) -> tuple[int, float]:
        """(V column, a / r) of the drive on ``node`` as span ``k`` sees it."""
        if node not in drive_of:
            raise NotCertifiable(
                f"{line.name}: zone of span {line.spans[k].name} ends at {names[node]}, an "
                "idle roller: its speed belongs to no section (thesis Thm 6.2.1 needs every "
                "zone between drives)")
        d = drive_of[node]
        return n_s + d, _arm(plan, x, k, node) / _measuring_arm(plan, x, d)

    v_at = [float(_measuring_arm(plan, x, d) * x[plan.offsets[B.O_OMEGA] + i])
            for d, i in enumerate(drives)]
    for d in zoned:
        i = drives[d]
        zone, row = line.zones[i], s_index[d]
        for k in zone.loadcells:
            web = line.spans[k].web
            spans = sorted((s for s in zone.spans if line.spans[s].web == web),
                           key=lambda s: line.spans[s].k)
            first, last = spans[0], spans[-1]
            length = sum(line.spans[s].length for s in spans)
            ea, tension = float(plan.sf[k, B.SF_EA]), float(x[k])
            node_a, node_b = int(plan.si[first, B.S_A]), int(plan.si[last, B.S_B])
            col_a, arm_a = speed_column(node_a, first)
            col_b, arm_b = speed_column(node_b, last)
            v_a, v_b = arm_a * v_at[col_a - n_s], arm_b * v_at[col_b - n_s]
            t_in, inputs = _carried_in(plan, x, first, tension_row)
            share = tension / zone_total(i)
            full[row, row] -= v_b / length * share
            full[row, col_b] += (ea - tension) / length * arm_b
            full[row, col_a] -= (ea - t_in) / length * arm_a
            for col, factor in inputs:
                full[row, col] += v_a / length * factor
    for d, i in enumerate(drives):
        row = n_s + d
        r = _measuring_arm(plan, x, d)
        inertia = float(node_inertia(i, x, plan.offsets, plan.nodes, plan.rolls))
        for k in range(len(line.spans)):
            sign = (1.0 if plan.si[k, B.S_A] == i else 0.0) - (
                1.0 if plan.si[k, B.S_B] == i else 0.0)
            if sign == 0.0:
                continue
            col, factor = tension_row(k, f"on {names[i]}")
            full[row, col] += sign * r * _arm(plan, x, k, i) / inertia * factor
        full[row, row] = -plan.nodes[i, B.N_VISCOUS] / inertia
        b_full[row] = plan.nodes[i, B.N_RATIO] * r / inertia
    index = [[s_index[d], n_s + d] if d in s_index else [n_s + d] for d in range(n_d)]
    models = []
    for d, i in enumerate(drives):
        rows = index[d]
        coupling = {j: full[np.ix_(rows, index[j])] for j in range(n_d) if j != d}
        states = ((["+".join(line.spans[k].name for k in line.zones[i].loadcells) + "_tension"]
                   if d in s_index else []) + [f"{names[i]}_speed"])
        models.append(SectionModel(i, i if d in s_index else None, full[np.ix_(rows, rows)],
                                   b_full[rows].reshape(-1, 1), coupling, tuple(states)))
    return models


def _carried_in(plan: BranchPlan, x: np.ndarray, k: int, tension_row
                ) -> tuple[float, list[tuple[int, float]]]:
    """(T_in* [N], [(S column, ∂T_in/∂S)]) of what the web carries into span ``k``: the
    previous span's, a laminate's layers' sum (B2), a lane's share of its base web (B3), a
    wound-in tension (constant, no column)."""
    src, frm = int(plan.si[k, B.S_SRC]), int(plan.si[k, B.S_FROM])
    if src == B.SRC_WOUND:
        return float(plan.wound[plan.si[k, B.S_WEB]]), []
    if src == B.SRC_PREVIOUS:
        sources, factor = [frm], 1.0
    elif src == B.SRC_LAYERS:
        sources = [int(plan.layers[frm + j]) for j in range(int(plan.si[k, B.S_COUNT]))]
        factor = 1.0
    else:  # a lane: its share of the base web's tension at the knife
        sources, factor = [frm], float(plan.sf[k, B.SF_SHARE])
    columns = []
    for s in sources:
        col, split = tension_row(s, "carried into a zone")
        columns.append((col, factor * split))
    return factor * float(sum(x[s] for s in sources)), columns


def state_feedback_line(line: BranchedLine) -> BranchedLine:
    """``line`` with every cascaded-PI drive on webline's default state feedback (the
    family's default scales and LQ design), as the chain's certificate designs every drive;
    ``NotCertifiable`` where the line cannot run it (one line, the key named)."""
    data = line.spec.model_dump(exclude_none=True)
    changed = False
    for roller in data["rollers"]:
        if roller.get("controller", {}).get("type") == "cascaded_pi":
            roller["controller"] = {"type": "state_feedback"}
            changed = True
    if not changed:
        return line
    try:
        return BranchedLine(branched_from_dict(data, line.source), line.source,
                            line.roll_change, line.scenario)
    except LineFileError as exc:
        raise NotCertifiable(f"thesis Thm 6.2.1 is about decentralized state feedback on every "
                             f"drive, which this line cannot run: "
                             f"{str(exc).splitlines()[0]}") from None


def branch_certificate(line: BranchedLine | str, *, n_rule: NRule = "thesis",
                       scaling: Scaling = "optimize", plant: bool = True) -> Certificate:
    """Theorem 6.2.1 for branched ``line`` at its design point (module docstring): each
    drive's Ā_i = A_i - B_i K_i of the run's design (a PI drive: webline's default
    state-feedback design, ``state_feedback_line``), the couplings of ``lumped_tree``.
    ``plant``: also the full closed-loop model's largest Re λ [1/s] with those gains and
    the sampled loop's spectral radius. ``NotCertifiable`` (an ``ArgumentError``) where the
    tree's sections do not hold all it reads or the line cannot run state feedback."""
    plan = compile_branches(state_feedback_line(load_branched(line)))
    point = operating_point(plan, design_time(plan))
    models = lumped_tree(plan, point)
    bars = []
    for d, model in enumerate(models):
        k = design(plan, point, d).gain[-model.a.shape[0]:]
        bars.append(model.a - model.b @ k[None, :])
    checks: tuple[float | None, float | None] = (None, None)
    if plant:
        full = branch_linear_model(plan, point, "closed").a
        checks = (float(np.linalg.eigvals(full).real.max()),
                  float(np.abs(np.linalg.eigvals(sampled_closed_loop(plan, point))).max()))
    names = [plan.line.spec.rollers[m.node].name for m in models]
    return certificate_of(models, bars, names, point.line_speed, n_rule=n_rule,
                          scaling=scaling, plant=checks)
