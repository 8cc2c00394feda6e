"""Bounds a study's size is held to before anything is read or allocated.

A study holds its cases in memory (their values, metrics and status) until it is merged and
written, so its number of cases is bounded by memory: checked first, from the number typed
(``--samples``, a range's ``n``, a grid's product), before a value is drawn or a list built.
This module imports nothing heavy, so the command line refuses ``--samples 1e9`` in a fraction
of a second. The work bounds (RK4 steps) that need the line live in ``webline.sim.budget``.
"""

from __future__ import annotations

from webline.errors import ArgumentError

#: Most states of a closed-loop linear model whose dense eigen-decomposition webline computes
#: for a run (its verdict's stability check, the report's modes and zone loops). LAPACK's
#: time grows as the cube of the states: 881 states (a 250-span line) took 80 s with left
#: eigenvectors on the shared, loaded 2-core machine; 400 states (about 110 spans of the
#: ``benchmarks/long_line.py`` line) take a few seconds. Beyond it a run's verdict carries a
#: warning that stability was not checked, and its report says modes and zone loops were not
#: computed (issue 22 item 7; docs/sweeps.md, "Long lines").
MAX_EIGEN_STATES = 400

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
