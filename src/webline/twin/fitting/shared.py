"""The coordinates of a fit over several records: parameters shared by every record (the
line's inertias, frictions, EA…) and parameters fitted once per record where the records
differ (an initial roll radius, a sensor offset that drifted between tests), named
``PATH@RECORD``."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from webline.errors import ArgumentError
from webline.twin.fitting.free import FreeParameter, parse_free
from webline.twin.fitting.records import FitRecord


@dataclass(frozen=True)
class Coordinates:
    """The optimiser's coordinates: each a ``FreeParameter`` (its start the line's value as
    the record drives it), the record it belongs to (``owner``: an index into the fit's
    records, None where shared) and its ``label`` (the path, or ``PATH@RECORD``)."""

    parameters: tuple[FreeParameter, ...]
    owner: tuple[int | None, ...]
    labels: tuple[str, ...]

    def of_record(self, k: int) -> np.ndarray:
        """Indices of the coordinates acting on record ``k``: the shared ones and its own."""
        return np.array([i for i, o in enumerate(self.owner) if o is None or o == k], dtype=int)

    def case(self, k: int, x: np.ndarray) -> dict[str, float]:
        """The SI values of record ``k``'s coordinates at ``x`` (its own entries, scaled to
        the bounds, in ``of_record(k)``'s order), by path."""
        return {self.parameters[i].path: self.parameters[i].unscaled(float(v))
                for i, v in zip(self.of_record(k), x, strict=True)}

    @property
    def shared(self) -> list[int]:
        """Indices of the shared coordinates."""
        return [i for i, o in enumerate(self.owner) if o is None]


def coordinates(records: Sequence[FitRecord], free: Mapping[str, object],
                per_record: Sequence[str] = ()) -> Coordinates:
    """The coordinates of ``free`` ({pattern: "LOW .. HIGH UNIT"}) over ``records``: the
    patterns named in ``per_record`` once per record, the others once for all (each record
    starts from the line's value as that record drives it). ``ArgumentError`` for a
    ``per_record`` pattern that is not a key of ``free``."""
    unknown = [p for p in per_record if p not in free]
    if unknown:
        raise ArgumentError(f"per-record {unknown[0]}: not among the free parameters (give "
                            "its bounds with --free, then name it per record)")
    params: list[FreeParameter] = []
    owner: list[int | None] = []
    labels: list[str] = []
    shared = {k: v for k, v in free.items() if k not in per_record}
    if shared:
        found = parse_free(records[0].driven, shared)
        params += found
        owner += [None] * len(found)
        labels += [p.path for p in found]
    own = {k: free[k] for k in per_record}
    for k, record in enumerate(records):
        if not own:
            break
        found = parse_free(record.driven, own)
        params += found
        owner += [k] * len(found)
        labels += [f"{p.path}@{record.label}" for p in found]
    paths = {p.path for p, o in zip(params, owner, strict=True) if o is None}
    twice = [p.path for p, o in zip(params, owner, strict=True) if o is not None and
             p.path in paths]
    if twice:
        raise ArgumentError(f"free: {twice[0]} is both shared and per record (a wildcard and "
                            "its element?)")
    return Coordinates(tuple(params), tuple(owner), tuple(labels))
