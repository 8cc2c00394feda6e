"""Modes of a linear model: natural frequency, damping ratio and the state each one lives in.

For an eigenvalue λ [1/s] of A, the natural frequency is ωn = |λ| [rad/s] (fn = ωn / 2π [Hz]),
the damped frequency ωd = |Im λ| [rad/s] and the damping ratio ζ = -Re λ / |λ| (1 for a
stable real pole, negative for an unstable mode). A complex pair is one mode. The dominant
state is the one with the largest participation factor |v_i w_i| (right and left eigenvectors).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from webline.line import Line
from webline.model.lines import load_line
from webline.sim.linear.linearize import LinearModel

if TYPE_CHECKING:
    import control

    from webline.model.web_graph import BranchedLine


@dataclass(frozen=True)
class Mode:
    """One mode (a real pole or a complex-conjugate pair) of a linear model."""

    eigenvalue: complex  #: [1/s], the one with Im >= 0 for a pair
    dominant: str  #: name of the state with the largest participation factor

    @property
    def natural_frequency(self) -> float:
        """ωn = |λ| [rad/s]."""
        return abs(self.eigenvalue)

    @property
    def frequency_hz(self) -> float:
        """fn = ωn / 2π [Hz]."""
        return self.natural_frequency / (2.0 * math.pi)

    @property
    def damped_frequency(self) -> float:
        """ωd = |Im λ| [rad/s] (0 for a real pole)."""
        return abs(self.eigenvalue.imag)

    @property
    def damping(self) -> float:
        """ζ = -Re λ / |λ| (dimensionless; 1 for a stable real pole, NaN at λ = 0)."""
        return -self.eigenvalue.real / abs(self.eigenvalue) if self.eigenvalue else math.nan

    @property
    def oscillatory(self) -> bool:
        return self.damped_frequency > 0.0

    def as_dict(self) -> dict[str, object]:
        """Plain data (for JSON): eigenvalue, ωn [rad/s], fn [Hz], ωd [rad/s], ζ, dominant."""
        return {"eigenvalue_real": self.eigenvalue.real, "eigenvalue_imag": self.eigenvalue.imag,
                "natural_frequency_rad_s": self.natural_frequency,
                "natural_frequency_hz": self.frequency_hz,
                "damped_frequency_rad_s": self.damped_frequency,
                "damping_ratio": self.damping, "dominant_state": self.dominant}


def modes(system: control.StateSpace | LinearModel) -> list[Mode]:
    """The modes of ``system`` (a python-control ``StateSpace`` or webline's ``LinearModel``:
    its A matrix and state names), slowest first."""
    if isinstance(system, LinearModel):
        return modes_of(np.asarray(system.a, dtype=float), list(system.states))
    return modes_of(np.asarray(system.A, dtype=float), list(system.state_labels))


def modes_of(a: np.ndarray, names: Sequence[str]) -> list[Mode]:
    """The modes of the matrix ``a`` [1/s] whose states are ``names``, slowest first."""
    if a.size == 0:
        return []
    values, right = np.linalg.eig(a)
    left = np.linalg.inv(right)  # rows are the left eigenvectors
    participation = np.abs(right * left.T)  # [state, mode]
    out = []
    for j, value in enumerate(values):
        if value.imag < 0.0:
            continue  # a real matrix: the conjugate of a pair counted with Im > 0
        out.append(Mode(complex(value), names[int(np.argmax(participation[:, j]))]))
    return sorted(out, key=lambda m: (m.natural_frequency, m.eigenvalue.imag))


def closed_loop_modes(line: Line | BranchedLine | str, t: float = 0.0) -> list[Mode]:
    """Modes of ``line`` with its controllers, linearized at time ``t`` [s] (the plan's cached
    closed-loop model: no python-control needed); a branched line's from
    ``sim.branches.linear`` (docs/branching.md, "Linear models")."""
    from webline.sim.core.plan import compile_plan
    from webline.sim.linear.linearize import plan_linear_model
    loaded = load_line(line)
    if loaded.branched:
        from webline.sim.branches.linear import linear_model

        return modes(linear_model(loaded, t, loop="closed"))
    return modes(plan_linear_model(compile_plan(loaded), loop="closed", t=t))
