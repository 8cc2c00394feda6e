"""Units and CF attributes (long_name, units, flags) of the signals a ``Result`` exports."""

from __future__ import annotations

import numpy as np

#: unit of each kind of signal, as attributes in the xarray output
SIGNAL_UNITS = {
    "tension": "N", "tension_ref": "N", "speed": "m/s", "speed_ref": "m/s", "omega": "rad/s",
    "torque": "N*m", "torque_cmd": "N*m", "trim": "m/s", "radius": "m", "inertia": "kg*m**2",
    "slack": "", "motor_speed": "rad/s", "twist": "rad", "contact": "",
    "friction_estimate": "N*m*s", "control_radius": "m", "equilibrium_input": "N*m",
    "web_unwound": "m",
    "surface_speed": "m/s", "slipping": "", "slip_velocity": "m/s", "slip_power": "W",
    "web_rewound": "m", "web_stored": "m", "wound_in": "N",
    "mrac_gain_tension": "m", "mrac_gain_speed": "N*s", "mrac_bias": "N*m",
    "dancer_position": "m", "tension_measured": "N", "speed_measured": "m/s",
    # a line of several webs (and laminates, differential shafts) also gives these
    "strain": "1", "layer_tension": "N", "layer_strain": "1",
    "web_in": "m", "web_out": "m", "layer_in": "m", "layer_out": "m", "layer_stored": "m",
    "core_omega": "rad/s", "motor_omega": "rad/s",
}


#: CF ``long_name`` of each signal (the CF standard names have none for web handling)
LONG_NAMES = {
    "tension": "span tension", "tension_ref": "span tension reference (loadcell spans)",
    "slack": "span is slack (no tension)", "speed": "web speed at the node",
    "surface_speed": "roller surface speed", "slipping": "web slips over the roller",
    "slip_velocity": "surface speed minus web speed", "slip_power": "power dissipated by slip",
    "omega": "roller angular speed", "radius": "effective roller radius",
    "speed_ref": "drive speed-loop reference", "torque": "motor torque",
    "torque_cmd": "motor torque command", "trim": "tension-loop speed trim",
    "motor_speed": "motor angular speed", "twist": "transmission twist at the load shaft",
    "contact": "backlash contact (+1 forward flank, -1 backward, 0 in the gap)",
    "friction_estimate": "adaptive friction estimate",
    "control_radius": "radius the drive's controllers use (calculated or true)",
    "equilibrium_input": "equilibrium motor torque", "inertia": "roll inertia at the shaft",
    "web_unwound": "unstrained web unwound", "web_rewound": "unstrained web rewound",
    "web_stored": "unstrained web held in the spans",
    "mrac_gain_tension": "MRAC adapted gain on the tension deviation",
    "mrac_gain_speed": "MRAC adapted gain on the speed deviation",
    "mrac_bias": "MRAC adapted bias (equilibrium input error)",
    "dancer_position": "dancer carriage position (0 and its stroke: the end stops)",
    "tension_measured": "span tension as its loadcell shows it (gain, offset, delay; no noise)",
    "speed_measured": "web speed as its drive's encoder shows it (scale, delay; no noise)",
    "strain": "span strain EA·ε / EA", "layer_tension": "layer tension in a laminate span",
    "layer_strain": "layer's own strain in a laminate span",
    "web_in": "unstrained web in at the path's start",
    "web_out": "unstrained web out at the path's end",
    "layer_in": "unstrained layer in at its laminate's start",
    "layer_out": "unstrained layer out at its laminate's end",
    "layer_stored": "unstrained layer in its laminate's spans",
    "core_omega": "angular speed of a lane's core on a differential shaft",
    "motor_omega": "motor angular speed / ratio (at the load shaft)",
}
#: flag meanings (CF) of the integer-coded signals
FLAGS = {"slack": ([0, 1], "taut slack"), "slipping": ([0, 1], "stuck slipping")}


def signal_attrs(name: str) -> dict[str, object]:
    """CF attributes of signal ``name``: ``long_name`` and ``units`` (UDUNITS syntax; "1" for
    a ratio), flags for the coded ones."""
    attrs: dict[str, object] = {"long_name": LONG_NAMES[name]}
    if name in FLAGS:
        values, meanings = FLAGS[name]
        attrs |= {"flag_values": np.array(values, dtype=np.int8), "flag_meanings": meanings}
    else:
        attrs["units"] = SIGNAL_UNITS[name] or "1"
    return attrs
