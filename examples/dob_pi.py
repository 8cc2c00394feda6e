"""A disturbance-observer PI as a user controller (docs/controllers.md).

The cascaded PI of ``user_pi.py`` with a disturbance observer (DOB) on each drive's speed
loop. Per drive the roller obeys M dv/dt = τ + d with M = J / (n r) [N·m·s/m] from
the measured inertia and radius, d [N·m] everything else (web tensions, friction). The DOB
estimates d through a first-order filter of bandwidth ``bandwidth`` [rad/s],

    d̂ ← d̂ + ω_c dt (M (v_k - v_k-1) / dt - τ_k-1 - d̂),

and the command cancels it: τ = τ_PI - d̂. It starts at equilibrium: d̂ holds the load there
(-equilibrium command) and the PI's speed integrator starts at zero.

    python examples/dob_pi.py
"""

from __future__ import annotations

import sys
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

import webline
from webline.sim.user_control import ControllerContext

sys.path.insert(0, str(Path(__file__).resolve().parent))
from user_pi import CascadedPI


class DisturbanceObserverPI(CascadedPI):
    """``CascadedPI`` plus a disturbance observer per drive (module docstring)."""

    def __init__(self, bandwidth: float = 30.0) -> None:
        self.bandwidth = bandwidth  # [rad/s]

    def reset(self, context: ControllerContext) -> None:
        super().reset(context)
        self.estimate = [-d.equilibrium_command for d in context.drives]  # d̂ [N·m]
        self.speed_integral = [0.0] * len(context.drives)  # the DOB holds the load
        self.last_speed: list[float | None] = [None] * len(context.drives)
        self.last_torque = [d.equilibrium_command for d in context.drives]

    def __call__(self, t: float, measurements: np.ndarray,
                 references: np.ndarray) -> np.ndarray:
        gain = min(self.bandwidth * self.dt, 1.0)
        for k, drive in enumerate(self.drives):
            speed, _, radius, inertia = measurements[4 * k:4 * k + 4]
            last = self.last_speed[k]
            if last is not None:
                mass = inertia / (drive.ratio * radius)  # [N·m·s/m]
                felt = mass * (speed - last) / self.dt - self.last_torque[k]
                self.estimate[k] += gain * (felt - self.estimate[k])
            self.last_speed[k] = speed
        torques = super().__call__(t, measurements, references)
        for k, drive in enumerate(self.drives):
            torques[k] = min(max(torques[k] - self.estimate[k], -drive.torque_limit),
                             drive.torque_limit)
            self.last_torque[k] = torques[k]
        return torques


def tension_rms(result: webline.Result) -> float:
    """RMS over spans and time of the tension error relative to each span's mean [-]."""
    tension = result.tension
    return float(np.sqrt(np.mean(((tension - tension.mean(axis=0)) / tension.mean(axis=0))
                                 ** 2)))


def main() -> None:
    line = webline.load_line("hswl")
    builtin = webline.simulate(line, scenario="speed-change")
    dob = webline.simulate(line, scenario="speed-change", controller=DisturbanceObserverPI())
    print(f"hswl speed-change: relative tension RMS built-in PI {tension_rms(builtin):.3g}, "
          f"DOB-PI {tension_rms(dob):.3g}; verdicts {builtin.status}, {dob.status}")
    _, ax = plt.subplots(figsize=(8, 3.5), layout="constrained")
    for name, result in (("built-in PI", builtin), ("DOB-PI", dob)):
        result.signals.tension.sel(span="span2").plot(ax=ax, label=name, lw=1.0)
    ax.set_title("hswl speed change: tension of span2")
    ax.legend()
    ax.grid(alpha=0.3)
    plt.show()


if __name__ == "__main__":
    main()
