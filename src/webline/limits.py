"""Bounds a study's size is held to before anything is read or allocated.

A study holds its cases in memory (their values, metrics and status) until it is merged and
written, so its number of cases is bounded by memory: checked first, from the number typed
(``--samples``, a range's ``n``, a grid's product), before a value is drawn or a list built.
This module imports nothing heavy, so the command line refuses ``--samples 1e9`` in a fraction
of a second. The work bounds (RK4 steps) that need the line live in ``webline.sim.budget``.
"""

from __future__ import annotations

from webline.errors import ArgumentError

#: Most bytes a study's cases may hold in memory (their values, metrics and traces), as
#: ``sim.budget.MAX_RECORD_BYTES`` for one run; not lifted: a study that cannot be held
#: cannot finish.
MAX_STUDY_BYTES = 4_000_000_000
#: Bytes one case holds at least beside its metrics and traces: its values (a Python dict),
#: its entry in the study's manifest, its status and coordinates, and their copies while the
#: results are merged and written.
CASE_BYTES = 2_000


def max_cases() -> int:
    """The most cases a study may have: ``MAX_STUDY_BYTES`` / ``CASE_BYTES``."""
    return MAX_STUDY_BYTES // CASE_BYTES


def check_case_count(n: int, what: str) -> None:
    """Refuse a study of ``n`` cases beyond ``max_cases()`` (``ArgumentError`` naming
    ``what`` made them: "--samples", "--set web.ea", "the grid")."""
    if n > max_cases():
        raise ArgumentError(
            f"{what}: a study of {n:.4g} cases needs at least {n * CASE_BYTES / 1e9:.3g} GB "
            f"of memory ({CASE_BYTES} bytes a case), more than {MAX_STUDY_BYTES / 1e9:.3g} GB; "
            f"run at most {max_cases():,} cases (split the study)")
