"""Robustness of a tuned line: a Monte Carlo over its uncertain parameters.

Each draw is the tuned line (its gains explicit, so they stay as commissioned) with the
uncertain parameters drawn, checked against the same constraints as the nominal line: in
every scenario no torque sits at its limit longer than allowed and the run neither fails nor
goes unstable (``tune_constraints.run_constraints``), and at every checked point of the roll
its modes, their damping and every drive's loop margins meet the limits (the line's own
``stability(line, limits)``, the function that checks the nominal; linear, so cheap). A draw
passes when every constraint holds; the check keeps, per constraint, its worst value over the
draws and how many draws miss it. The distributions come in webline's language
(``"normal(4 GPa, 10 %)"``, as ``webline.monte_carlo`` takes them) or from a fit's
``fit.json`` (normal(value, stderr), truncated at zero for a positive value).
"""

from __future__ import annotations

import json
import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np

from webline.errors import ArgumentError
from webline.line import Line
from webline.sim.sweeps.sweep import monte_carlo
from webline.twin.tuning.tune_constraints import Constraint, Limits, run_constraints

#: draws whose failures are described in the result, at most
REASONS_KEPT = 5


@dataclass(frozen=True)
class RobustCheck:
    """``passed`` of ``n`` draws met every constraint; ``required`` share [1];
    ``distributions`` as given (text); ``reasons``: why the first failing draws failed (each
    constraint missed, its value and limit); ``worst``: each constraint's worst value over
    the draws (``where`` names the draw); ``missing``: {constraint name: draws missing it}."""

    n: int
    passed: int
    required: float
    distributions: dict[str, str]
    reasons: tuple[str, ...] = field(default_factory=tuple)
    worst: tuple[Constraint, ...] = field(default_factory=tuple)
    missing: dict[str, int] = field(default_factory=dict)

    @property
    def share(self) -> float:
        return self.passed / self.n if self.n else math.nan

    @property
    def holds(self) -> bool:
        return self.n > 0 and self.share >= self.required

    def as_dict(self) -> dict[str, object]:
        return {"draws": self.n, "passed": self.passed, "share": self.share,
                "required_share": self.required, "holds": self.holds,
                "distributions": self.distributions, "first_failures": list(self.reasons),
                "worst_over_draws": [c.as_dict() | {"draws_missing": self.missing.get(c.name, 0)}
                                     for c in self.worst]}

    def lines(self) -> list[str]:
        """The check in words: the share, then each constraint's worst value over the draws
        (for the terminal, ``tuned.toml``'s header and the report)."""
        out = [f"robustness: {self.passed} of {self.n} draws met every constraint (required "
               f"{self.required:.0%}): {'holds' if self.holds else 'FAILS'}"]
        for c in self.worst:
            missed = self.missing.get(c.name, 0)
            out.append(f"  worst over the draws: {c.name} {c.value:.4g} {c.sense} {c.limit:g} "
                       + (f"(FAILS in {missed} of {self.n} draws; {c.where})" if missed
                          else f"(holds in every draw; {c.where})"))
        return out


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
               limits: Limits, n: int, seed: int,
               stability: Callable[[Any, dict[str, float]], list[Constraint]],
               workers: int | None = None) -> RobustCheck:
    """Monte Carlo of ``n`` draws (``seed``) of ``uncertain`` on ``line`` (gains explicit)
    over ``scenarios`` (module docstring); ``stability(line, drawn values [SI])``: the
    stability constraints of the line with the drawn values at their paths, as the nominal
    line's are computed (``tune.LineOps.stability`` of the derived line)."""
    text = {p: d if isinstance(d, str) else _describe(d) for p, d in uncertain.items()}
    if not uncertain or n == 0:
        return RobustCheck(0, 0, limits.robust_share, text)
    checks: list[list[Constraint]] = [[] for _ in range(n)]
    drawn: dict[str, np.ndarray] = {}
    for scenario in scenarios:
        ds = monte_carlo(line, dict(uncertain), n, seed=seed, scenario=scenario,
                         workers=workers)
        drawn = {p: np.asarray(ds[p].values, dtype=float) for p in uncertain}
        drives = [str(d) for d in ds.drive.values]
        for c in range(n):
            status = str(ds.status.values[c])
            run = run_constraints(scenario, status, np.asarray(ds.torque_limit_time.values[c]),
                                  drives, float(ds.attrs["duration"]), limits)
            if status in ("failed", "unstable"):  # the verdict says why
                run[-1] = replace(run[-1], where=f"{scenario}: {ds.headline.values[c]}")
            checks[c] += run
    for c in range(n):
        checks[c] += stability(line, {p: float(drawn[p][c]) for p in uncertain})
    failing = [c for c in range(n) if not all(k.holds for k in checks[c])]
    reasons = tuple(f"draw {c}: " + "; ".join(_missed(k) for k in checks[c] if not k.holds)
                    for c in failing[:REASONS_KEPT])
    worst, missing = worst_over_draws(checks)
    return RobustCheck(n, n - len(failing), limits.robust_share, text, reasons, worst, missing)


def worst_over_draws(checks: Sequence[Sequence[Constraint]],
                     ) -> tuple[tuple[Constraint, ...], dict[str, int]]:
    """(each constraint's worst value over the draws, by name, in the order first met, its
    ``where`` prefixed with the draw's index; {name: draws in which it fails}) of the
    constraints ``checks[draw]`` (a name met twice in one draw, as in two scenarios, counts
    that draw once)."""
    worst: dict[str, Constraint] = {}
    missing: dict[str, int] = {}
    for c, constraints in enumerate(checks):
        failed: set[str] = set()
        for k in constraints:
            here = replace(k, where=f"draw {c}, {k.where}" if k.where else f"draw {c}")
            old = worst.get(k.name)
            if old is None or _worse(here, old):
                worst[k.name] = here
            if not k.holds:
                failed.add(k.name)
        for name in failed:
            missing[name] = missing.get(name, 0) + 1
    return tuple(worst.values()), missing


def _worse(a: Constraint, b: Constraint) -> bool:
    """Whether ``a`` is worse than ``b`` (the same constraint): NaN is worst."""
    if math.isnan(a.value) or math.isnan(b.value):
        return math.isnan(a.value) and not math.isnan(b.value)
    return a.value < b.value if a.sense == ">=" else a.value > b.value


def _missed(k: Constraint) -> str:
    where = f", {k.where}" if k.where else ""
    return f"{k.name} {k.value:.4g}, limit {k.sense} {k.limit:g}{where}"


def _describe(dist: Any) -> str:
    mean, std = float(dist.mean()), float(dist.std())
    return f"{dist.dist.name}(mean {mean:.6g}, std {std:.3g}) [SI]"
