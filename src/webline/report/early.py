"""The report's own process, started with ``webline run`` so that its libraries load while the
line is simulated (issue 12: the main job's wall time).

Drawing the report needs matplotlib: importing it and drawing the figures was over half of the
main job, all of it after the simulation. Where ``fork`` is available, the process is still
single-threaded and there is more than one core, ``Reporter.start`` forks a copy of the
command once the line is loaded and the simulation's modules imported (``webline run``): the
copy shares them (forked any earlier, it imported pydantic, the line's schema and numba again
to read the result: about a CPU-second more in all, issue 37). The copy imports the report's
modules while the line is simulated, then receives the job (the result, pickled through a
pipe) and writes the figures (half of them on a further fork, ``report.render``), summary and
report, while this process writes the results file. Should the copy fail in any way,
``collect`` says so and the caller writes the report itself, as it would without the copy: a
report is never lost.

The manifest (``report.outputs``) stays consistent: the results file is claimed before the
job is handed over, the copy claims its own files in its copy of the output folder, and
``collect`` adopts the copy's list of written files before the caller finishes the folder.
"""

from __future__ import annotations

import contextlib
import multiprocessing
from dataclasses import dataclass
from multiprocessing.connection import Connection
from multiprocessing.process import BaseProcess
from pathlib import Path
from typing import TYPE_CHECKING

from webline.report.forking import can_fork

if TYPE_CHECKING:  # at run time only the copy imports them (the command forks before)
    from webline.report.outputs import OutputFolder, ReportFiles
    from webline.report.text.display import System
    from webline.sim.results.result import Result

#: Longest wait [s] for the copy to end after its reply (it has nothing left to do).
JOIN_SECONDS = 5.0


@dataclass(frozen=True)
class ReportJob:
    """What the copy needs to write a run's report (``writer.write_report``'s arguments)."""

    result: Result
    folder: OutputFolder
    units: System
    scenario: str | None
    results_file: Path
    svg: bool


def _serve(conn: Connection, parent_end: Connection) -> None:
    """The copy: load the report's modules, then write the one job it is sent and reply with
    (the files, the folder's written list), or with the error's text."""
    parent_end.close()  # else the pipe stays open here and a dead command's copy waits forever
    try:
        from webline.report.writer import write_report  # the slow imports, done meanwhile

        job: ReportJob = conn.recv()
        files = write_report(job.result, job.folder.path, units=job.units,
                             scenario=job.scenario, results_file=job.results_file,
                             folder=job.folder, svg=job.svg)
        conn.send((files, job.folder.written))
    except EOFError:  # the command ended without a report to write (an error, Ctrl-C)
        pass
    except BaseException as exc:  # any failure: the command writes the report itself
        with contextlib.suppress(OSError, ValueError):  # the command may be gone
            conn.send(f"{type(exc).__name__}: {exc}")
    finally:
        conn.close()


class Reporter:
    """A forked copy of the command that writes its report (module docstring)."""

    def __init__(self, process: BaseProcess, conn: Connection) -> None:
        self._process, self._conn = process, conn

    @classmethod
    def start(cls) -> Reporter | None:
        """Fork the copy, or None where it cannot be (``can_fork``)."""
        if not can_fork():
            return None
        context = multiprocessing.get_context("fork")
        mine, theirs = context.Pipe()
        # not a daemon: it forks in turn to share the figures (report.render); it ends when
        # the pipe closes: ``close``, which the command calls on every way out, or the
        # command's death (the kernel closes its end)
        process = context.Process(target=_serve, args=(theirs, mine))
        process.start()
        theirs.close()
        return cls(process, mine)

    def submit(self, job: ReportJob) -> bool:
        """Hand ``job`` to the copy; False if it could not take it."""
        try:
            self._conn.send(job)  # pickled first: a failure to pickle sends nothing
            return True
        except Exception:  # pickling or the pipe: the command writes the report
            return False

    def collect(self, folder: OutputFolder) -> ReportFiles | None:
        """The files the copy wrote, its manifest entries adopted into ``folder``; None if it
        wrote no report (it died, or replied with its error's text)."""
        reply: object = None
        try:
            reply = self._conn.recv()
        except (EOFError, OSError):
            pass
        finally:
            self.close()
        if not isinstance(reply, tuple):
            folder.recover_claims()  # what it wrote before it failed is this run's
            return None
        files, written = reply
        folder.written.extend(w for w in written if w not in folder.written)
        return files

    def close(self) -> None:
        """Close the pipe (the copy then ends) and wait for the copy; again: nothing."""
        if self._conn.closed:
            return
        self._conn.close()
        self._process.join(JOIN_SECONDS)
        if self._process.is_alive():
            self._process.terminate()
            self._process.join()

