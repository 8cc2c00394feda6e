"""Parameter distributions of a Monte Carlo study, written as in line files and the CLI.

``"normal(9 kN, 5 %)"``: mean and standard deviation (a percentage, written ``%``,
``percent`` or ``pct``, is relative to the mean);
``"uniform(0.1, 0.3)"`` or ``"uniform(9 kN, 10 %)"``: bounds, or centre and relative half
width; ``"lognormal(9 kN, 5 %)"``: median and the standard deviation of its logarithm (a
percentage is that fraction). A scipy.stats frozen distribution is taken as is, in SI units.
Every sample is drawn up front from one ``numpy.random.Generator``, parameter after
parameter, so a study is the same whatever the number of workers.
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping
from typing import Any

import numpy as np

_CALL = re.compile(r"^\s*(normal|uniform|lognormal)\s*\((.*)\)\s*$", re.IGNORECASE)


def _call(text: str) -> tuple[str, list[str]] | None:
    """(kind, argument texts) of ``"normal(9 kN, 5 %)"``, or None if it is no call."""
    match = _CALL.match(text)
    return None if match is None else (match[1].lower(), match[2].split(","))


#: the words of a relative spread, all one meaning: ``5 %``, ``5 percent``, ``5 pct`` (pint
#: alone reads "percent" as the plain number 0.05 and "pct" as a picocarat)
PERCENT_WORDS = ("%", "percent", "pct")


def _quantity(text: str) -> tuple[float, str]:
    """(magnitude in SI base units, its dimensions as pint writes them, "" for a plain
    number, SI) of ``"9 kN"``, or (fraction, "%") of ``"5 %"`` / ``"5 percent"`` /
    ``"5 pct"``. Read as strictly as a line file's values (``units.quantity_parts``: no
    expressions); another ratio word (ppm, permille) is refused, as a spread it would be
    ambiguous. Raises ``ValueError``."""
    from webline.units import quantity_parts, unit_reading

    number, unit = quantity_parts(text)
    if not math.isfinite(number):
        raise ValueError(f"{text.strip()!r} is not a finite number")
    if unit.lower() in PERCENT_WORDS:
        return number / 100.0, "%"
    if not unit:
        return number, ""
    factor, dims, ratio = unit_reading(unit, text)
    if ratio:
        raise ValueError(f"{text.strip()!r}: write a relative spread in % (or 'percent', "
                         "'pct'), an absolute one with the parameter's unit")
    return number * factor, dims


def values_written(text: str) -> list[tuple[str | float, float]]:
    """The arguments of a valid written distribution that are values of the parameter, as
    written (a plain number as a number, SI) and in SI base units: ``[("9 kN", 9000.0)]`` of
    ``"normal(9 kN, 5 %)"``, both bounds of ``"uniform(1 Hz, 2 Hz)"``. The line may read a
    unit otherwise than pint's base units do (Hz as 2π rad/s for an angular frequency, N/m
    as a force per width of web): ``sweep.monte_carlo`` scales the samples by the line's own
    reading of these."""
    call = _call(text)
    if call is None:
        return []
    kind, args = call
    out: list[tuple[str | float, float]] = []
    for k, arg in enumerate(args):
        number, unit = _quantity(arg)
        if unit != "%" and (k == 0 or kind != "lognormal"):
            out.append((arg.strip() if unit else number, number))
    return out


def parse_distribution(text: str) -> tuple[str, float, float]:
    """(kind, a, b) of a written distribution in SI: normal (mean, std), uniform (low,
    high), lognormal (median, sigma of the log). Raises ``ValueError`` naming the problem."""
    call = _call(text)
    if call is None:
        raise ValueError(f"cannot read {text!r} as a distribution: write normal(mean, std), "
                         "uniform(low, high) or lognormal(median, sigma)")
    kind, args = call
    if len(args) != 2:
        raise ValueError(f"{text!r}: {kind} takes two arguments, got {len(args)}")
    try:
        (a, unit_a), (b, unit_b) = _quantity(args[0]), _quantity(args[1])
    except Exception as exc:  # pint raises many types
        raise ValueError(f"{text!r}: {exc}") from None
    if unit_a == "%":
        raise ValueError(f"{text!r}: the first argument is a value, not a percentage")
    if kind == "lognormal" and unit_b not in ("%", ""):
        raise ValueError(f"{text!r}: sigma, the standard deviation of the logarithm, is a "
                         "plain number or a percentage")
    if kind != "lognormal" and unit_a and not unit_b and b != 0:  # read as SI, silently
        raise ValueError(f"{text!r}: {args[1].strip()} has no unit beside {args[0].strip()}; "
                         f"write it with a unit or as a percentage ('{args[1].strip()} %')")
    if kind != "lognormal" and unit_a and unit_b and unit_b not in ("%", unit_a):
        raise ValueError(f"{text!r}: {args[0].strip()} and {args[1].strip()} are not of one "
                         "kind (a plain number is in SI units)")
    if kind == "normal":
        std = abs(a) * b if unit_b == "%" else b
        if std < 0:
            raise ValueError(f"{text!r}: the standard deviation must not be negative")
        return kind, a, std
    if kind == "uniform":
        low, high = (a * (1 - b), a * (1 + b)) if unit_b == "%" else (a, b)
        if high < low:
            raise ValueError(f"{text!r}: the upper bound is below the lower one")
        return kind, min(low, high), max(low, high)
    if a <= 0 or b < 0:
        raise ValueError(f"{text!r}: lognormal needs a positive median and sigma >= 0")
    return kind, a, b


def draw(distributions: Mapping[str, Any], n: int, seed: int) -> dict[str, np.ndarray]:
    """``n`` samples [SI] of each distribution, in the order given, from one generator."""
    rng = np.random.default_rng(seed)
    out: dict[str, np.ndarray] = {}
    for path, dist in distributions.items():
        if isinstance(dist, str):
            try:
                kind, a, b = parse_distribution(dist)
            except ValueError as exc:
                raise ValueError(f"{path}: {exc}") from None
            if kind == "normal":
                out[path] = rng.normal(a, b, n)
            elif kind == "uniform":
                out[path] = rng.uniform(a, b, n)
            else:
                out[path] = a * np.exp(rng.normal(0.0, b, n))
        elif hasattr(dist, "rvs"):
            out[path] = np.asarray(dist.rvs(size=n, random_state=rng), dtype=float)
        else:
            out[path] = np.full(n, float(dist))  # a fixed value
    return out


def proportion_interval(k: int, n: int, confidence: float = 0.95) -> tuple[float, float]:
    """The exact (Clopper-Pearson) interval of a probability seen ``k`` times in ``n`` draws
    (a share of a study's cases). Unlike a standard error it does not shrink to nothing at
    k = 0: no failure in 8 draws still allows 37 % at 95 %."""
    from scipy.stats import binomtest

    interval = binomtest(k, n).proportion_ci(confidence_level=confidence, method="exact")
    return float(interval.low), float(interval.high)
