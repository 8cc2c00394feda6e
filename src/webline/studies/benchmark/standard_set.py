"""The standard set of ``webline benchmark``, version ``BENCHMARK_VERSION``: built-in lines x
scenarios x disturbances, each case a line, a scenario, values set by path (as ``--set`` and
``Line.replace`` take them) and the time from which its settling is measured; one case is a
Monte Carlo of uncertain parameters in webline's distribution language.

Any change to a case (a value, a duration, a case added or removed) changes ``set_hash`` and
must bump ``BENCHMARK_VERSION`` (docs/benchmark.md: published numbers name both).
"""

from __future__ import annotations

import hashlib
import json
from dataclasses import asdict, dataclass, field

#: the version of the standard set; bump it with any change to ``CASES``
BENCHMARK_VERSION = "1"

_NOISE = {"type": "measurement_noise", "tension": "0.05 lbf", "speed": "0.5 ft/min",
          "seed": 7}  # the hswl-controllers study's noise (thesis Sec. 6.2's signals)
_DRAG_RAMP = {"type": "roller_drag", "roller": "process",
              "torque": {"type": "ramp", "initial": "0 N*m", "final": "1 N*m",
                         "start": "2 s", "duration": "4 s"}}


@dataclass(frozen=True)
class Case:
    """One case: ``line`` (a built-in name) run for ``duration`` [s] under ``scenario`` (or
    none), then the values of ``set`` (path -> value, with units) changed; settling is
    measured from ``onset`` [s]. A Monte Carlo case (``samples`` > 0) runs ``samples``
    lines, each with the parameters of ``uncertain`` (path -> distribution) drawn from
    ``numpy.random.default_rng(seed)``. ``quick``: in the ``--quick`` subset."""

    name: str
    line: str
    what: str
    duration: float
    onset: float = 0.0
    scenario: str | None = None
    set: dict[str, object] = field(default_factory=dict)
    uncertain: dict[str, str] = field(default_factory=dict)
    samples: int = 0
    seed: int = 0
    quick: bool = False

    @property
    def monte_carlo(self) -> bool:
        return self.samples > 0


CASES: tuple[Case, ...] = (
    Case("hswl/tension-step", "hswl", "process-zone tension reference +25 % at 2 s",
         6.0, 2.0, scenario="tension-step", quick=True),
    Case("hswl/speed-change", "hswl", "line speed 200 -> 1000 ft/min over 5 s (from 2 s)",
         12.0, 2.0, scenario="speed-change", quick=True),
    Case("hswl/ripple-eccentric", "hswl", "wound-in tension ripple 1 lbf at 1 Hz and an "
         "eccentric idle roller (0.05 mm)", 10.0, scenario="disturbance"),
    Case("hswl/eccentric-roll", "hswl", "an out-of-round unwind roll (0.2 mm eccentricity)",
         8.0, set={"disturbances": [{"type": "eccentric_roller", "roller": "unwind",
                                     "eccentricity": "0.2 mm"}]}),
    Case("hswl/drift", "hswl", "parameter drift: the process roller's bearing drag rises "
         "0 -> 1 N·m over 2-6 s", 10.0, 2.0, set={"disturbances": [_DRAG_RAMP]}),
    Case("hswl/noise", "hswl", "measurement noise 0.05 lbf (tension), 0.5 ft/min (speed) at "
         "500 ft/min", 6.0, set={"disturbances": [_NOISE]}),
    Case("hswl/roll-change", "hswl", "200 -> 1000 ft/min, then until the unwind roll "
         "(from 3.6 in) runs nearly empty", 120.0, 6.0, scenario="roll-change"),
    Case("converter/startup", "converter", "from rest to 300 m/min in 20 s", 30.0, 21.0,
         scenario="startup"),
    Case("converter/flying-splice", "converter", "flying splices of both rolls at 300 m/min "
         "(unwind at 4 s, rewind at 12 s)", 20.0, 4.0, scenario="flying-splice"),
    Case("hswl/monte-carlo", "hswl", "the tension step on lines with uncertain web stiffness, "
         "bearing friction and roller inertia", 6.0, 2.0, scenario="tension-step",
         uncertain={"web.ea": "normal(2000 lbf, 10 %)",
                    "rollers.unwind.friction": "uniform(0.5 lbf*ft*s, 50 %)",
                    "rollers.process.friction": "uniform(0.5 lbf*ft*s, 50 %)",
                    "rollers.rewind.friction": "uniform(0.5 lbf*ft*s, 50 %)",
                    "rollers.process.inertia": "normal(2 lb*ft**2, 10 %)"},
         samples=6, seed=2025, quick=True),
)

#: samples of a Monte Carlo case in the ``--quick`` subset
QUICK_SAMPLES = 2


def cases(quick: bool = False) -> tuple[Case, ...]:
    """The standard set's cases, or its ``--quick`` subset (fewer cases and Monte Carlo
    samples, for the tests)."""
    if not quick:
        return CASES
    return tuple(Case(**{**asdict(c), "samples": min(c.samples, QUICK_SAMPLES)})
                 for c in CASES if c.quick)


def set_hash(chosen: tuple[Case, ...]) -> str:
    """First 12 hex digits of the SHA-256 of the cases as canonical JSON: the same cases
    give the same hash on any machine."""
    text = json.dumps([asdict(c) for c in chosen], sort_keys=True, separators=(",", ":"))
    return hashlib.sha256(text.encode()).hexdigest()[:12]
