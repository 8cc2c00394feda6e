"""What every session keeps of a line file's contract (``Session`` and its branched line's
``BranchSession``): its settings checked as ``simulate`` checks them, and a snapshot
restored only into the session (or a copy of it) it came from."""

from __future__ import annotations

from webline.errors import ArgumentError
from webline.spec.ranges import argument, whole_argument


def check_snapshot(snap: object, kind: type, identity: str, line: str) -> None:
    """Refuse (``ArgumentError``, one line saying whose it is) a snapshot that is not a
    ``kind`` of this session's line and plan (``identity``, line name ``line``)."""
    if not isinstance(snap, kind):
        raise ArgumentError(
            f"restore: expected a {kind.__name__} from this session's "
            f"snapshot(), got {type(snap).__name__}"
        )
    if getattr(snap, "identity", "") != identity:
        raise ArgumentError(
            f"restore: the snapshot is of line {getattr(snap, 'line', '?')!r} (identity "
            f"{getattr(snap, 'identity', '') or 'none'}), not of this session's line "
            f"{line!r} and plan (identity {identity}): restore it into the session it came "
            f"from or a copy of it"
        )


def session_settings(sample_rate: object, substeps: object) -> tuple[float | None, int | None]:
    """A session's ``sample_rate`` [Hz] and ``substeps`` checked as ``simulate`` checks
    them (the ranges and messages of the line file's keys), SI."""
    rate = (
        None
        if sample_rate is None
        else argument(sample_rate, "frequency", "sample_rate", within="control.sample_rate")
    )
    steps = (
        None
        if substeps is None
        else whole_argument(
            substeps, "substeps", 1, "expected a whole number of RK4 steps per controller period"
        )
    )
    return rate, steps
