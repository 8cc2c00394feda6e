"""The signals a measurement file may hold: the names webline itself writes
(``tension[process_span]``, ``speed[rewind]``, ``torque[unwind]`` ...), what kind of quantity
each is, and how to read the same signal from a simulated ``Result``."""

from __future__ import annotations

import difflib
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from webline.twin.traces.layout import layout

if TYPE_CHECKING:
    from webline.line import Line
    from webline.model.web_graph import BranchedLine
    from webline.sim.results.run_result import RunResult

#: signal kind -> (element dimension, unit kind of ``webline.units``, ``Result`` attribute);
#: a log's tension and speed are what its loadcells and encoders show: they compare with the
#: readings of the line's sensors (``spec.sensors``; the true values where none is calibrated)
COMPARED: dict[str, tuple[str, str, str]] = {
    "tension": ("span", "force", "tension_measured"),
    "tension_ref": ("span", "force", "tension_ref"),
    "speed": ("node", "speed", "speed_measured"),
    "surface_speed": ("node", "speed", "surface_speed"),
    "omega": ("node", "angular_frequency", "omega"),
    "radius": ("node", "length", "radius"),
    "speed_ref": ("drive", "speed", "speed_ref"),
    "torque": ("drive", "torque", "torque"),
    "torque_cmd": ("drive", "torque", "torque_cmd"),
    "trim": ("drive", "speed", "trim"),
    "motor_speed": ("drive", "angular_frequency", "motor_speed"),
    "dancer_position": ("dancer", "length", "dancer_position"),
}
#: signals of webline's own results files that are read but never compared (flags, the
#: controllers' internal estimates, web bookkeeping, a branched run's strains, layers and
#: lanes' cores): a run's own file loads without a mapping
IGNORED = ("slack", "slipping", "slip_velocity", "slip_power", "twist", "contact",
           "friction_estimate", "control_radius", "equilibrium_input", "inertia",
           "web_unwound", "web_rewound", "web_stored", "mrac_gain_tension", "mrac_gain_speed",
           "mrac_bias", "strain", "layer_tension", "layer_strain", "web_in", "web_out",
           "layer_in", "layer_out", "layer_stored", "core_omega", "radius_calc",
           "tension_measured", "speed_measured")
#: references: they drive a replay, and are compared only to show they were followed
REFERENCES = ("tension_ref", "speed_ref")


@dataclass(frozen=True)
class Signal:
    """One measurable signal of a line: ``kind[element]``, its unit kind and where it sits in
    a ``Result`` (attribute, column)."""

    name: str
    kind: str
    element: str
    unit_kind: str
    attribute: str
    column: int


def line_signals(line: Line | BranchedLine) -> dict[str, Signal]:
    """Every comparable signal of ``line`` by name (``tension[process_span]`` ...): the kinds
    its runs record, each on its elements (a branched line's radii per roll,
    ``radius[rewind/laminate]``, as its results files name them)."""
    view = layout(line)
    out = {}
    for kind, (dim, unit_kind, attribute) in COMPARED.items():
        if kind in view.missing:
            continue
        dim = view.dims.get(kind, dim)
        for column, element in enumerate(view.elements[dim]):
            name = f"{kind}[{element}]"
            out[name] = Signal(name, kind, element, unit_kind, attribute, column)
    return out


def is_ignored(line: Line | BranchedLine, name: str) -> bool:
    """Whether ``name`` is a signal webline writes that is never compared."""
    kind = name.partition("[")[0]
    return kind in IGNORED


def suggestions(name: str, known: list[str]) -> str:
    """ "; did you mean ...?" with up to three close names, or ""."""
    close = difflib.get_close_matches(name, known, n=3, cutoff=0.5)
    return f"; did you mean {', '.join(repr(c) for c in close)}?" if close else ""


def simulated(result: RunResult, signals: list[Signal]) -> dict[str, np.ndarray]:
    """The values [SI] of ``signals`` over ``result.time``: the result's attribute of that
    name where it has one (a single-path run has them all), else its signal of that name
    (``result.signals``: a branched run's speeds, radii, dancer positions)."""
    cache: dict[str, np.ndarray] = {}
    out = {}
    for signal in signals:
        if signal.attribute not in cache:
            values = getattr(result, signal.attribute, None)
            if values is None:
                values = result.signals[signal.attribute].values
            cache[signal.attribute] = np.asarray(values)
        out[signal.name] = cache[signal.attribute][:, signal.column]
    return out


def si_unit(name: str) -> str:
    """SI unit of a signal ``kind[element]`` ("" for one webline does not compare)."""
    from webline.units import SI_UNITS

    entry = COMPARED.get(name.partition("[")[0])
    return SI_UNITS[entry[1]] if entry else ""
