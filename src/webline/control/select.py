"""Choose the controller family of every drive of a line: ``with_controller``."""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from typing import Literal

from webline.line import Line
from webline.model.web_graph import BranchedLine
from webline.spec.load import branched_from_dict, spec_from_dict

Family = Literal["cascaded_pi", "state_feedback", "adaptive", "mrac"]
FAMILIES: tuple[Family, ...] = ("cascaded_pi", "state_feedback", "adaptive", "mrac")


def with_controller(line: Line, family: Family, *,
                    overrides: Mapping[str, Mapping[str, object]] | None = None,
                    **options: object) -> Line:
    """A copy of ``line`` whose every driven roller runs a ``family`` controller.

    Each driven roller's ``controller`` table is replaced by ``{"type": family, **options}``,
    updated with ``overrides[roller name]`` where given (per-drive gains, friction estimates).
    Options are the keys of the family's table in the line file (``CascadedPISpec``,
    ``StateFeedbackSpec``, ``AdaptiveSpec``, ``MRACSpec``; SI numbers or unit strings). The new
    spec is validated, so a key the family does not have is an error naming it.
    """
    if family not in FAMILIES:
        raise ValueError(f"unknown controller family {family!r}; expected one of {FAMILIES}")
    overrides = dict(overrides or {})
    data = line.spec.model_dump(exclude_none=True)
    driven = {line.node_name(i) for i in line.drives}
    unknown = set(overrides) - driven
    if unknown:
        raise ValueError(f"overrides name rollers that are not driven: {sorted(unknown)}")
    for roller in data["rollers"]:
        if roller["name"] in driven:
            roller["controller"] = {"type": family, **options,
                                    **dict(overrides.get(roller["name"], {}))}
    return Line(spec_from_dict(data, f"{line.source} [{family}]"), line.source)


def with_branched_controller(line: BranchedLine, family: Family) -> BranchedLine:
    """A copy of branched ``line`` whose every driven roller runs a ``family`` controller (its
    default design), as ``with_controller`` does for a single-path line; validated, so a
    drive that cannot run it (a differential shaft's: speed control only) is a
    ``LineFileError`` naming its key."""
    if family not in FAMILIES:
        raise ValueError(f"unknown controller family {family!r}; expected one of {FAMILIES}")
    data = line.spec.model_dump(exclude_none=True)
    driven = {line.spec.rollers[i].name for i in line.drives}
    for roller in data["rollers"]:
        if roller["name"] in driven:
            roller["controller"] = {"type": family}
    return dataclasses.replace(line, spec=branched_from_dict(
        data, f"{line.source} [--controller {family}]"))
