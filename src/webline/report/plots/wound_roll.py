"""The report's wound-roll figure (docs/wound-roll.md): pressure and hoop stress against
radius, with the limits and the transient bands, and the roll's cross-section coloured by its
interlayer pressure."""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure

from webline.report.plots.mpl_text import literal
from webline.sim.results.wound_roll import WoundRoll

#: rings drawn in the cross-section (layers are averaged into them)
RINGS = 400


def wound_roll_caption(roll: WoundRoll) -> str:
    s = roll.stress
    return (
        f"The roll on {roll.where} at the end of the run: interlayer pressure and hoop "
        f"stress against radius ({len(s.radius)} layers, core pressure "
        f"{s.core_pressure / 1e6:.3g} MPa; bands from the run shaded), and its "
        "cross-section coloured by pressure."
        + (
            f" Dash-dotted: the pressure when the roll's surface passed "
            f"{', '.join(f'{1e3 * x.radius:.4g}' for x in roll.snapshots)} mm."
            if roll.snapshots
            else ""
        )
    )


def wound_roll_figure(roll: WoundRoll) -> Figure:
    """Left: pressure and hoop stress [MPa] against radius [mm], the steady roll's pressure
    dashed, the pressure at each snapshot (``at_radii``) dash-dotted, the limits dotted, the
    layers the run wound and its bands shaded. Right: the roll's cross-section coloured by
    pressure."""
    s, spec = roll.stress, roll.spec
    fig = Figure(figsize=(11.0, 4.6))
    grid = fig.add_gridspec(
        1, 2, width_ratios=(1.7, 1.0), left=0.07, right=0.9, bottom=0.12, top=0.9, wspace=0.25
    )
    ax = fig.add_subplot(grid[0, 0])
    r_mm = 1e3 * s.radius
    ax.plot(r_mm, s.pressure / 1e6, color="C0", lw=1.3, label="pressure")
    ax.plot(
        r_mm,
        roll.steady.pressure / 1e6,
        color="C0",
        lw=0.9,
        ls="--",
        label="pressure, steady tension",
    )
    ax.plot(r_mm, s.hoop / 1e6, color="C3", lw=1.0, label="hoop stress")
    for k, snap in enumerate(roll.snapshots):  # the roll as it was at chosen radii
        when = "" if np.isnan(snap.time) else f", t = {snap.time:.4g} s"
        ax.plot(
            1e3 * snap.stress.radius,
            snap.stress.pressure / 1e6,
            color=f"C{4 + k % 6}",
            lw=0.9,
            ls="-.",
            label=f"pressure when r = {1e3 * snap.radius:.4g} mm{when}",
        )
    ax.axhline(spec.min_hoop / 1e6, color="C3", lw=0.8, ls=":", label="hoop limit")
    if spec.max_pressure is not None:
        ax.axhline(spec.max_pressure / 1e6, color="C0", lw=0.8, ls=":", label="pressure limit")
    run = roll.layers.in_run
    if run.any():
        ax.axvspan(
            r_mm[run][0], r_mm[run][-1], color="0.85", alpha=0.5, lw=0, label="wound in the run"
        )
    for f in roll.findings():
        if f.kind == "roll_band":
            span = np.asarray(f.details["radius_m"], dtype=float)
            ax.axvspan(1e3 * span[0], 1e3 * span[1], color="C1", alpha=0.35, lw=0)
    ax.axhline(0.0, color="k", lw=0.5)
    ax.set_xlabel("radius [mm]")
    ax.set_ylabel("stress [MPa]")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=7, loc="best")
    ax.set_title(literal(roll.where), fontsize=9)
    polar = fig.add_subplot(grid[0, 1], projection="polar")
    step = max(1, len(s.radius) // RINGS)
    n = len(s.radius) // step
    rings = s.pressure[: n * step].reshape(n, step).mean(axis=1) / 1e6
    edges = np.append(s.radius[: n * step : step], s.outer_radius) * 1e3
    theta = np.linspace(0.0, 2.0 * np.pi, 73)
    mesh = polar.pcolormesh(
        theta, edges, np.tile(rings[:, None], (1, 72)), cmap="viridis", shading="flat"
    )
    polar.set_ylim(0.0, edges[-1])
    polar.set_xticks([])
    polar.set_yticks([edges[0], edges[-1]])
    polar.set_yticklabels([f"{edges[0]:.0f} mm", f"{edges[-1]:.0f} mm"], fontsize=7)
    polar.grid(False)
    fig.colorbar(mesh, ax=polar, fraction=0.05, pad=0.08, label="pressure [MPa]")
    return fig
