"""When the report may fork copies of the process (``report.early``, ``report.render``)."""

from __future__ import annotations

import multiprocessing
import os
import threading


def can_fork() -> bool:
    """Whether forking a copy of this process is safe and worth it: more than one core, this
    process single-threaded (a fork copies no other thread, whatever lock it held) and the
    ``fork`` start method available."""
    return ((os.cpu_count() or 1) > 1 and threading.active_count() == 1
            and "fork" in multiprocessing.get_all_start_methods())
