"""The closed-loop mode of each dancer carriage (docs/winder.md D2, "validate"): a carriage
with little damping beside a strong tension-to-torque path (a zone's tension loop, the
loadcell it loads) can be driven unstable by the torque lag; ``webline validate`` warns."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from webline.line import Line
from webline.model.lines import load_line
from webline.sim.linearize import linearize
from webline.spec.schema import DancerSpec

if TYPE_CHECKING:
    from webline.model.web_graph import BranchedLine


@dataclass(frozen=True)
class CarriageMode:
    """The closed-loop eigenvalue ``eigenvalue`` [1/s] in which the carriage of dancer
    ``dancer`` takes the largest part (participation factor ``share`` [-] of its position
    and velocity states, of 1 over all states)."""

    dancer: str
    eigenvalue: complex
    share: float

    @property
    def damping(self) -> float:
        """Damping ratio ζ = -Re λ / |λ| [-] (negative: the mode grows)."""
        return float(-self.eigenvalue.real / abs(self.eigenvalue))

    @property
    def frequency(self) -> float:
        """Natural frequency |λ| / 2π [Hz]."""
        return float(abs(self.eigenvalue) / (2.0 * np.pi))

    def message(self) -> str:
        return (f"dancer {self.dancer}: its carriage's closed-loop mode ({self.frequency:.3g} Hz, "
                f"{self.share:.0%} carriage) has damping ζ = {self.damping:.3g} < 0: it grows "
                "(the torque lag drives a carriage with little damping beside a strong "
                "tension loop); give the carriage damping or soften the zone's tension loop")


def carriage_modes(line: Line | BranchedLine | str) -> list[CarriageMode]:
    """Each dancer's closed-loop carriage mode at the line's operating point: the eigenvalue
    of the closed-loop linear model with the largest participation factor |v_k w_k| (right
    and left eigenvectors, unit-free) summed over the carriage's position and velocity, for
    any line (``webline.linearize``)."""
    line = load_line(line)
    names = [r.name for r in line.spec.rollers if isinstance(r, DancerSpec)]
    if not names:
        return []
    system = linearize(line)  # (any line: its closed loop with the same state names)
    values, right = np.linalg.eig(system.A)
    left = np.linalg.inv(right)  # rows: the left eigenvectors, w_k v_k = 1
    participation = np.abs(right * left.T)  # [state, mode]
    participation /= participation.sum(axis=0, keepdims=True)
    out = []
    for name in names:
        rows = [system.state_labels.index(f"{name}_{part}") for part in ("position", "velocity")]
        share = participation[rows].sum(axis=0)
        k = int(np.argmax(share))
        out.append(CarriageMode(name, complex(values[k]), float(share[k])))
    return out


def unstable_carriages(line: Line | BranchedLine | str) -> list[CarriageMode]:
    """The dancers whose carriage mode has damping below zero (``carriage_modes``)."""
    return [mode for mode in carriage_modes(line) if mode.eigenvalue.real > 0.0]
