"""The map of closed-loop modes across the roll (docs/winder.md, "Modes across the roll"):
the loops' modes and their least damping against the rewind's diameter."""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure

from webline.report.plots.frame import framed_figure
from webline.report.text.display import Display
from webline.sim.linear.roll_modes import RollModes


def roll_modes_caption(course: RollModes, display: Display) -> str:
    """The figure's caption: where the course runs, and the least damping along it."""
    damping = course.least_damping()
    worst = int(np.nanargmin(damping)) if np.isfinite(damping).any() else None
    text = (f"Closed-loop modes across the roll at {len(course.time)} points: the rewind from "
            f"{display.text(2 * course.rewind_radius[0], 'length')} to "
            f"{display.text(2 * course.rewind_radius[-1], 'length')}, the unwind from "
            f"{display.text(2 * course.unwind_radius[0], 'length')} to "
            f"{display.text(2 * course.unwind_radius[-1], 'length')}.")
    if worst is not None:
        text += (f" Least damped loop mode: ζ = {damping[worst]:.3g} with the rewind at "
                 f"{display.text(2 * course.rewind_radius[worst], 'length')} (threshold "
                 f"{course.threshold:g}).")
    return text


def roll_modes_figure(course: RollModes, display: Display) -> Figure:
    """Top: natural frequency [rad/s] of every oscillatory loop mode at each point, coloured
    by its damping; bottom: the least damping of a loop mode and the threshold; both against
    the rewind's diameter."""
    fig = framed_figure(8.0, 6.0, rows=2)
    top, bottom = fig.subplots(2, 1, sharex=True)
    diameter = display.array(2.0 * course.rewind_radius, "length")
    xs, ys, zs = [], [], []
    for x, values, flags in zip(diameter, course.eigenvalues, course.loop, strict=True):
        for v, flag in zip(values, flags, strict=True):
            if flag and v.imag > 0.0:
                xs.append(x)
                ys.append(abs(v))
                zs.append(-v.real / abs(v))
    points = top.scatter(xs, ys, c=zs, s=14, cmap="viridis", vmin=0.0, vmax=1.0)
    top.set_yscale("log")
    top.set_ylabel("ωn [rad/s]")
    top.set_title("oscillatory loop modes (colour: ζ)", fontsize=9)
    fig.colorbar(points, ax=top, pad=0.01, label="ζ")
    bottom.plot(diameter, course.least_damping(), "o-", ms=3, lw=1.0, color="C3",
                label="least damped loop mode")
    bottom.axhline(course.threshold, color="k", ls="--", lw=0.8, label="threshold")
    bottom.set_ylabel("ζ")
    bottom.set_xlabel(display.label("rewind diameter", "length"))
    bottom.set_ylim(bottom=0.0)
    for ax in (top, bottom):
        ax.grid(True, alpha=0.3)
    bottom.legend(fontsize=7, loc="best")
    return fig
