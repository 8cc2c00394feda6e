"""Checks of a branched line's web break (docs/branching.md, "Web breaks"): a ``web_break``
disturbance or a scenario's ``break``, each problem one ``LineFileError`` line naming the
file, the key and the problem."""

from __future__ import annotations

from collections.abc import Callable
from typing import NoReturn

from webline.spec.branched.schema import BranchedLineSpec
from webline.spec.winder import WebBreak

Fail = Callable[[str, str], NoReturn]


def span_names(spec: BranchedLineSpec) -> list[str]:
    """Every span's name as the line names it: its own, or ``web[k]``."""
    return [s.name or f"{web.name}[{k}]" for web in spec.webs for k, s in enumerate(web.spans)]


def check_break(spec: BranchedLineSpec, item: WebBreak, key: str, fail: Fail) -> None:
    """A break's span exists (every controller family follows the stop ramp and holds)."""
    names = span_names(spec)
    if item.span not in names:
        fail(f"{key}.span", f"no span named {item.span!r} (spans: {', '.join(names)})")


def check_breaks(spec: BranchedLineSpec, fail: Fail) -> None:
    """Every scenario's ``break``; with the line's or the scenario's disturbances one break
    per run."""
    for name, scenario in spec.scenarios.items():
        if scenario.break_ is None:
            continue
        check_break(spec, scenario.break_, f"scenarios.{name}.break", fail)
        listed = spec.disturbances if scenario.disturbances is None else scenario.disturbances
        if any(isinstance(d, WebBreak) for d in listed):
            fail(f"scenarios.{name}.break", "one web break per run: the disturbances already "
                 "have a web_break")
