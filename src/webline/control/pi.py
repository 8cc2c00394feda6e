"""Industrial decentralized cascaded PI (thesis Fig. 4.3): gains and their tuning.

Tuning by pole placement, each loop designed on its dominant dynamics:

* speed loop of node i, rigid roller driven through ratio n: (J/(n r)) dv/dt = u, so with
  u = kp e + ki ∫e the loop is s² + (n r/J) kp s + (n r/J) ki. Matching
  s² + 2ζω_s s + ω_s² gives kp = 2ζ ω_s J/(n r), ki = ω_s² J/(n r)  [N·s, N];
* tension loop of a zone of total length L with an ideal speed loop: L dT/dt ≈ EA·trim, so
  with trim = kp_t e + ki_t ∫e: kp_t = 2ζ ω_t L/EA, ki_t = ω_t² L/EA  [(m/s)/N, (m/s)/(N·s)]
  (the stabilising v/L self-regulation of the span is ignored, which errs on the safe side).

With ``inertia_adaptive`` the speed gains follow J(t)/(n r(t)) of an unwinding or rewinding
roll, as industrial winder drives adapt their speed loop to the roll.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class PIGains:
    """Cascaded-PI gains of one drive (SI, see module docstring)."""

    speed_kp: float
    speed_ki: float
    tension_kp: float
    tension_ki: float


def tune(inertia: float, ratio: float, radius: float, zone_length: float, ea: float,
         speed_bandwidth: float, tension_bandwidth: float, damping: float) -> PIGains:
    """Pole-placement gains for a drive of ``inertia`` [kg·m²] at the roller shaft, gear
    ``ratio`` [-], roller ``radius`` [m], regulating a zone of ``zone_length`` [m] of a web of
    stiffness ``ea`` [N]; bandwidths [rad/s], ``damping`` ratio [-]."""
    plant = inertia / (ratio * radius)
    return PIGains(
        speed_kp=2.0 * damping * speed_bandwidth * plant,
        speed_ki=speed_bandwidth**2 * plant,
        tension_kp=2.0 * damping * tension_bandwidth * zone_length / ea,
        tension_ki=tension_bandwidth**2 * zone_length / ea,
    )
