"""The wound roll a run leaves on its rewind (docs/wound-roll.md): each layer's wound-on
tension from the run, the roll's interlayer pressure and hoop stress at the end of winding,
and the roll's findings for the verdict (hoop below its limit, pressure or core pressure above
theirs, a band from a tension transient traced to its time in the run)."""

from __future__ import annotations

import math
from collections.abc import Callable
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
class Snapshot:
    """The roll as it was when its surface passed ``radius`` [m] (``roll_stress.at_radii``):
    its ``stress`` (the layers on by then, the last one reaching ``radius``) and ``time`` [s]
    that last layer was wound (NaN: outside the run)."""

    radius: float
    time: float
    stress: RollStress

    def summary(self) -> dict[str, object]:
        """Plain numbers for summary.json (SI)."""
        s = self.stress
        return {
            "radius_m": self.radius,
            "time_s": None if math.isnan(self.time) else self.time,
            "layers": len(s.radius),
            "core_pressure_Pa": s.core_pressure,
            "max_pressure_Pa": float(s.pressure.max()),
            "min_hoop_Pa": float(s.hoop.min()),
        }


@dataclass(frozen=True)
class WoundRoll:
    """The rewind ``where``'s roll at the end of a run: its ``layers`` (wound-on tension per
    layer, ``physics.wound_on``), its ``stress`` and, for comparison, ``steady``: the same
    roll wound at the steady set tension (times the taper) throughout; ``spec`` its table;
    ``snapshots`` the roll at the table's ``at_radii`` during winding, ``missed`` those of
    them [m] the finished roll never reached (no snapshot)."""

    where: str
    layers: WoundLayers
    stress: RollStress
    steady: RollStress
    spec: RollStressSpec
    snapshots: tuple[Snapshot, ...] = ()
    missed: tuple[float, ...] = ()

    def to_xarray(self) -> Any:
        """The roll per layer (dimension ``layer``, coordinate ``radius`` [m]): wound-on
        tension [N] and stress [Pa], the time each layer was wound [s] (NaN outside the run),
        pressure and hoop stress [Pa], and the steady roll's pressure [Pa]; with snapshots
        (dimension ``at_radius`` [m]) their ``at_time`` [s], ``at_pressure`` and ``at_hoop``
        [Pa] per layer (NaN above each snapshot's layers)."""
        import xarray as xr

        plain = self.group_variables()
        coords = {k: plain.pop(k) for k in ("layer", "radius", "at_radius") if k in plain}
        return xr.Dataset(
            plain,
            coords=coords,
            attrs={"rewind": self.where, "thickness_m": self.stress.thickness},
        )

    def group_variables(self) -> dict[str, tuple[tuple[str, ...], np.ndarray, dict[str, str]]]:
        """``to_xarray``'s variables and coordinates as plain arrays (the results file's
        ``wound_roll`` group): per layer, and per snapshot (``at_radius``) its time and the
        pressure and hoop stress of its layers (NaN above them)."""
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
        } | self._snapshot_variables()

    def _snapshot_variables(self) -> dict[str, tuple[tuple[str, ...], np.ndarray, dict[str, str]]]:
        """The snapshots as (at_radius, layer) arrays, NaN on the layers not yet wound."""
        if not self.snapshots:
            return {}
        n = len(self.stress.radius)
        pressure = np.full((len(self.snapshots), n), np.nan)
        hoop = np.full((len(self.snapshots), n), np.nan)
        for j, snap in enumerate(self.snapshots):
            pressure[j, : len(snap.stress.radius)] = snap.stress.pressure
            hoop[j, : len(snap.stress.radius)] = snap.stress.hoop
        two = ("at_radius", "layer")
        return {
            "at_radius": (("at_radius",), np.array([x.radius for x in self.snapshots]),
                          {"units": "m"}),
            "at_time": (("at_radius",), np.array([x.time for x in self.snapshots]),
                        {"units": "s"}),
            "at_pressure": (two, pressure, {"units": "Pa"}),
            "at_hoop": (two, hoop, {"units": "Pa"}),
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
            "snapshots": [x.summary() for x in self.snapshots],
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
                        # where the hoop departs most: the transient's own layers (a stiff
                        # web's band reaches below them, its pressure pressing the stack)
                        "peak_radius_m": float(s.radius[k]),
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
        for r in self.missed:
            out.append(
                Finding(
                    "warning",
                    "roll_snapshot",
                    self.where,
                    f"{self.where}: no snapshot at r = {1e3 * r:.4g} mm (roll_stress.at_radii): "
                    f"the finished roll ends at {1e3 * s.outer_radius:.4g} mm",
                    None,
                    {"radius_m": r, "outer_radius_m": s.outer_radius},
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

    # the roll when its surface passed each asked radius: once the layer m reaching it is on;
    # a radius less than a layer beyond the roll (its diameter rounded to whole layers) is
    # the finished roll's, one further is missed
    n = len(layers.radius)
    reach = [math.ceil((r - core_radius) / thickness - 1e-9) - 1 for r in spec.at_radii]
    kept = [(r, min(max(0, m), n - 1)) for r, m in zip(spec.at_radii, reach, strict=True)
            if m <= n]
    missed = tuple(r for r, m in zip(spec.at_radii, reach, strict=True) if m > n)

    def solve(wound_on: np.ndarray, during: tuple[int, ...] = ()) -> RollStress:
        return roll_stress(
            wound_on,
            core_radius,
            thickness,
            tangential_modulus=e_t,
            k1=k1,
            k2=k2,
            poisson=spec.poisson,
            core_stiffness=core,
            during=during,
        )

    stress = solve(layers.stress, tuple(m for _, m in kept))
    steady = solve(
        wound_on_stress(steady_tension(layers.radius), width, thickness, nip, spec.nip_friction)
    )
    snapshots = tuple(
        Snapshot(float(r), float(layers.time[m]), at)
        for (r, m), at in zip(kept, stress.during, strict=True)
    )
    return WoundRoll(name, layers, stress, steady, spec, snapshots, missed)


def run_wound_roll(result: Any) -> WoundRoll | None:
    """The wound roll of a single-path run's rewind (``Result``), or None without a
    ``roll_stress`` table (``recorded_roll``)."""
    line = result.line
    rewind = line.rewind
    spec = getattr(rewind, "roll_stress", None)
    if spec is None or len(result.time) < 2:
        return None
    web = line.spec.web
    last = line.n_spans - 1
    tension = result.tension[:, last]
    return recorded_roll(
        rewind.name,
        spec,
        time=result.time,
        radius=result.radius[:, -1],
        tension=tension,
        core_radius=rewind.core_radius,
        thickness=web.thickness,
        width=web.width,
        modulus=line.ea / (web.width * web.thickness),
        set_tension=_set_tension(line, last, float(result.time[-1]), float(tension[-1])),
        taper=rewind.taper,
        taper_acts=line.controlled_zone(line.n_nodes - 1) is not None,
    )


def recorded_roll(
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
    set_tension: float | Callable[[np.ndarray], np.ndarray],
    taper: Any,
    taper_acts: bool = True,
) -> WoundRoll:
    """The roll ``name`` a run wound, whatever the line (a chain's rewind, a branched line's
    rewind or lane on a shaft): its records ``time`` [s], roll ``radius`` [m] and entering
    ``tension`` [N]; the web's ``thickness``, ``width`` [m] and ``modulus`` [Pa] on it; the
    roll's ``core_radius`` [m]; ``set_tension`` [N] its zone's set tension at the end and
    ``taper`` its ``TaperSpec`` or None, which give the steady roll (``taper_acts`` False:
    no tension loop applies it, only its ``max_diameter`` counts); ``set_tension`` may be a
    function of the radius [m] instead, the steady tension itself (a differential shaft's
    slip torque over the radius).

    After a flying splice of the rewind the roll is the finished one it passed on (the last
    roll the splices completed, its diameter at its splice); else the roll on the shaft at
    the end, completed to the table's ``diameter`` (default the taper's ``max_diameter``)."""
    # a run that ran away (non-finite records) wound its roll up to its last finite record
    bad = np.flatnonzero(~(np.isfinite(radius) & np.isfinite(tension)))
    if bad.size:
        time, radius, tension = time[: bad[0]], radius[: bad[0]], tension[: bad[0]]
    # a splice puts a new core on the shaft: the radius falls by more than a few layers
    drops = np.flatnonzero(np.diff(radius) < -10.0 * thickness)
    core, finished = core_radius, None
    if drops.size:
        start = int(drops[-2]) + 1 if drops.size > 1 else 0
        stop = int(drops[-1]) + 1
        time, radius, tension = time[start:stop], radius[start:stop], tension[start:stop]
        finished = float(radius[-1])
        core = min(core, float(radius[0]))

    acting = taper if taper_acts else None

    def steady(r: np.ndarray) -> np.ndarray:
        if callable(set_tension):
            return set_tension(r)
        return set_tension * np.array([spec_factor(acting, core, x) for x in np.ravel(r)])

    if finished is not None:
        spec = spec.model_copy(update={"diameter": 2.0 * finished})
    elif spec.diameter is None and taper is not None and taper.max_diameter:
        spec = spec.model_copy(update={"diameter": taper.max_diameter})
    return wound_roll(
        name,
        spec,
        time=time,
        radius=radius,
        tension=tension,
        core_radius=core,
        thickness=thickness,
        width=width,
        modulus=modulus,
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
