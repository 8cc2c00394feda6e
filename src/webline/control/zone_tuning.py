"""The stiffness a zone's tension loop works against, and the speed loops' stiffness against
the web (docs/winder.md, Z1-Z3).

A zone's tension PI trims the web speed of its drive, so its plant is the web stored in the
zone: an extra length δu of unstrained web changes the tension by δT = -K δu. Without a
dancer K = EA / L_zone (the spans in series). A dancer on a spring k (its load constant)
whose strands lengthen the spans by g = g_in + g_out per metre of travel (2 for two parallel
strands; docs/winder.md D0) lets its carriage move by δy = -g δT / k and stores g δy of web,
so the zone's compliance is

    C = δu / (-δT) = L_zone / EA + Σ_dancers g_j² / k_j                               (Z1)

(the dancer's spring, seen through its strands as k/g², in series with the spans); an
air-loaded dancer (k = 0) makes C infinite: its load alone sets the tension. The tension loop
designed for K = 1/C closes at the asked bandwidth ω_t and damping ζ:
kp = 2 ζ ω_t C, ki = ω_t² C (``control.pi.tune`` with L/EA replaced by C). A loop on the
position y_p of a dancer p (position control) sees δy_p = G δu with

    G = 1 / (g_p + k_p C_p / g_p),   C_p = C without dancer p's own term              (Z2)

(air-loaded: G = 1/g_p), so kp = 2 ζ ω_t / G, ki = ω_t² / G [(m/s)/m, (m/s)/(m·s)].

A loadcell in a zone with a dancer feels the carriage's damper c too: to first order in s
the zone is a spring K_e = 1/C with a damper c_e = K_e² Σ g_j² c_j / k_j² in parallel, and the
plant from trim to tension is -(K_e + c_e s)/s. With the PI, the closed loop is
(1 + c_e kp) s² + (K_e kp + c_e ki) s + K_e ki; matching s² + 2ζω s + ω² gives, with
ρ = c_e ω / K_e,

    kp = (ω / K_e) (2ζ - ρ) / (1 - 2ζρ + ρ²),    ki = ω² (1 + c_e kp) / K_e         (Z4)

(ρ = 0: the plain design; 2ζ < ρ: kp = 0, and ζ = ρ/2 > the asked). Above the dancer's own
mode the carriage stands still and the loadcell sees the spans' full stiffness EA/L: the loop
gain there is kp EA/L times the speed loop's response, so kp is kept within ``KP_SPANS`` times
the spans' own design 2 ζ ω_t L/EA (which the speed loop and the sampling tolerate), ki then
keeping ω_t (the damping is what results). A
dancer as tension sensor reads its spring's force only (c_e = 0).

A driven roller's speed PI (u = kp e + ki ∫e on its surface speed, ratio n, radius r) holds
its surface like a spring of k_r = n ki / r = ω_s² J / r² [N/m] (with damper n kp / r): a
tension step ΔT on one side moves it by ΔT / (k_r + K_other) and so changes the span on the
other side (stiffness K_other = EA / L) by

    ΔT_other / ΔT = K_other / (k_r + K_other)                                         (Z3)

until the tension loops take it back: a speed loop not much stiffer than the spans beside it
lets tension leak through the roller.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from webline.line import Line
from webline.spec.schema import CascadedPISpec, DancerSpec, DrivenSpec

#: largest kp of a loadcell loop beside a dancer over the spans' own design (Z4)
KP_SPANS = 6.0
#: a speed loop leaking more than this share of a tension step into the span beside it (Z3)
#: is reported: k_r < 3 K_span, i.e. the roller yields more than a quarter of the step
LEAK_WARNING = 0.25


def zone_dancers(line: Line, z: int) -> list[int]:
    """Nodes of the dancers inside zone ``z``."""
    zone = line.zones[z]
    return [i for i in range(zone.first + 1, zone.last)
            if isinstance(line.spec.rollers[i], DancerSpec)]


def zone_compliance(line: Line, z: int, without: int | None = None) -> float:
    """C [m/N] of zone ``z`` (Z1): the spans' L/EA plus g²/k of each dancer in it (inf for
    an air-loaded one), leaving out the dancer on node ``without``."""
    length = sum(line.spec.spans[k].length for k in line.zones[z].spans)
    compliance = length / line.ea
    for i in zone_dancers(line, z):
        if i == without:
            continue
        dancer = line.spec.rollers[i].dancer  # type: ignore[union-attr]
        k = dancer.stiffness
        compliance += math.inf if k == 0.0 else sum(dancer.gains) ** 2 / k
    return compliance


def position_gain(line: Line, z: int, i: int) -> float:
    """G [m/m] (Z2): carriage travel of the dancer on node ``i`` per metre of web stored in
    zone ``z``."""
    dancer = line.spec.rollers[i].dancer  # type: ignore[union-attr]
    k, g = dancer.stiffness, sum(dancer.gains)
    other = zone_compliance(line, z, without=i)
    return 1.0 / (g + (0.0 if k == 0.0 else k * other / g))


def loop_plant_gain(line: Line, z: int) -> tuple[str, float]:
    """(what the zone's tension loop measures, its plant gain per metre of web stored):
    ``"dancer position"`` G [m/m] for a dancer in position control, else K = 1/C [N/m] of
    a ``"dancer tension"`` sensor or the ``"loadcell"``."""
    for i in zone_dancers(line, z):  # the first dancer in use is the one the loop reads
        use = line.spec.rollers[i].dancer.use  # type: ignore[union-attr]
        if use == "position":
            return "dancer position", position_gain(line, z, i)
        if use == "tension":
            return "dancer tension", 1.0 / zone_compliance(line, z)
    return "loadcell", 1.0 / zone_compliance(line, z)


def zone_damper(line: Line, z: int) -> float:
    """c_e [N·s/m] (Z4): the dampers of the sprung dancers of zone ``z`` as the loadcell
    feels them, to first order in s (0 where a dancer is air-loaded: no static stiffness)."""
    stiffness = 1.0 / zone_compliance(line, z)
    total = 0.0
    for i in zone_dancers(line, z):
        c = line.spec.rollers[i].dancer  # type: ignore[union-attr]
        if c.stiffness > 0.0:
            total += sum(c.gains) ** 2 * c.damping / c.stiffness**2
    return stiffness**2 * total


def tension_gains(stiffness: float, damper: float, bandwidth: float, damping: float,
                  kp_max: float = math.inf) -> tuple[float, float]:
    """(kp [(m/s)/N], ki [(m/s)/(N·s)]) of a tension PI on the plant -(K + c s)/s, K =
    ``stiffness`` [N/m], c = ``damper`` [N·s/m], placing its pair at ``bandwidth`` [rad/s]
    with ``damping`` (Z4); kp kept within [0, ``kp_max``], ki then keeping the bandwidth."""
    rho = damper * bandwidth / stiffness
    denominator = 1.0 - 2.0 * damping * rho + rho * rho
    kp = (bandwidth / stiffness * (2.0 * damping - rho) / denominator if denominator > 0.0
          else math.inf)
    kp = min(max(kp, 0.0), kp_max)
    return kp, bandwidth**2 * (1.0 + damper * kp) / stiffness


def nominal_plant_gain(line: Line, z: int) -> float:
    """EA / L_zone [N/m]: the plant gain ``control.pi.tune`` designs the tension loop for."""
    return line.ea / sum(line.spec.spans[k].length for k in line.zones[z].spans)


@dataclass(frozen=True)
class SpeedLoopLeak:
    """A driven roller whose speed loop is soft against a span beside it (Z3)."""

    roller: str
    stiffness: float  #: k_r = n ki / r [N/m]
    span: str
    span_stiffness: float  #: EA / L [N/m]

    @property
    def leak(self) -> float:
        """Share of a tension step on the other side that reaches ``span`` (Z3)."""
        return self.span_stiffness / (self.stiffness + self.span_stiffness)

    def message(self) -> str:
        return (f"rollers.{self.roller}.controller.speed_bandwidth: the speed loop holds the "
                f"web like a spring of {self.stiffness:.3g} N/m, not much stiffer than span "
                f"{self.span!r} ({self.span_stiffness:.3g} N/m): {self.leak:.0%} of a tension "
                f"step on the other side leaks into it (raise the speed bandwidth)")


def speed_loop_leaks(line: Line, speed_ki: dict[int, float]) -> list[SpeedLoopLeak]:
    """Driven rollers (not the rolls) whose speed loop, of integral gain ``speed_ki[i]``
    [N·m/m] on node i, leaks more than ``LEAK_WARNING`` of a tension step into the stiffer
    (shorter) of the two spans beside it (Z3), one per roller."""
    out = []
    for i, ki in speed_ki.items():
        roller = line.spec.rollers[i]
        if not isinstance(roller, DrivenSpec) or not isinstance(roller.controller,
                                                                CascadedPISpec):
            continue
        stiffness = roller.drive.ratio * ki / roller.radius
        k = min((i - 1, i), key=lambda k: line.spec.spans[k].length)  # the stiffer span
        found = SpeedLoopLeak(roller.name, stiffness, line.span_name(k),
                              line.ea / line.spec.spans[k].length)
        if found.leak > LEAK_WARNING:
            out.append(found)
    return out

