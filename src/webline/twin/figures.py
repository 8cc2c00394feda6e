"""Figures of a replay and a fit: measured against simulated traces, and residuals."""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from webline.twin.signals import si_unit

if TYPE_CHECKING:
    from matplotlib.figure import Figure

#: panels per figure at most (the rest are left to the metrics table)
MAX_PANELS = 12


#: the order of signals in figures: what a fit learns most from first
ORDER = ("tension", "torque", "speed", "omega", "motor_speed", "surface_speed", "radius")


def shown(names: Sequence[str]) -> list[str]:
    """The signals a figure draws: at most ``MAX_PANELS``, tensions and torques first."""
    rank = {kind: i for i, kind in enumerate(ORDER)}
    ordered = sorted(names, key=lambda n: rank.get(n.partition("[")[0], len(ORDER)))
    return ordered[:MAX_PANELS]


def _panels(n: int) -> tuple[Figure, list[object]]:
    from matplotlib.figure import Figure

    n = max(1, min(n, MAX_PANELS))
    fig = Figure(figsize=(9, 1.9 * n + 0.6), layout="constrained")
    axes = fig.subplots(n, 1, sharex=True, squeeze=False)[:, 0]
    return fig, list(axes)


def overlay_figure(time: np.ndarray, measured: dict[str, np.ndarray],
                   simulated: dict[str, np.ndarray], names: Sequence[str], title: str,
                   before: dict[str, np.ndarray] | None = None) -> Figure:
    """One panel per signal (``shown``: at most ``MAX_PANELS``): measured (grey), simulated
    (blue) and, if given, the simulation ``before`` a fit (dashed) against time [s]."""
    names = shown(names)
    fig, axes = _panels(len(names))
    for ax, name in zip(axes, names, strict=False):
        ax.plot(time, measured[name], color="0.6", lw=0.8, label="measured")  # type: ignore[attr-defined]
        if before is not None:
            ax.plot(time, before[name], color="tab:orange", lw=1.0, ls="--",  # type: ignore[attr-defined]
                    label="before the fit")
        ax.plot(time, simulated[name], color="tab:blue", lw=1.2, label="simulated")  # type: ignore[attr-defined]
        ax.set_ylabel(f"{name}\n[{si_unit(name)}]", fontsize=8)  # type: ignore[attr-defined]
        ax.grid(alpha=0.3)  # type: ignore[attr-defined]
    axes[0].legend(loc="best", fontsize=8)  # type: ignore[attr-defined]
    axes[-1].set_xlabel("time [s]")  # type: ignore[attr-defined]
    fig.suptitle(title)
    return fig


def residual_figure(time: np.ndarray, residuals: dict[str, np.ndarray],
                    noise: dict[str, float], title: str) -> Figure:
    """One panel per signal: simulated - measured [SI] with the ±2σ band of the noise level
    the fit weighted it by."""
    names = shown(list(residuals))
    fig, axes = _panels(len(names))
    for ax, name in zip(axes, names, strict=False):
        ax.plot(time, residuals[name], color="tab:red", lw=0.6)  # type: ignore[attr-defined]
        sigma = noise.get(name, np.nan)
        if np.isfinite(sigma):
            ax.axhspan(-2 * sigma, 2 * sigma, color="0.85", zorder=0,  # type: ignore[attr-defined]
                       label="±2σ noise")
        ax.axhline(0.0, color="0.3", lw=0.6)  # type: ignore[attr-defined]
        ax.set_ylabel(f"{name}\n[{si_unit(name)}]", fontsize=8)  # type: ignore[attr-defined]
    axes[0].legend(loc="upper right", fontsize=8)  # type: ignore[attr-defined]
    axes[-1].set_xlabel("time [s]")  # type: ignore[attr-defined]
    fig.suptitle(title)
    return fig
