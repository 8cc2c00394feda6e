"""Tables of a run, its operating point and its modes, as numbers in the chosen units and as
formatted text that both the terminal and the HTML report show."""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from webline.analysis.modes import Mode
from webline.line import Line
from webline.model.operating_point import OperatingPoint
from webline.report.text.display import Display, number_text
from webline.sim.results.run_result import RunResult
from webline.spec.schema import DrivenSpec

if TYPE_CHECKING:
    from webline.model.web_graph import BranchedLine


@dataclass(frozen=True)
class Table:
    """A titled table of text cells; ``key`` names it (HTML id, tests)."""

    key: str
    title: str
    columns: tuple[str, ...]
    rows: tuple[tuple[str, ...], ...]


def make_table(key: str, title: str, columns: Sequence[str],
               rows: Sequence[Sequence[str]]) -> Table:
    """A ``Table`` from any sequences of text."""
    return Table(key, title, tuple(columns), tuple(tuple(row) for row in rows))


def node_kind(line: Line | BranchedLine, i: int) -> str:
    """'unwind', 'rewind', 'idle', 'master' or 'tension' (a tension-controlling driven roller)."""
    roller = line.spec.rollers[i]
    return roller.role if isinstance(roller, DrivenSpec) else roller.type


# --- run summary ---------------------------------------------------------------------------

_SPAN_STATS = (("reference", "reference (mean)"), ("mean", "mean"), ("std", "std"),
               ("mean_error", "mean error"), ("max_abs_error", "largest |error|"),
               ("rms_error", "rms error"))
_DRIVE_STATS = (("mean_reference", "speed reference (mean)", "speed"),
                ("mean_error", "mean speed error", "speed"),
                ("std_error", "std of speed error", "speed"),
                ("max_abs_error", "largest |speed error|", "speed"),
                ("max_abs_torque", "largest |torque|", "torque"))


def summary_values(result: RunResult, display: Display) -> dict[str, object]:
    """The run's summary in the chosen units: per span tension statistics (reference mean,
    mean, std, mean/largest/rms error against the reference; errors absent where a span has
    no loadcell), per drive speed-error statistics and largest torque, the event statistics
    per span and drive [s] (``webline.sim.results.events``), status."""
    force, speed, torque = (display.factor(k) for k in ("force", "speed", "torque"))
    raw = result.summary()
    spans: dict[str, dict[str, float]] = {}
    for k, (name, stats) in enumerate(raw["spans"].items()):
        ref = result.tension_ref[:, k]
        entry = {"reference": float(np.mean(ref)) * force} if np.all(np.isfinite(ref)) else {}
        spans[name] = entry | {key: value * force for key, value in stats.items()}
    drives = {name: {key: value * (torque if key == "max_abs_torque" else speed)
                     for key, value in stats.items()}
              for name, stats in raw["drives"].items()}
    return {
        "line": result.line.name, "status": result.status, "message": result.message,
        "duration_s": float(result.time[-1]) if len(result.time) else 0.0,
        "units": {"tension": display.plain_unit("force"), "speed": display.plain_unit("speed"),
                  "torque": display.plain_unit("torque")},
        "spans": spans, "drives": drives,
        "events": [e.as_dict() for e in result.events],
    }


def json_safe(value: object) -> object:
    """``value`` with every NaN or infinite float replaced by None (strict JSON, as
    ``summary.json`` is written)."""
    if isinstance(value, dict):
        return {k: json_safe(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [json_safe(v) for v in value]
    if isinstance(value, float):
        return float(value) if math.isfinite(value) else None
    return value


def summary_tables(result: RunResult, display: Display) -> list[Table]:
    """The span-tension and drive tables of any run's summary (a line of webs' too), in the
    chosen units."""
    values = summary_values(result, display)
    spans: dict[str, dict[str, float]] = values["spans"]  # type: ignore[assignment]
    drives: dict[str, dict[str, float]] = values["drives"]  # type: ignore[assignment]
    span_rows = [[name] + [number_text(stats.get(key)) for key, _ in _SPAN_STATS]
                 for name, stats in spans.items()]
    drive_rows = [[name, node_kind(result.line, i)]
                  + [number_text(drives[name][key]) for key, _, _ in _DRIVE_STATS]
                  for name, i in zip(drives, result.line.drives, strict=True)]
    return [
        make_table("summary-spans", "Span tension",
                   ["span"] + [display.label(label, "force") for _, label in _SPAN_STATS],
                   span_rows),
        make_table("summary-drives", "Drives",
                   ["drive", "role"] + [display.label(label, kind)
                                        for _, label, kind in _DRIVE_STATS], drive_rows),
    ]


# --- operating point and modes ----------------------------------------------------------------


def operating_point_values(op: OperatingPoint, display: Display) -> dict[str, object]:
    """The operating point in the chosen units: line speed, per span tension, per node radius,
    web speed and inertia, per drive equilibrium motor torque."""
    drives = dict(zip(op.drives, op.torque.tolist(), strict=True))
    return {
        "time_s": op.time,
        "line_speed": display.value(op.line_speed, "speed"),
        "units": {k: display.plain_unit(k)
                  for k in ("force", "speed", "length", "inertia", "torque")},
        "tension": {name: display.value(t, "force")
                    for name, t in zip(op.span_names, op.tension, strict=True)},
        "nodes": {name: {"radius": display.value(op.radius[i], "length"),
                         "speed": display.value(op.speed[i], "speed"),
                         "inertia": display.value(op.inertia[i], "inertia"),
                         "torque": (display.value(drives[i], "torque") if i in drives
                                    else None)}
                  for i, name in enumerate(op.node_names)},
    }


def operating_point_tables(line: Line, op: OperatingPoint, display: Display) -> list[Table]:
    """Node and span tables of the operating point (equilibrium inputs = motor torques)."""
    values = operating_point_values(op, display)
    nodes: dict[str, dict[str, float | None]] = values["nodes"]  # type: ignore[assignment]
    node_rows = [[name, node_kind(line, i)] + [number_text(v[key]) for key in
                                               ("radius", "speed", "inertia", "torque")]
                 for i, (name, v) in enumerate(nodes.items())]
    loadcells = {zone.loadcell for zone in line.zones}
    span_rows = [[name, f"{line.node_name(k)} → {line.node_name(k + 1)}",
                  number_text(display.value(op.tension[k], "force")),
                  "yes" if k in loadcells else ""] for k, name in enumerate(op.span_names)]
    speed = display.text(op.line_speed, "speed")
    return [
        make_table("op-nodes", f"Rollers at the operating point (t = {op.time:g} s, "
                   f"line speed {speed})",
                   ["roller", "kind", display.label("radius", "length"),
                    display.label("web speed", "speed"), display.label("inertia", "inertia"),
                    display.label("equilibrium motor torque", "torque")], node_rows),
        make_table("op-spans", "Spans at the operating point",
                   ["span", "from → to", display.label("tension", "force"), "loadcell"],
                   span_rows),
    ]


def modes_table(modes: Sequence[Mode]) -> Table:
    """Closed-loop modes: eigenvalue, natural and damped frequency [rad/s, Hz], damping ratio."""
    rows = []
    for j, mode in enumerate(modes, start=1):
        lam = mode.eigenvalue
        eig = number_text(lam.real) + (f" ± {number_text(lam.imag)}j" if lam.imag else "")
        rows.append([str(j), eig, number_text(mode.natural_frequency),
                     number_text(mode.frequency_hz), number_text(mode.damped_frequency),
                     number_text(mode.damping, 3), mode.dominant])
    return make_table("modes", "Closed-loop modes (the line with its controllers, linearized)",
                      ["mode", "eigenvalue [1/s]", "ωn [rad/s]", "fn [Hz]", "ωd [rad/s]",
                       "ζ", "dominant state"], rows)


def least_damped(modes: Sequence[Mode]) -> Mode | None:
    """The oscillatory mode with the smallest damping ratio (None if no mode oscillates)."""
    oscillatory = [m for m in modes if m.oscillatory and not math.isnan(m.damping)]
    return min(oscillatory, key=lambda m: m.damping, default=None)
