"""The errors webline raises for a user's mistakes and for runs that leave physical validity."""

from __future__ import annotations

import signal
from dataclasses import dataclass

#: Most problems a ``LineFileError`` message lists (the rest are counted).
MAX_LISTED = 20


@dataclass(frozen=True)
class Problem:
    """One problem of a line file: key path, what is wrong, and its TOML line if known."""

    key: str
    problem: str
    line: int | None = None

    def text(self, file: str) -> str:
        where = f"{file}:{self.line}" if self.line else file
        return f"{where}: {self.key}: {self.problem}"


class WeblineError(Exception):
    """Base of webline's own errors: the CLI turns these into one line and an exit status."""

    exit_code = 1


class LineFileError(WeblineError):
    """A line file (or a line spec built in Python) is malformed.

    The message names the file, the key path and the problem, e.g.
    ``line.toml: spans[2].length: must be > 0, got -3 m``; with several problems, one per
    line (``file:LINE: key: problem`` where the TOML line is known), at most ``MAX_LISTED``
    and then "and N more". ``file``, ``key`` and ``problem`` are the first problem's;
    ``problems`` holds them all.
    """

    exit_code = 2

    def __init__(self, file: str, key: str, problem: str, *, line: int | None = None,
                 problems: list[Problem] | None = None) -> None:
        self.file = file
        self.key = key
        self.problem = problem
        self.problems = problems or [Problem(key, problem, line)]
        lines = [p.text(file) for p in self.problems[:MAX_LISTED]]
        if len(self.problems) > MAX_LISTED:
            lines.append(f"{file}: and {len(self.problems) - MAX_LISTED} more problems")
        super().__init__("\n".join(lines))

    @classmethod
    def of(cls, file: str, problems: list[Problem]) -> LineFileError:
        """The error listing ``problems`` (at least one) of ``file``."""
        first = problems[0]
        return cls(file, first.key, first.problem, line=first.line, problems=problems)


class ArgumentError(WeblineError):
    """An argument of a Python front-door function (``simulate``, ``linearize``, ...) is
    wrong; the message names the argument (exit status 2 in the CLI)."""

    exit_code = 2


class SimulationError(WeblineError):
    """A simulation left physical validity or diverged; ``partial`` holds what was computed."""

    exit_code = 1

    def __init__(self, message: str, partial: object | None = None) -> None:
        self.partial = partial
        super().__init__(message)


class ControllerError(SimulationError):
    """A user's controller raised or returned a wrong shape or a non-finite torque; the
    message names it and the tick, ``partial`` holds the run up to that tick."""


class LawCompileError(WeblineError):
    """numba cannot compile a user's control law (``sim.compiled_control``): bad input, named
    with numba's reason (exit status 2)."""

    exit_code = 2


class StudyError(WeblineError):
    """A study stopped before its end (a full disk, its workers lost, a damaged chunk); the
    message says what ``--resume`` will continue from (exit status 1)."""

    exit_code = 1


class StudyInterrupted(KeyboardInterrupt):
    """Ctrl-C stopped a study; the message says what ``--resume`` will continue from. A
    ``KeyboardInterrupt``, so that it still stops a script."""


class SimulationInterrupted(KeyboardInterrupt):
    """Ctrl-C stopped a simulation; ``partial`` holds the ``Result`` computed until then.

    A ``KeyboardInterrupt`` (not a ``WeblineError``), so that it still stops a script and is not
    swallowed by ``except Exception`` or ``except WeblineError``."""

    def __init__(self, message: str, partial: object | None = None) -> None:
        self.partial = partial
        super().__init__(message)


class Terminated(KeyboardInterrupt):
    """A stop by signal ``signum`` (SIGTERM) raised as Ctrl-C's KeyboardInterrupt is, so that
    whatever keeps its work on Ctrl-C keeps it here too and can say which signal came."""

    def __init__(self, signum: int) -> None:
        self.signum = signum
        super().__init__(f"stopped by signal {signum}")


def terminate_as_interrupt(signum: int, frame: object) -> None:
    """A SIGTERM handler (``signal.signal(signal.SIGTERM, terminate_as_interrupt)``) that
    stops as Ctrl-C does: where a deferring SIGINT handler is in place (``simulate``'s), it is
    called with SIGTERM's number, so the run keeps what it computed (status interrupted);
    elsewhere (Python's default handler, or SIGINT ignored, as in a job started in the
    background) ``Terminated``, a KeyboardInterrupt, is raised. The command line installs it
    (a batch scheduler stops a job with SIGTERM); a script may too."""
    handler = signal.getsignal(signal.SIGINT)
    if not callable(handler) or handler is signal.default_int_handler:
        raise Terminated(signum)
    handler(signum, frame)  # type: ignore[arg-type]


class MissingExtra(WeblineError, ImportError):
    """An optional part of webline is used without its packages installed; the message names
    the extra that installs them (``pip install 'webline[dask]'``). Also an ``ImportError``,
    so code that falls back when an import fails keeps working."""

    exit_code = 2
