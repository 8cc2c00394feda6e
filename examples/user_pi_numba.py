"""The built-in cascaded PI as a compiled control law (docs/controllers.md, "Moving a
controller into the loop").

examples/user_pi.py written against the array contract: ``params`` holds each drive's gains
and constants (``PARAMS_PER_DRIVE`` values, in the order of ``drive_params``) and the sample
period last; ``state`` holds each drive's two integrators. numba compiles the law into the
loop, where it runs as fast as the built-in PI; on a built-in line it reproduces the built-in
run to round-off.

    python examples/user_pi_numba.py
"""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np

import webline
from webline import CompiledController
from webline.sim.user_control import ControllerContext, DriveInfo

PARAMS_PER_DRIVE = 10


def drive_params(drive: DriveInfo) -> list[float]:
    """One drive's parameters: roll (1/0), tension role (1/0), σ, torque limit [N·m], speed
    kp [N·m·s/m], speed ki [N·m/m], tension kp [(m/s)/N], tension ki [(m/s)/(N·s)], motor /
    roller speed ratio, gain norm [kg·m]."""
    g = drive.builtin_pi
    return [float(drive.roll), float(drive.role == "tension"), drive.tension_sign,
            drive.torque_limit, g.speed_kp, g.speed_ki, g.tension_kp, g.tension_ki,
            drive.ratio, drive.gain_norm]


def pi_params(context: ControllerContext) -> list[float]:
    """The law's ``params``: every drive's ``drive_params``, then the sample period [s]."""
    return [v for d in context.drives for v in drive_params(d)] + [context.sample_period]


def pi_state(context: ControllerContext) -> list[float]:
    """The law's initial ``state``: per drive the speed integral [N·m] and the tension
    integral [m/s] that hold the equilibrium the run starts from."""
    return [v for d in context.drives
            for v in (d.equilibrium_command, d.tension_sign * d.equilibrium_trim)]


def cascaded_pi_law(t: float, meas: np.ndarray, refs: np.ndarray, params: np.ndarray,
                    state: np.ndarray, out: np.ndarray) -> None:
    """The cascaded PI of examples/user_pi.py, one drive after the other (SI units)."""
    dt = params[params.shape[0] - 1]
    for k in range(out.shape[0]):
        p = params[PARAMS_PER_DRIVE * k:PARAMS_PER_DRIVE * (k + 1)]
        roll, tension_role, sigma, limit = p[0], p[1], p[2], p[3]
        kps, kis, kpt, kit, ratio, gain_norm = p[4], p[5], p[6], p[7], p[8], p[9]
        speed, tension = meas[4 * k], meas[4 * k + 1]
        radius, inertia = meas[4 * k + 2], meas[4 * k + 3]
        speed_ref, tension_ref = refs[2 * k], refs[2 * k + 1]
        # a roll's speed gains follow its inertia and radius (gain scheduling)
        scale = inertia / (ratio * radius) / gain_norm if roll != 0.0 else 1.0
        error_t = trim = 0.0
        if tension_role != 0.0:
            error_t = tension_ref - tension
            trim = sigma * (kpt * error_t + state[2 * k + 1])
        error_v = speed_ref + trim - speed
        raw = kps * scale * error_v + state[2 * k]
        torque = min(max(raw, -limit), limit)
        saturated = raw != torque
        # conditional integration: no integrator pushes further into the limit
        if not (saturated and error_v * raw > 0.0):
            state[2 * k] += kis * scale * error_v * dt
        if not (saturated and sigma * error_t * raw > 0.0):
            state[2 * k + 1] += kit * error_t * dt
        out[k] = torque


def cascaded_pi() -> CompiledController:
    """The compiled cascaded PI for the drives it is given (a whole line or one drive)."""
    return CompiledController(cascaded_pi_law, params=pi_params, state=pi_state,
                              name="cascaded_pi_law")


def main() -> None:
    line = webline.load_line("hswl")
    builtin = webline.simulate(line, 2.0)
    user = webline.simulate(line, 2.0, controller=cascaded_pi())
    scale = np.max(np.abs(builtin.states), axis=0)
    worst = float(np.max(np.abs(user.states - builtin.states) / scale))
    print(f"hswl, 2 s: compiled user PI vs built-in PI, largest difference {worst:.2g} "
          f"of each state's range; verdict: {user.status}")
    # the difference stays at round-off through the run (a zero would not show on a log axis)
    _, ax = plt.subplots(figsize=(8, 3), layout="constrained")
    ax.semilogy(user.time, np.max(np.abs(user.states - builtin.states) / scale, axis=1) + 1e-18)
    ax.set_xlabel("time [s]")
    ax.set_ylabel("largest |difference| / range")
    ax.set_title("hswl: compiled user PI against the built-in PI, largest state difference")
    ax.grid(alpha=0.3, which="both")
    plt.show()


if __name__ == "__main__":
    main()
