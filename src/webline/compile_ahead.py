"""Compile ahead: the compiled loops a user will need, compiled and cached before the first run.

The simulation loop is compiled (numba) the first time a line of its structure runs and cached
on disk (``webline.sim``: a folder named after the kernel's sources); from empty caches the
first single-path run spends tens of CPU-seconds compiling, the first sweep and the first
branched run as much again. ``warm`` pays that once, ahead: ``webline warm`` after installing,
and ``make run`` / ``make test`` before they start.

What is warmed (``TARGETS``): a built-in line's run (the compiled loop of its structure, its
verdict and summary), and for the single-path and branched lines a two-case sweep (the batch
loop that sweeps and Monte Carlo share). Each target is a tiny simulation (hundredths of a
second of line time); its cost is the compiling, or, when the cache already holds it, loading.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

#: the lines ``warm`` compiles by default: the built-in single-path line of ``make run`` and
#: the built-in branched line (``docs/branching.md``)
DEFAULT_LINES = ("hswl", "laminator")

#: CPU-seconds each target took to compile from empty caches (measured 2026-12-02 on the
#: project's shared 2-core machine, rounded up; wall time is this over the free cores;
#: ``benchmarks/bench_first_run.py``: hswl 21-25 s, laminator 31-36 s once its plant compiles
#: once). A target not listed is counted as a single-path line's run. The branched line's
#: sweep reuses most of what its run compiled (its batch loop: 3.9 CPU-s after the run,
#: measured 2026-12-02, issue 33).
FIRST_COMPILE_CPU_S = {
    "run hswl": 30.0,
    "run laminator": 40.0,
    "sweep hswl": 25.0,
    "sweep laminator": 5.0,
}

#: simulated time of each warming run [s]: a few controller ticks, as cheap as a run can be
WARM_SECONDS = 0.02

#: a parameter each target's sweep varies (two values, so the batch loop runs two cases)
_SWEEP_VALUES = {
    "hswl": {"web.ea": ["8 kN", "9 kN"]},
    "laminator": {"webs.film.web.modulus": ["4 GPa", "5 GPa"]},
}


@dataclass(frozen=True)
class Warmed:
    """One warmed target: ``what`` ("run LINE" or "sweep LINE") and the wall time it took
    [s] (compiling when the cache lacked it, loading otherwise)."""

    what: str
    seconds: float


def cache_folder() -> Path:
    """The folder holding webline's compiled loops (numba's cache for this version of the
    kernel's sources, or ``NUMBA_CACHE_DIR`` where the user set it)."""
    import numba

    import webline.sim  # noqa: F401  (sets numba's cache folder)

    # this module lives outside sim/: the cache folder is named after sim/'s sources
    return Path(numba.config.CACHE_DIR)  # type: ignore[attr-defined]


def cache_is_empty() -> bool:
    """Whether no compiled loop of this version is cached yet (the first run will compile)."""
    folder = cache_folder()
    return not folder.is_dir() or next(folder.rglob("*.nbi"), None) is None


def targets(lines: Sequence[str] = DEFAULT_LINES, *, sweeps: bool = True) -> list[str]:
    """The names of what ``warm`` compiles for ``lines``: "run LINE" for each line and, with
    ``sweeps``, "sweep LINE" for each line with a sweep parameter (``_SWEEP_VALUES``)."""
    out = [f"run {line}" for line in lines]
    if sweeps:
        out += [f"sweep {line}" for line in lines if line in _SWEEP_VALUES]
    return out


def first_compile_estimate(names: Sequence[str]) -> float:
    """Rough CPU-seconds to compile ``names`` (``targets``) from empty caches [s]."""
    return sum(FIRST_COMPILE_CPU_S.get(name, FIRST_COMPILE_CPU_S["run hswl"]) for name in names)


def check_lines(lines: Sequence[str]) -> None:
    """Raise ``LineFileError`` for the first of ``lines`` that is neither a built-in line nor
    a readable TOML file, before anything is compiled."""
    from webline.spec.load import read_any

    for line in lines:
        read_any(line)


def warm(
    lines: Sequence[str] = DEFAULT_LINES,
    *,
    sweeps: bool = True,
    progress: Callable[[str], None] | None = None,
) -> list[Warmed]:
    """Compile (or load from the cache) the loops ``lines`` need: each line's run and, with
    ``sweeps``, its sweep's batch loop. ``lines``: built-in names or line-file paths.
    ``progress(name)`` is called before each target. Returns each target with its wall time
    [s]; a second call finds everything cached and takes about a second per target."""
    from webline.sim.simulate import simulate
    from webline.sim.sweeps.sweep import sweep

    check_lines(lines)
    done = []
    for name in targets(lines, sweeps=sweeps):
        kind, line = name.split(" ", 1)
        if progress is not None:
            progress(name)
        started = time.perf_counter()
        if kind == "run":
            result = simulate(line, WARM_SECONDS, raise_on_failure=False)
            result.verdict  # noqa: B018  (compiles the event statistics too)
        else:
            sweep(line, _SWEEP_VALUES[line], duration=WARM_SECONDS, workers=1)
        done.append(Warmed(name, time.perf_counter() - started))
    return done
