"""The built-in cascaded PI written as a user controller (docs/controllers.md).

A user controller is an object with ``reset(context)`` and ``__call__(t, measurements,
references) -> torques``. This one is webline's own cascaded PI (thesis Fig. 4.3; the code of
``webline.sim.drives.controllers.pi_command``) in plain Python, with the gains webline tuned for
each
drive: run on a built-in line it reproduces the built-in run to round-off. Start from it to
write your own.

    python examples/user_pi.py
"""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np

import webline
from webline.sim.user_control import ControllerContext


class CascadedPI:
    """A tension PI trims the speed reference of a speed PI, per drive (SI units)."""

    def reset(self, context: ControllerContext) -> None:
        self.dt = context.sample_period  # [s]
        self.drives = context.drives
        # start at the equilibrium the run starts from: the integrators hold its command
        self.speed_integral = [d.equilibrium_command for d in context.drives]  # [N·m]
        self.tension_integral = [d.tension_sign * d.equilibrium_trim
                                 for d in context.drives]  # [m/s]
        self.torques = np.zeros(len(context.drives))

    def __call__(self, t: float, measurements: np.ndarray,
                 references: np.ndarray) -> np.ndarray:
        for k, drive in enumerate(self.drives):
            speed, tension, radius, inertia = measurements[4 * k:4 * k + 4]
            speed_ref, tension_ref = references[2 * k], references[2 * k + 1]
            gains = drive.builtin_pi
            # a roll's speed gains follow its inertia and radius (gain scheduling)
            scale = inertia / (drive.ratio * radius) / drive.gain_norm if drive.roll else 1.0
            error_t = trim = 0.0
            if drive.role == "tension":
                error_t = tension_ref - tension
                trim = drive.tension_sign * (gains.tension_kp * error_t
                                             + self.tension_integral[k])
            error_v = speed_ref + trim - speed
            raw = gains.speed_kp * scale * error_v + self.speed_integral[k]
            torque = min(max(raw, -drive.torque_limit), drive.torque_limit)
            saturated = raw != torque
            # conditional integration: no integrator pushes further into the limit
            if not (saturated and error_v * raw > 0.0):
                self.speed_integral[k] += gains.speed_ki * scale * error_v * self.dt
            if not (saturated and drive.tension_sign * error_t * raw > 0.0):
                self.tension_integral[k] += gains.tension_ki * error_t * self.dt
            self.torques[k] = torque
        return self.torques


def main() -> None:
    line = webline.load_line("hswl")
    builtin = webline.simulate(line, 2.0)
    user = webline.simulate(line, 2.0, controller=CascadedPI())
    scale = np.max(np.abs(builtin.states), axis=0)
    worst = float(np.max(np.abs(user.states - builtin.states) / scale))
    print(f"hswl, 2 s: user PI vs built-in PI, largest difference {worst:.2g} "
          f"of each state's range; verdict: {user.status}")
    # the difference stays at round-off through the run (a zero would not show on a log axis)
    _, ax = plt.subplots(figsize=(8, 3), layout="constrained")
    ax.semilogy(user.time, np.max(np.abs(user.states - builtin.states) / scale, axis=1) + 1e-18)
    ax.set_xlabel("time [s]")
    ax.set_ylabel("largest |difference| / range")
    ax.set_title("hswl: user PI against the built-in PI, largest state difference")
    ax.grid(alpha=0.3, which="both")
    plt.show()


if __name__ == "__main__":
    main()
