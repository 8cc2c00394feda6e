"""A result as named variables: the one place that says which signal has which dimensions and
attributes, for ``Result.to_xarray`` and the file writers."""

from __future__ import annotations

from dataclasses import dataclass
from datetime import UTC, datetime
from typing import TYPE_CHECKING, Any

import numpy as np

from webline.sim.results.signal_attrs import signal_attrs
from webline.spec.load import dump_spec

if TYPE_CHECKING:
    import xarray as xr


#: CF ``long_name`` of each element coordinate (names, so no units)
COORD_NAMES = {"span": "span name (web order)", "node": "roller name (web order)",
               "drive": "driven roller name (web order)", "roll": "roll name (unwind, rewind)",
               "dancer": "dancer name (web order)",
               # a line of several webs: its webs, laminate layers, and lanes' cores
               "web": "web name", "span_web": "web of each span",
               "layer_span": "laminate span/layer name", "layer_web": "layer web name",
               "core": "roll on a differential shaft's clutch core"}

#: the roll coordinate's ``long_name`` of a line of webs: a roll is named ``roller/web`` (a
#: shaft's lanes one each)
WEB_ROLL_NAME = "roll name (roller/web)"

#: CF attributes of the time coordinate
TIME_ATTRS = {"units": "s", "long_name": "simulated time", "standard_name": "time", "axis": "T"}

#: one exported variable: dimensions, values and CF attributes
Variable = tuple[tuple[str, ...], np.ndarray, dict[str, object]]


@dataclass(frozen=True)
class ResultVariables:
    """A result as the variables of a CF dataset: coordinates, data and global attributes,
    with no xarray (the NetCDF writer needs none)."""

    coords: dict[str, Variable]
    data: dict[str, Variable]
    attrs: dict[str, object]


def result_variables(result: Any) -> ResultVariables:
    """``result`` (a ``Result``, which imports this module) as named variables over time with
    span, node and drive coordinates; SI units as attributes; the resolved line (TOML) and the
    webline version embedded."""
    dims_span, dims_node, dims_drive = ("time", "span"), ("time", "node"), ("time", "drive")
    data = {
        "tension": (dims_span, result.tension),
        "tension_ref": (dims_span, result.tension_ref),
        "slack": (dims_span, (result.stretch < 0.0).astype(np.int8)),
        "speed": (dims_node, result.speed),
        "surface_speed": (dims_node, result.surface_speed),
        "slipping": (dims_node, result.slipping.astype(np.int8)),
        "slip_velocity": (dims_node, result.slip_velocity),
        "slip_power": (dims_node, result.slip_power),
        "omega": (dims_node, result.omega),
        "radius": (dims_node, result.radius),
        "speed_ref": (dims_drive, result.speed_ref),
        "torque": (dims_drive, result.torque),
        "torque_cmd": (dims_drive, result.torque_cmd),
        "trim": (dims_drive, result.trim),
        "motor_speed": (dims_drive, result.motor_speed),
        "twist": (dims_drive, result.twist),
        "contact": (dims_drive, result.contact),
        "friction_estimate": (dims_drive, result.friction_estimate),
        "control_radius": (dims_drive, result.control_radius),
        "equilibrium_input": (dims_drive, result.equilibrium_input),
        "inertia": (("time", "roll"), result.inertia),
        "web_unwound": (("time",), result.web_unwound),
        "web_rewound": (("time",), result.web_rewound),
        "web_stored": (("time",), result.web_stored),
    }
    if result.has_mrac.any():
        gains = result.mrac_gains
        data |= {"mrac_gain_tension": (dims_drive, gains[:, :, 0]),
                 "mrac_gain_speed": (dims_drive, gains[:, :, 1]),
                 "mrac_bias": (dims_drive, gains[:, :, 2])}
    if result.line.spec.sensors:  # what the calibrated sensors show (spec.sensors)
        data |= {"tension_measured": (dims_span, result.tension_measured),
                 "speed_measured": (dims_node, result.speed_measured)}
    names = {"span": result.span_names, "node": result.node_names,
             "drive": result.drive_names, "roll": [result.node_names[0], result.node_names[-1]]}
    if result.dancer_names:
        data["dancer_position"] = (("time", "dancer"), result.dancer_position)
        names["dancer"] = result.dancer_names
    coords: dict[str, Variable] = {
        "time": (("time",), result.time, dict(TIME_ATTRS)),
        **{dim: ((dim,), np.array(values, dtype=object), {"long_name": COORD_NAMES[dim]})
           for dim, values in names.items()},
    }
    return ResultVariables(
        coords, {name: (dims, values, signal_attrs(name)) for name, (dims, values) in data.items()},
        result_attrs(result))


def result_attrs(result: Any) -> dict[str, object]:
    """The global CF attributes of any run's dataset (``RunResult``): conventions, title,
    source, history, the line's name and resolved file (TOML, SI), the webline version, the
    verdict's status, message and headline, and each setting as ``setting_NAME``."""
    from webline.version import __version__

    return {
        "Conventions": "CF-1.8",
        "title": f"webline simulation of line {result.line.name}",
        "source": f"webline {__version__}: compiled RK4 plant with sampled controllers",
        "history": f"{datetime.now(UTC):%Y-%m-%dT%H:%M:%SZ} webline {__version__} "
                   f"simulate ({result.status})",
        "line": result.line.name,
        "line_spec_toml": dump_spec(result.line.spec),
        "webline_version": __version__,
        "status": result.status,
        "message": result.message,
        "verdict": result.verdict.headline,
        **{f"setting_{k}": v for k, v in result.settings.items()},
    }


def to_xarray(result: Any) -> xr.Dataset:
    """``result_variables(result)`` as an ``xarray.Dataset``."""
    import xarray as xr

    variables = result_variables(result)
    ds = xr.Dataset(
        {name: xr.Variable(*variable) for name, variable in variables.data.items()},
        coords={name: xr.Variable(dims, values.astype(str) if values.dtype == object else values,
                                  attrs=attrs)
                for name, (dims, values, attrs) in variables.coords.items()},
    )
    ds.attrs.update(variables.attrs)
    return ds
