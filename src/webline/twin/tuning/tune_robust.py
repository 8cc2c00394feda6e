"""Robustness of a tuned line: a Monte Carlo over its uncertain parameters.

Each draw is the tuned line (its gains explicit, so they stay as commissioned) with the
uncertain parameters drawn; it passes when it is stable at every checked point of the roll
(every closed-loop mode in the left half plane) and, in every scenario, no torque sits at its
limit longer than allowed and the run neither fails nor goes unstable. The distributions come
in webline's language (``"normal(4 GPa, 10 %)"``, as ``webline.monte_carlo`` takes them) or
from a fit's ``fit.json`` (normal(value, stderr), truncated at zero for a positive value).
"""

from __future__ import annotations

import json
import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from webline.errors import ArgumentError
from webline.line import Line
from webline.sim.sweeps.cases import derive_line
from webline.sim.sweeps.sweep import monte_carlo
from webline.twin.tuning.tune_constraints import Limits, controller_modes
from webline.twin.tuning.tune_space import line_at_roll, roll_radii

#: draws whose failures are described in the result, at most
REASONS_KEPT = 5


@dataclass(frozen=True)
class RobustCheck:
    """``passed`` of ``n`` draws stayed stable and within limits; ``required`` share [1];
    ``distributions`` as given (text); ``reasons``: why the first failing draws failed."""

    n: int
    passed: int
    required: float
    distributions: dict[str, str]
    reasons: tuple[str, ...] = field(default_factory=tuple)

    @property
    def share(self) -> float:
        return self.passed / self.n if self.n else math.nan

    @property
    def holds(self) -> bool:
        return self.n > 0 and self.share >= self.required

    def as_dict(self) -> dict[str, object]:
        return {"draws": self.n, "passed": self.passed, "share": self.share,
                "required_share": self.required, "holds": self.holds,
                "distributions": self.distributions, "first_failures": list(self.reasons)}


def default_uncertain(line: Line) -> dict[str, str]:
    """Uncertainties assumed when none are given [SI]: the web's stiffness ±10 % (humidity and
    temperature; its ``ea`` or ``modulus`` as the file gives it: hswl gives ``ea``), every
    driven roller's and roll's rotating inertia ±10 %, every dancer's damping ±30 % (one
    standard deviation each)."""
    web = line.spec.web
    key, value = ("ea", web.ea) if web.ea is not None else ("modulus", web.modulus)
    return {f"web.{key}": f"normal({value!r}, 10 %)", **rollers_uncertain(line)}


def rollers_uncertain(line: Any) -> dict[str, str]:
    """The rollers' part of ``default_uncertain`` (a single-path or branched line): every
    driven roller's and roll's rotating inertia ±10 %, every dancer's damping ±30 %."""
    out = {}
    for i in line.drives:
        roller = line.spec.rollers[i]
        out[f"rollers.{roller.name}.inertia"] = f"normal({roller.inertia!r}, 10 %)"
    for roller in line.spec.rollers:
        carriage = getattr(roller, "dancer", None)
        if carriage is not None and carriage.damping > 0:
            out[f"rollers.{roller.name}.dancer.damping"] = f"normal({carriage.damping!r}, 30 %)"
    return out


def fit_uncertain(path: str | Path, poor_fit: str = "refuse",
                  ) -> tuple[dict[str, Any], list[str]]:
    """Distributions from a fit's ``fit.json`` (``{"parameters": {PATH: {"value", "stderr",
    ...}}}``, SI): normal(value, stderr) (scipy frozen), truncated at 0 for a positive
    value; and notes: the paths left out (no finite positive stderr), each with why. A fit
    whose ``verdict`` is not "good" (issue 36) is refused (``ArgumentError`` naming the file,
    the verdict and its reasons) unless ``poor_fit`` is "widen": then every parameter is
    drawn uniformly over its ``bounds`` (the fit's values are not trusted), said in the
    notes. Raises ``ArgumentError`` naming the file and key for a bad file."""
    from scipy import stats

    try:
        data = json.loads(Path(path).read_text(encoding="utf-8"))
        parameters = data["parameters"]
        if not isinstance(parameters, dict):
            raise TypeError
    except OSError as exc:
        raise ArgumentError(f"{path}: cannot read it ({exc.strerror})") from None
    except (ValueError, KeyError, TypeError):
        raise ArgumentError(f"{path}: parameters: expected a fit.json with a "
                            "'parameters' table of {value, stderr} per path") from None
    verdict = data.get("verdict", "good")
    if verdict != "good":
        why = "; ".join(str(r) for r in data.get("reasons", [])) or "no reason given"
        if poor_fit != "widen":
            raise ArgumentError(f"{path}: verdict: the fit is {verdict} ({why}): tune does not "
                                "build on it; fit again (docs/commissioning.md: when the fit is "
                                "poor), or --poor-fit widen to draw its parameters over their "
                                "bounds")
        return _over_bounds(path, parameters, verdict)
    out: dict[str, Any] = {}
    skipped = []
    for name, entry in parameters.items():
        try:
            value, stderr = float(entry["value"]), float(entry["stderr"])
        except (KeyError, TypeError, ValueError):
            raise ArgumentError(f"{path}: parameters.{name}: needs numbers 'value' and "
                                "'stderr'") from None
        if not (math.isfinite(stderr) and stderr > 0):
            skipped.append(f"{name}: no finite positive stderr ({stderr!r}), left out")
            continue
        if value > 0:
            out[name] = stats.truncnorm(-value / stderr, math.inf, loc=value, scale=stderr)
        else:
            out[name] = stats.norm(value, stderr)
    return out, skipped


def _over_bounds(path: str | Path, parameters: dict[str, Any],
                 verdict: str) -> tuple[dict[str, Any], list[str]]:
    """Uniform distributions over each parameter's ``bounds`` [SI] of a fit not trusted."""
    from scipy import stats

    out: dict[str, Any] = {}
    for name, entry in parameters.items():
        try:
            low, high = (float(v) for v in entry["bounds"])
        except (KeyError, TypeError, ValueError):
            raise ArgumentError(f"{path}: parameters.{name}.bounds: a {verdict} fit is widened "
                                "to its bounds, and this one has none (fit it again)") from None
        if not (math.isfinite(low) and math.isfinite(high) and low < high):
            raise ArgumentError(f"{path}: parameters.{name}.bounds: expected LOW < HIGH, got "
                                f"{low!r} .. {high!r}")
        out[name] = stats.uniform(low, high - low)
    return out, [f"the fit is {verdict}: its {len(out)} parameters are drawn uniformly over "
                 "their bounds, not from its values (--poor-fit widen)"]


def robustness(line: Any, uncertain: Mapping[str, Any], scenarios: Sequence[str], *,
               limits: Limits, n: int, seed: int, workers: int | None = None,
               instability: Callable[[Any, dict[str, float]], str | None] | None = None,
               ) -> RobustCheck:
    """Monte Carlo of ``n`` draws (``seed``) of ``uncertain`` on ``line`` (gains explicit)
    over ``scenarios`` (module docstring). ``instability(line, drawn values)``: why the drawn
    line is unstable, or None (default ``chain_instability``; a branched line's:
    ``tune_branched``)."""
    def unstable(drawn: Any, values: dict[str, float]) -> str | None:
        if instability is not None:
            return instability(drawn, values)
        return chain_instability(drawn, values, limits.roll_points)

    text = {p: d if isinstance(d, str) else _describe(d) for p, d in uncertain.items()}
    if not uncertain or n == 0:
        return RobustCheck(0, 0, limits.robust_share, text)
    ok = np.ones(n, dtype=bool)
    why: dict[int, str] = {}
    drawn: dict[str, np.ndarray] = {}
    for scenario in scenarios:
        ds = monte_carlo(line, dict(uncertain), n, seed=seed, scenario=scenario,
                         workers=workers)
        drawn = {p: np.asarray(ds[p].values, dtype=float) for p in uncertain}
        share = np.asarray(ds.torque_limit_time.values) / float(ds.attrs["duration"])
        for c in range(n):
            status = str(ds.status.values[c])
            if status in ("failed", "unstable"):
                ok[c] = False
                why.setdefault(c, f"{scenario}: {ds.headline.values[c]}")
            elif share[c].max() > limits.saturation_share:
                ok[c] = False
                d = int(np.argmax(share[c]))
                why.setdefault(c, f"{scenario}: {ds.drive.values[d]} at its torque limit "
                                  f"{share[c, d]:.1%} of the run")
    for c in range(n):
        reason = unstable(line, {p: float(drawn[p][c]) for p in uncertain})
        if reason is not None:
            ok[c] = False
            why.setdefault(c, reason)
    reasons = tuple(f"draw {c}: {why[c]}" for c in sorted(why)[:REASONS_KEPT])
    return RobustCheck(n, int(ok.sum()), limits.robust_share, text, reasons)


def chain_instability(line: Line, values: dict[str, float], points: int = 3) -> str | None:
    """Why single-path ``line`` with ``values`` [SI] at their paths is unstable at one of
    ``points`` points across the roll (a closed-loop mode with Re λ >= 0), or None."""
    drawn_line = derive_line(line, values)
    for ru, rw in roll_radii(line, points):
        eig, _ = controller_modes(line_at_roll(drawn_line, ru, rw))
        if eig.real.max() >= 0.0:
            return (f"unstable at unwind r = {ru:.3g} m, rewind r = {rw:.3g} m "
                    f"(largest real part {eig.real.max():.3g} 1/s)")
    return None


def _describe(dist: Any) -> str:
    mean, std = float(dist.mean()), float(dist.std())
    return f"{dist.dist.name}(mean {mean:.6g}, std {std:.3g}) [SI]"
