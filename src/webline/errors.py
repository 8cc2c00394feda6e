"""The errors webline raises for a user's mistakes and for runs that leave physical validity."""

from __future__ import annotations


class WeblineError(Exception):
    """Base of webline's own errors: the CLI turns these into one line and an exit status."""

    exit_code = 1


class LineFileError(WeblineError):
    """A line file (or a line spec built in Python) is malformed.

    The message always names the file, the key path and the problem, e.g.
    ``line.toml: spans[2].length: must be > 0, got -3 m``.
    """

    exit_code = 2

    def __init__(self, file: str, key: str, problem: str) -> None:
        self.file = file
        self.key = key
        self.problem = problem
        super().__init__(f"{file}: {key}: {problem}")


class SimulationError(WeblineError):
    """A simulation left physical validity or diverged; ``partial`` holds what was computed."""

    exit_code = 1

    def __init__(self, message: str, partial: object | None = None) -> None:
        self.partial = partial
        super().__init__(message)


class SimulationInterrupted(KeyboardInterrupt):
    """Ctrl-C stopped a simulation; ``partial`` holds the ``Result`` computed until then.

    A ``KeyboardInterrupt`` (not a ``WeblineError``), so that it still stops a script and is not
    swallowed by ``except Exception`` or ``except WeblineError``."""

    def __init__(self, message: str, partial: object | None = None) -> None:
        self.partial = partial
        super().__init__(message)
