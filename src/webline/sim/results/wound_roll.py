"""The wound roll a run leaves on its rewind (docs/wound-roll.md): each layer's wound-on
tension from the run, the roll's interlayer pressure and hoop stress at the end of winding,
and the roll's findings for the verdict (hoop below its limit, pressure or core pressure above
theirs, a band from a tension transient traced to its time in the run)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from webline.physics.roll_stress import RollStress, core_modulus, roll_stress
from webline.physics.taper import spec_factor
from webline.physics.wound_on import WoundLayers, layers_from_run, wound_on_stress
from webline.spec.roll_stress import RollStressSpec
from webline.verdict import Finding

#: bands named in full in a finding's details (the rest are counted)
MAX_BANDS = 5


@dataclass(frozen=True)
class Band:
    """Consecutive layers ``first`` .. ``last`` (indices, core outwards)."""

    first: int
    last: int


def bands(mask: np.ndarray) -> list[Band]:
    """The runs of consecutive True entries of ``mask``."""
    m = np.concatenate(([False], np.asarray(mask, dtype=bool), [False]))
    edges = np.flatnonzero(np.diff(m.astype(np.int8)))
    return [Band(int(a), int(b) - 1) for a, b in zip(edges[::2], edges[1::2], strict=True)]


@dataclass(frozen=True)
class WoundRoll:
    """The rewind ``where``'s roll at the end of a run: its ``layers`` (wound-on tension per
    layer, ``physics.wound_on``), its ``stress`` and, for comparison, ``steady``: the same
    roll wound at the steady set tension (times the taper) throughout; ``spec`` its table."""

    where: str
    layers: WoundLayers
    stress: RollStress
    steady: RollStress
    spec: RollStressSpec

    def to_xarray(self) -> Any:
        """The roll per layer (dimension ``layer``, coordinate ``radius`` [m]): wound-on
        tension [N] and stress [Pa], the time each layer was wound [s] (NaN outside the run),
        pressure and hoop stress [Pa], and the steady roll's pressure [Pa]."""
        import xarray as xr

        lay, s = self.layers, self.stress
        coords = {"layer": np.arange(len(lay.radius)), "radius": ("layer", lay.radius)}
        return xr.Dataset(
            {
                "wound_on_tension": ("layer", lay.tension, {"units": "N"}),
                "wound_on_stress": ("layer", lay.stress, {"units": "Pa"}),
                "wound_time": ("layer", lay.time, {"units": "s"}),
                "pressure": ("layer", s.pressure, {"units": "Pa"}),
                "hoop": ("layer", s.hoop, {"units": "Pa"}),
                "steady_pressure": ("layer", self.steady.pressure, {"units": "Pa"}),
            },
            coords=coords,
            attrs={"rewind": self.where, "thickness_m": s.thickness},
        )

    def group_variables(self) -> dict[str, tuple[tuple[str, ...], np.ndarray, dict[str, str]]]:
        """``to_xarray``'s variables and coordinates as plain arrays (the results file's
        ``wound_roll`` group)."""
        lay, s = self.layers, self.stress
        one = ("layer",)
        return {
            "layer": (one, np.arange(len(lay.radius)), {}),
            "radius": (one, lay.radius, {"units": "m"}),
            "wound_on_tension": (one, lay.tension, {"units": "N"}),
            "wound_on_stress": (one, lay.stress, {"units": "Pa"}),
            "wound_time": (one, lay.time, {"units": "s"}),
            "pressure": (one, s.pressure, {"units": "Pa"}),
            "hoop": (one, s.hoop, {"units": "Pa"}),
            "steady_pressure": (one, self.steady.pressure, {"units": "Pa"}),
        }

    def summary(self) -> dict[str, object]:
        """Plain numbers for summary.json (SI, keys name their units)."""
        s = self.stress
        run = self.layers.in_run
        return {
            "rewind": self.where,
            "layers": len(s.radius),
            "layers_in_run": int(run.sum()),
            "core_radius_m": float(s.radius[0]),
            "outer_radius_m": s.outer_radius,
            "core_pressure_Pa": s.core_pressure,
            "max_pressure_Pa": float(s.pressure.max()),
            "min_hoop_Pa": float(s.hoop.min()),
            "max_hoop_Pa": float(s.hoop.max()),
            "wound_on_stress_Pa": [
                float(self.layers.stress.min()),
                float(self.layers.stress.max()),
            ],
        }

    def findings(self) -> list[Finding]:
        """The roll's findings (all ``warning``): hoop stress below ``min_hoop`` over a band
        (starring, telescoping), pressure above ``max_pressure`` (crushing, blocking), core
        pressure above ``core_rating``, and bands whose pressure departs from the steady
        roll's by more than ``band`` where the run wound them (a tension transient)."""
        spec, s, lay = self.spec, self.stress, self.layers
        out = []
        low = bands(s.hoop < spec.min_hoop)
        if low:
            worst = int(np.argmin(s.hoop))
            out.append(
                self._finding(
                    "roll_hoop",
                    low,
                    f"hoop stress below {spec.min_hoop / 1e6:.3g} MPa",
                    f"(lowest {s.hoop[worst] / 1e6:.3g} MPa at r = "
                    f"{1e3 * s.radius[worst]:.4g} mm): "
                    "starring / telescoping risk",
                    {"min_hoop_Pa": float(s.hoop[worst]), "limit_Pa": spec.min_hoop},
                )
            )
        if spec.max_pressure is not None:
            high = bands(s.pressure > spec.max_pressure)
            if high:
                worst = int(np.argmax(s.pressure))
                out.append(
                    self._finding(
                        "roll_pressure",
                        high,
                        f"interlayer pressure above {spec.max_pressure / 1e6:.3g} MPa",
                        f"(highest {s.pressure[worst] / 1e6:.3g} MPa at r = "
                        f"{1e3 * s.radius[worst]:.4g} mm): crushing / blocking risk",
                        {
                            "max_pressure_Pa": float(s.pressure[worst]),
                            "limit_Pa": spec.max_pressure,
                        },
                    )
                )
        if spec.core_rating is not None and s.core_pressure > spec.core_rating:
            out.append(
                Finding(
                    "warning",
                    "roll_core",
                    self.where,
                    f"{self.where}: the roll presses its core with "
                    f"{s.core_pressure / 1e6:.3g} MPa, "
                    f"above its rating {spec.core_rating / 1e6:.3g} MPa",
                    None,
                    {"core_pressure_Pa": s.core_pressure, "rating_Pa": spec.core_rating},
                )
            )
        # A transient band: where the hoop stress (the pressure's slope, d(rP)/dr = -σ_t)
        # departs from the steady roll's by more than `band` of the steady wound-on stress.
        # The pressure under a band rises too, but smoothly and far down: it is reported.
        scale = np.maximum(np.abs(self.steady.wound_on), 1e-12)
        departure = (s.hoop - self.steady.hoop) / scale
        lifted = (s.pressure - self.steady.pressure) / np.maximum(self.steady.pressure, 1e-12)
        for b in bands((np.abs(departure) > spec.band) & lay.in_run)[:MAX_BANDS]:
            sl = slice(b.first, b.last + 1)
            k = b.first + int(np.argmax(np.abs(departure[sl])))
            t0, t1 = float(np.nanmin(lay.time[sl])), float(np.nanmax(lay.time[sl]))
            kind = "hard" if departure[k] > 0 else "soft"
            r0, r1 = float(s.radius[b.first]), float(s.radius[b.last] + s.thickness)
            out.append(
                Finding(
                    "warning",
                    "roll_band",
                    self.where,
                    f"{self.where}: a {kind} band at r = {1e3 * r0:.4g}-{1e3 * r1:.4g} mm "
                    f"({b.last - b.first + 1} layers), hoop stress {100 * departure[k]:+.3g} % of "
                    f"the wound-on stress off the steady roll's (pressure under it "
                    f"{100 * lifted[b.first]:+.3g} %), wound at t = {t0:.4g}-{t1:.4g} s",
                    t0,
                    {
                        "radius_m": [r0, r1],
                        "time_s": [t0, t1],
                        "layers": b.last - b.first + 1,
                        "hoop_departure": float(departure[k]),
                        "pressure_departure": float(lifted[b.first]),
                        "wound_on_tension_N": [
                            float(lay.tension[sl].min()),
                            float(lay.tension[sl].max()),
                        ],
                    },
                )
            )
        return out

    def _finding(
        self, kind: str, found: list[Band], what: str, tail: str, details: dict[str, object]
    ) -> Finding:
        s = self.stress
        widest = max(found, key=lambda b: b.last - b.first)
        r0, r1 = float(s.radius[widest.first]), float(s.radius[widest.last] + s.thickness)
        count = sum(b.last - b.first + 1 for b in found)
        where = (
            f"r = {1e3 * r0:.4g}-{1e3 * r1:.4g} mm"
            if len(found) == 1
            else f"{len(found)} bands, the widest r = {1e3 * r0:.4g}-{1e3 * r1:.4g} mm"
        )
        times = self.layers.time[widest.first : widest.last + 1]
        t = float(np.nanmin(times)) if np.isfinite(times).any() else None
        return Finding(
            "warning",
            kind,
            self.where,
            f"{self.where}: {what} over {count} layers, {where} {tail}",
            t,
            {**details, "layers": count, "bands": len(found), "radius_m": [r0, r1]},
        )


def wound_roll(
    name: str,
    spec: RollStressSpec,
    *,
    time: np.ndarray,
    radius: np.ndarray,
    tension: np.ndarray,
    core_radius: float,
    thickness: float,
    width: float,
    modulus: float,
    steady_tension: Any,
) -> WoundRoll:
    """The roll a rewind ``name`` wound: ``time`` [s], its ``radius`` [m] and the entering
    span's ``tension`` [N] as recorded; ``core_radius``, web ``thickness``, ``width`` [m] and
    ``modulus`` [Pa]; ``steady_tension(r)`` [N] the set tension (with taper) at radius ``r``
    [m], for the layers the run did not wind and for the steady roll."""
    outer = 0.5 * spec.diameter if spec.diameter is not None else float(np.max(radius))
    outer = max(outer, core_radius + thickness)
    nip = spec.nip_load / width if spec.nip_load is not None else 0.0
    layers = layers_from_run(
        time,
        radius,
        tension,
        core_radius=core_radius,
        outer_radius=outer,
        thickness=thickness,
        width=width,
        fill=steady_tension,
        nip_load=nip,
        nip_friction=spec.nip_friction,
    )
    if isinstance(spec.core, str):
        core = math.inf
    else:
        core = core_modulus(
            spec.core.modulus, spec.core.poisson, spec.core.inner_radius, core_radius
        )
    if spec.model == "pfeiffer":
        k1, k2 = float(spec.k1 or 0.0), float(spec.k2 or 0.0)
    else:
        k1, k2 = float(spec.radial_modulus or 0.0), 0.0
    e_t = spec.tangential_modulus or modulus

    def solve(wound_on: np.ndarray) -> RollStress:
        return roll_stress(
            wound_on,
            core_radius,
            thickness,
            tangential_modulus=e_t,
            k1=k1,
            k2=k2,
            poisson=spec.poisson,
            core_stiffness=core,
        )

    stress = solve(layers.stress)
    steady = solve(
        wound_on_stress(steady_tension(layers.radius), width, thickness, nip, spec.nip_friction)
    )
    return WoundRoll(name, layers, stress, steady, spec)


def run_wound_roll(result: Any) -> WoundRoll | None:
    """The wound roll of a single-path run's rewind (``Result``), or None without a
    ``roll_stress`` table. After a flying splice of the rewind the roll is the finished one
    it passed on (the last roll the splices completed, its diameter at its splice); else the
    roll on the shaft at the end, completed to the table's ``diameter``."""
    line = result.line
    rewind = line.rewind
    spec = getattr(rewind, "roll_stress", None)
    if spec is None or len(result.time) < 2:
        return None
    web = line.spec.web
    last = line.n_spans - 1
    time, radius, tension = result.time, result.radius[:, -1], result.tension[:, last]
    base = _set_tension(line, last, float(time[-1]), float(tension[-1]))
    taper = rewind.taper if line.controlled_zone(line.n_nodes - 1) is not None else None
    # a splice puts a new core on the shaft: the radius falls by more than a few layers
    drops = np.flatnonzero(np.diff(radius) < -10.0 * web.thickness)
    core, finished = rewind.core_radius, None
    if drops.size:
        start = int(drops[-2]) + 1 if drops.size > 1 else 0
        stop = int(drops[-1]) + 1
        time, radius, tension = time[start:stop], radius[start:stop], tension[start:stop]
        finished = float(radius[-1])
        core = min(core, float(radius[0]))

    def steady(r: np.ndarray) -> np.ndarray:
        return base * np.array([spec_factor(taper, core, x) for x in np.ravel(r)])

    if finished is not None:
        spec = spec.model_copy(update={"diameter": 2.0 * finished})
    elif spec.diameter is None and rewind.taper is not None and rewind.taper.max_diameter:
        spec = spec.model_copy(update={"diameter": rewind.taper.max_diameter})
    return wound_roll(
        rewind.name,
        spec,
        time=time,
        radius=radius,
        tension=tension,
        core_radius=core,
        thickness=web.thickness,
        width=web.width,
        modulus=line.ea / (web.width * web.thickness),
        steady_tension=steady,
    )


def _set_tension(line: Any, span: int, at: float, fallback: float) -> float:
    """The set tension [N] of ``span``'s zone at time ``at`` (its loadcell's profile, before
    taper), or ``fallback`` where the zone has none."""
    from webline.profiles import breakpoints

    zone = line.zones[line.zone_of_span(span)]
    profile = line.spec.spans[zone.loadcell].tension
    if profile is None:
        return fallback
    times, values = breakpoints(profile)
    return float(np.interp(at, times, values))
