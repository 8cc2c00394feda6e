"""A discrete LQR with integral action as a user controller (docs/controllers.md).

Each drive gets its own discrete-time LQR on webline's section model (thesis Ch. 6: the
deviations of its zone's tension T - T_ref [N] and its web speed V - V_ref [m/s], or the speed
alone for the master), augmented with the integral of its tension error (of its speed error
for the master) so that a constant disturbance leaves no offset. The model is discretized
with the controllers' sample period (zero-order hold, ``scipy.linalg.expm``), the gain comes
from ``control.dlqr`` with states scaled by 1 % of the tension reference, 1 % of the line
speed and the integral over 1 s of those, the torque by 10 % of the limit (Bryson's rule).
The command is the equilibrium command plus the LQR's: u = u_eq - K [x, ∫e].

    python examples/user_lqr.py
"""

from __future__ import annotations

import control
import matplotlib.pyplot as plt
import numpy as np
from scipy.linalg import expm

import webline
from webline.control.sections import section_models
from webline.sim.user_control import ControllerContext


class IntegralLQR:
    """Per drive: u = u_eq - K [x, ∫e] (module docstring)."""

    def reset(self, context: ControllerContext) -> None:
        self.dt = context.sample_period
        self.drives = context.drives
        models = {m.node: m for m in section_models(context.line, context.operating_point)}
        op = context.operating_point
        self.gains, self.integral = [], [0.0] * len(context.drives)
        self.torques = np.zeros(len(context.drives))
        for drive in context.drives:
            model = models[drive.node]
            n = model.a.shape[0]
            # augmented continuous model: the integral of the first state (T, or V)
            a = np.zeros((n + 1, n + 1))
            a[:n, :n], a[n, 0] = model.a, 1.0
            b = np.zeros((n + 1, 1))
            b[:n, 0] = np.ravel(model.b)
            block = np.zeros((n + 2, n + 2))  # zero-order hold: expm of [[A, B], [0, 0]] dt
            block[:n + 1, :n + 1], block[:n + 1, n + 1:] = a * self.dt, b * self.dt
            phi = expm(block)
            ad, bd = phi[:n + 1, :n + 1], phi[:n + 1, n + 1:]
            tension = float(np.max(op.tension)) * 0.01
            speed = max(op.line_speed * 0.01, 0.01)
            scales = ([tension, speed] if n == 2 else [speed]) + [tension if n == 2 else speed]
            q = np.diag(1.0 / np.square(scales))
            r = np.array([[1.0 / (0.1 * drive.torque_limit) ** 2]])
            k, _, _ = control.dlqr(ad, bd, q, r)
            self.gains.append(np.asarray(k).ravel())

    def __call__(self, t: float, measurements: np.ndarray,
                 references: np.ndarray) -> np.ndarray:
        for k, drive in enumerate(self.drives):
            speed, tension = measurements[4 * k], measurements[4 * k + 1]
            x_v = speed - references[2 * k]
            if drive.role == "tension":
                x_t = tension - references[2 * k + 1]
                state = (x_t, x_v, self.integral[k])
                self.integral[k] += x_t * self.dt
            else:
                state = (x_v, self.integral[k])
                self.integral[k] += x_v * self.dt
            torque = drive.equilibrium_command - float(np.dot(self.gains[k], state))
            self.torques[k] = min(max(torque, -drive.torque_limit), drive.torque_limit)
        return self.torques


def main() -> None:
    line = webline.load_line("hswl")
    builtin = webline.simulate(line, scenario="speed-change")
    lqr = webline.simulate(line, scenario="speed-change", controller=IntegralLQR(),
                           raise_on_failure=False)
    _, ax = plt.subplots(figsize=(8, 3.5), layout="constrained")
    for name, result in (("built-in PI", builtin), ("integral LQR", lqr)):
        error = result.tension - result.tension[0]
        print(f"{name:13s} verdict {result.status:8s} largest tension deviation "
              f"{float(np.max(np.abs(error))):.3g} N")
        result.signals.tension.sel(span="span2").plot(ax=ax, label=name, lw=1.0)
    ax.set_title("hswl speed change: tension of span2")
    ax.legend()
    ax.grid(alpha=0.3)
    plt.show()


if __name__ == "__main__":
    main()
