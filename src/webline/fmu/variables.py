"""The variables of a line's FMU (docs/fmu.md, "Variables"): inputs, outputs and parameters
named as webline's results name them, each read from or written to a cell of the loop's
tables (``loop_object.FLOAT_ARRAYS``) by one of the C wrapper's operations (``fmi_wrapper.c``,
``OP_*``).

Outputs are read at each communication point from the record the loop writes for that tick
(``kernel.new_records``: [t, x..., torque commands..., calculated radii...]), after the
tick's controller step, as ``webline.simulate`` records it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from webline.sim.branches.dancers import dancer_nodes
from webline.sim.branches.loop import layout as B
from webline.sim.branches.loop.web_law import felt_start
from webline.sim.branches.plan import BranchPlan

#: the C wrapper's operations (fmi_wrapper.c, in its order)
(OP_COPY, OP_CLIP0, OP_MUL, OP_LE0, OP_SAT, OP_GE0, OP_STATUS, OP_PARAM,
 OP_INPUT, OP_TIME, OP_LIVE) = range(11)

Cell = tuple[str, int]  # (array name, flat index)


@dataclass(frozen=True)
class Variable:
    """One FMU variable: ``name`` as webline names the signal (``tension[zone2]``), ``kind``
    "Real" | "Boolean" | "Integer", ``causality`` "output" | "input" | "parameter", ``unit``
    (SI, "" for none), the operation ``op`` (``OP_*``) on cells ``a`` and ``b`` (an input:
    ``a`` = (``"profile"``, its profile number)), ``start`` (inputs and parameters), a
    description and, for a parameter, its smallest value ``low``."""

    name: str
    kind: str
    causality: str
    unit: str
    op: int
    a: Cell
    b: Cell
    start: float
    text: str
    low: float | None = None  #: the smallest value a parameter takes (FMI ``min``)


#: the independent variable (FMI 3.0 requires it; FMI 2.0 leaves it out)
TIME = Variable("time", "Real", "independent", "s", OP_TIME, ("", -1), ("", -1), 0.0,
                "simulation time")


def fmu_variables(plan: BranchPlan, arrays: dict[str, np.ndarray],
                  plant_only: bool = False, single_path: bool = False) -> list[Variable]:
    """The variables of ``plan``'s FMU, outputs first, then inputs and parameters; ``arrays``:
    the loop's start tables (``loop_object.loop_arrays``), for the parameters' start
    values. ``plant_only``: ``plan``'s drives are all user drives (``FAMILY_USER``): their
    torque commands are inputs, and what each drive measures is an output
    (``plant_variables``). ``single_path``: ``plan`` is a single-path line's line of one web,
    whose rolls are named by their roller alone, as the single-path line's result names them."""
    if plant_only:
        plant_out, plant_in = plant_variables(plan, arrays)
        return (outputs(plan, plant_only=True, single_path=single_path) + plant_out
                + inputs(plan) + plant_in + parameters(plan, arrays) + [TIME])
    return outputs(plan, single_path=single_path) + inputs(plan) + parameters(plan, arrays) + [TIME]


def plant_variables(plan: BranchPlan, arrays: dict[str, np.ndarray]
                    ) -> tuple[list[Variable], list[Variable]]:
    """Outputs and inputs of a plant-only FMU: per drive, what a user controller reads
    (``sim.core.user_protocol`` MEASURED, REFERENCES: ``unwind.speed`` [m/s], ``.tension``
    [N], ``.radius`` [m], ``.inertia`` [kg·m²], ``.speed_reference`` [m/s],
    ``.tension_reference`` [N], as ``loop.user`` stores them at the tick), and its torque
    command ``torque_cmd[unwind]`` [N·m] (held until set again, saturated at the drive's
    limit)."""
    line = plan.line
    none: Cell = ("", -1)
    readings = (("speed", "m/s", B.I_USPEED, "surface speed the drive measures"),
                ("tension", "N", B.I_UTENSION, "tension of its zone as its loadcells read it "
                 "(NaN: none)"),
                ("radius", "m", B.I_URADIUS, "radius the drive works with"),
                ("inertia", "kg.m2", B.I_UINERTIA, "inertia at its roller"),
                ("speed_reference", "m/s", B.I_UVREF, "its speed reference"),
                ("tension_reference", "N", B.I_UTREF, "its zone's tension reference (NaN: "
                 "none)"))
    out, into = [], []
    for d, i in enumerate(line.drives):
        name = line.spec.rollers[i].name
        for what, unit, column, text in readings:
            out.append(Variable(f"{name}.{what}", "Real", "output", unit, OP_COPY,
                                ("istate", d * B.I_COLS + column), none, 0.0, text))
        cell = d * B.I_COLS + B.I_UCMD
        into.append(Variable(f"torque_cmd[{name}]", "Real", "input", "N.m", OP_LIVE,
                             ("istate", cell), none, float(arrays["istate"].ravel()[cell]),
                             "torque command of the drive (held, saturated at its limit)"))
    return out, into


def outputs(plan: BranchPlan, plant_only: bool = False, single_path: bool = False
            ) -> list[Variable]:
    """Span tensions, roller surface speeds, roll radii, motor torques and their commands
    (not ``plant_only``: there they are inputs), calculated radii, dancer positions, and
    flags: slack per span, a torque command at its limit per drive, a web break detected,
    the run's status. ``single_path``: a roll's radius named by its roller alone."""
    line, o = plan.line, plan.offsets
    n_x, n_d, n_s = plan.n_x, plan.di.shape[0], len(line.spans)
    rec = 1  # the record's x starts after its time
    none: Cell = ("", -1)
    out: list[Variable] = []

    def add(name: str, unit: str, op: int, a: Cell, b: Cell, text: str,
            kind: str = "Real") -> None:
        out.append(Variable(name, kind, "output", unit, op, a, b, 0.0, text))

    laws = plan.lawi.shape[0] > 0 or plan.kv.shape[0] > 0
    start = felt_start(n_s, plan.nodes.shape[0], plan.lawi.shape[0] > 0, plan.kv.shape[0] > 0)
    felt = [("work", start + k) if laws else ("rec", rec + k) for k in range(n_s)]
    for k, span in enumerate(line.spans):
        add(f"tension[{span.name}]", "N", OP_COPY if laws else OP_CLIP0, felt[k], none,
            "span tension the rollers feel")
    arm: list[Cell] = [("nodes", i * B.N_COLS + B.N_RADIUS) for i in range(plan.nodes.shape[0])]
    for j in reversed(range(len(line.rolls))):  # a roll: its first web's radius
        arm[line.rolls[j].node] = ("rec", rec + int(o[B.O_RADIUS]) + j)
    for d, i in enumerate(line.drives):  # a shaft: the lane its drive measures speed on
        if plan.di[d, B.DI_ROLL] >= 0:
            arm[i] = ("rec", rec + int(o[B.O_RADIUS]) + int(plan.di[d, B.DI_ROLL]))
    for i, roller in enumerate(line.spec.rollers):
        add(f"speed[{roller.name}]", "m/s", OP_MUL, arm[i], ("rec", rec + int(o[B.O_OMEGA]) + i),
            "surface speed of the roller")
    for j, roll in enumerate(line.rolls):
        name = line.spec.rollers[roll.node].name
        name += "" if single_path else f"/{line.spec.webs[roll.web].name}"
        add(f"radius[{name}]", "m", OP_COPY, ("rec", rec + int(o[B.O_RADIUS]) + j), none,
            "wound radius of the roll")
    drives = [line.spec.rollers[i].name for i in line.drives]
    for d, name in enumerate(drives):
        add(f"torque[{name}]", "N.m", OP_COPY, ("rec", rec + int(o[B.O_TORQUE]) + d), none,
            "motor torque")
    for d, name in enumerate(drives if not plant_only else []):
        add(f"torque_cmd[{name}]", "N.m", OP_COPY, ("rec", rec + n_x + d), none,
            "torque command of the drive's controller")
    for d, name in enumerate(drives):
        add(f"control_radius[{name}]", "m", OP_COPY, ("rec", rec + n_x + n_d + d), none,
            "radius the drive's diameter calculator gives it (0: none)")
    for q, i in enumerate(dancer_nodes(line)):
        add(f"dancer_position[{line.spec.rollers[i].name}]", "m", OP_COPY,
            ("rec", rec + int(o[B.O_DANCER]) + 2 * q), none,
            "dancer carriage position y (0 .. travel)")
    for k, span in enumerate(line.spans):
        add(f"slack[{span.name}]", "", OP_LE0, felt[k], none, "the span carries no tension",
            "Boolean")
    for d, name in enumerate(drives):
        add(f"saturated[{name}]", "", OP_SAT, ("rec", rec + n_x + d),
            ("df", d * B.D_COLS + B.D_LIMIT), "the torque command is at the drive's limit",
            "Boolean")
    if n_d:
        add("break_detected", "", OP_GE0, ("istate", B.I_DETECT), none,
            "a web break was detected by the drives' monitor", "Boolean")
    add("status", "", OP_STATUS, none, none, "0 running; 1 non-finite state, 2 unwind empty, "
        "3 runaway, 4 web beyond its strength (the run stopped)", "Integer")
    return out


def inputs(plan: BranchPlan) -> list[Variable]:
    """The line speed reference and each zone's tension set point: setting one holds the
    value from that communication point on in place of the scenario's profile (profile 0 is
    the line speed, then the spans with a tension reference, ``BranchPlan``)."""
    line = plan.line
    out = [Variable("speed_ref", "Real", "input", "m/s", OP_INPUT, ("profile", 0), ("", -1),
                    _profile_start(plan, 0), "line speed reference")]
    p = 1
    for k, span in enumerate(line.spans):
        if line.span_tension_spec(k) is not None:
            out.append(Variable(f"tension_ref[{span.name}]", "Real", "input", "N", OP_INPUT,
                                ("profile", p), ("", -1), _profile_start(plan, p),
                                "tension set point of the span's zone"))
            p += 1
    return out


def parameters(plan: BranchPlan, arrays: dict[str, np.ndarray]) -> list[Variable]:
    """Table cells a user may tune at instantiation: EA per span (linear elastic webs),
    constant inertia and frictions per roller, gains and torque limit per cascaded-PI drive.
    A cell with a reciprocal in the tables (1/EA, 1/J) keeps it (``b``)."""
    line = plan.line
    out: list[Variable] = []

    def add(name: str, unit: str, array: str, index: int, text: str, inverse: int = -1) -> None:
        value = float(arrays[array].ravel()[index])
        out.append(Variable(name, "Real", "parameter", unit, OP_PARAM, (array, index),
                            (array, inverse), value, text, 0.0))

    if plan.lawi.shape[0] == 0 and plan.kv.shape[0] == 0:
        for k, span in enumerate(line.spans):
            add(f"EA[{span.name}]", "N", "sf", k * B.SF_COLS + B.SF_EA,
                "web stiffness E·A in the span", k * B.SF_COLS + B.SF_INVEA)
    for i, roller in enumerate(line.spec.rollers):
        row = i * B.N_COLS
        add(f"inertia[{roller.name}]", "kg.m2", "nodes", row + B.N_JCONST,
            "constant inertia of the roller with its drive (a roll adds its wound web)",
            row + B.N_INVJ)
        add(f"viscous_friction[{roller.name}]", "N.m.s/rad", "nodes", row + B.N_VISCOUS,
            "viscous friction of the roller")
        add(f"coulomb_friction[{roller.name}]", "N.m", "nodes", row + B.N_COULOMB,
            "Coulomb friction of the roller")
    for d, i in enumerate(line.drives):
        name, row = line.spec.rollers[i].name, d * B.D_COLS
        add(f"torque_limit[{name}]", "N.m", "df", row + B.D_LIMIT, "torque limit of the drive")
        if plan.di[d, B.DI_FAMILY] != B.FAMILY_PI:
            continue
        add(f"speed_kp[{name}]", "N.m.s/m", "df", row + B.D_KPS, "speed PI proportional gain")
        add(f"speed_ki[{name}]", "N.m/m", "df", row + B.D_KIS, "speed PI integral gain")
        add(f"tension_kp[{name}]", "m/(s.N)", "df", row + B.D_KPT,
            "tension PI proportional gain (speed trim per N)")
        add(f"tension_ki[{name}]", "m/(s2.N)", "df", row + B.D_KIT, "tension PI integral gain")
    return out


def _profile_start(plan: BranchPlan, p: int) -> float:
    return plan.profile(p, 0.0)
