"""Wound-on tension: the hoop stress each layer carries as it joins the roll (docs/wound-roll.md).

Without a nip the outermost layer is wound at the web's stress, ``σ_w = T / (w h)`` (tension
``T`` [N] over width ``w`` [m] and thickness ``h`` [m]). A lay-on (rider) nip pressing the
roll with ``N`` [N/m of width] adds the friction it can transmit into the layer entering the
nip: ``σ_w = T/(w h) + μ N / h`` (Good, Wu & Fikes 1994, J. Appl. Mech. 61(1):182-185, the
"nip-induced tension" ``NIT = μ N`` per width, with ``μ`` the layer-to-layer friction
coefficient; their measurements on newsprint and film put the coefficient within some 20 % of
μ, the value used here).

A run gives the roll's radius and the entering span's tension in time; each layer of the roll
takes the tension at the instant its radius was reached. The layers under the run's first
radius and above its last are given steady values by the caller (``fill_below``,
``fill_above``): a run covers seconds of a roll that takes an hour to wind.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np


def wound_on_stress(
    tension: np.ndarray,
    width: float,
    thickness: float,
    nip_load: float = 0.0,
    nip_friction: float = 0.0,
) -> np.ndarray:
    """Wound-on stress [Pa] of web under ``tension`` [N] (width ``width`` [m], thickness
    ``thickness`` [m]), plus a lay-on nip's ``nip_friction`` μ [-] × ``nip_load`` [N/m] over
    the thickness (Good, Wu & Fikes 1994)."""
    return (np.asarray(tension, dtype=float) / width + nip_friction * nip_load) / thickness


@dataclass(frozen=True)
class WoundLayers:
    """The layers of a roll, core outwards: ``radius`` [m] (n,) the radius on which each
    layer was laid; ``time`` [s] (n,) when, NaN for a layer laid outside the run;
    ``tension`` [N] (n,) the web tension it was wound with; ``stress`` [Pa] (n,) its wound-on
    stress (``wound_on_stress``)."""

    radius: np.ndarray
    time: np.ndarray
    tension: np.ndarray
    stress: np.ndarray

    @property
    def in_run(self) -> np.ndarray:
        """Mask of the layers the run wound."""
        return ~np.isnan(self.time)


def layers_from_run(
    time: np.ndarray,
    radius: np.ndarray,
    tension: np.ndarray,
    *,
    core_radius: float,
    outer_radius: float,
    thickness: float,
    width: float,
    fill: Callable[[np.ndarray], np.ndarray],
    nip_load: float = 0.0,
    nip_friction: float = 0.0,
) -> WoundLayers:
    """Layers of ``thickness`` [m] from ``core_radius`` to ``outer_radius`` [m] of a roll whose
    radius [m] and entering tension [N] a run recorded at ``time`` [s].

    A layer whose radius the run's roll passed takes the tension at the first instant the
    radius reached it (linear interpolation between records; a radius that falls back, as an
    unwinding roll would, is held at its largest value so far). Every other layer takes
    ``fill(radius)`` [N] (the steady tension the winder would have set there: the set tension
    times its taper). ``nip_load`` [N/m], ``nip_friction`` [-]: a lay-on nip (see module).
    """
    if not 0.0 < core_radius < outer_radius:
        raise ValueError(
            f"need 0 < core radius < outer radius, got {core_radius}, {outer_radius} m"
        )
    n = max(1, round((outer_radius - core_radius) / thickness))
    r = core_radius + thickness * np.arange(n)
    grown = np.maximum.accumulate(np.asarray(radius, dtype=float))
    t_layer = np.full(n, np.nan)
    ten = np.asarray(fill(r), dtype=float).copy()
    if grown.size >= 2 and grown[-1] > grown[0]:
        inside = (r >= grown[0]) & (r <= grown[-1])
        # first instant of each radius: interpolate on the strictly rising records
        rising = np.concatenate(([True], np.diff(grown) > 0.0))
        t_layer[inside] = np.interp(r[inside], grown[rising], np.asarray(time)[rising])
        ten[inside] = np.interp(t_layer[inside], time, tension)
    stress = wound_on_stress(ten, width, thickness, nip_load, nip_friction)
    return WoundLayers(radius=r, time=t_layer, tension=ten, stress=stress)
