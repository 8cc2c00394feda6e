"""The chunks of a study run as Dask tasks, and every way that can end said in one line.

A chunk whose worker dies is retried (``retries``); once every try has killed its worker
(``KilledWorker``), or the scheduler is lost, the study stops with a ``StudyError`` saying how
many chunks are saved for ``--resume``. The client and a ``LocalCluster`` are closed with
time-outs whatever happened (Ctrl-C included: its worker processes got the same signal, and
an unbounded close could wait for them for ever).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from webline.errors import StudyError

#: seconds the client and a local cluster get to close before they are left to the OS
CLOSE_SECONDS = 3.0


def run_on_dask(client_cluster: tuple[Any, Any], task: Callable[..., Any],
                tasks: dict[int, tuple[Any, ...]], save: Callable[[int, Any], None],
                retries: int, hint: Callable[[], str]) -> None:
    """Submit ``task(*tasks[k])`` for every chunk ``k`` on the client of ``client_cluster``
    (a client and the local cluster it owns, or None), ``save(k, result)`` each as it
    arrives; ``hint()`` says what ``--resume`` will continue from."""
    from distributed import CancelledError, KilledWorker, as_completed

    client, cluster = client_cluster
    try:
        futures = {client.submit(task, *args, key=f"webline-chunk-{k}", retries=retries,
                                 pure=False): k for k, args in tasks.items()}
        for future in as_completed(futures):
            k = futures[future]
            try:
                result = future.result()
            except KilledWorker:
                raise StudyError(f"the Dask workers died running chunk {k} ({retries + 1} "
                                 f"tries, each killed its worker: out of memory?); "
                                 f"{hint()}") from None
            except (OSError, CancelledError, TimeoutError) as exc:  # the scheduler is gone
                raise StudyError(f"lost the Dask scheduler running chunk {k} "
                                 f"({type(exc).__name__}: {exc}); {hint()}") from None
            save(k, result)
    except KeyboardInterrupt:
        if cluster is not None:
            close(client, cluster, hurry=True)
        raise
    else:
        if cluster is not None:
            close(client, cluster)
    finally:
        if cluster is not None:
            close(client, cluster)  # after an error; closing twice does nothing


def start_local(workers: int | None) -> tuple[Any, Any]:
    """(client, cluster) of a ``LocalCluster`` of ``workers`` (default 2) single-threaded
    processes, started with Ctrl-C (SIGINT) ignored: a terminal sends it to the whole process
    group, and workers killed by it while the study closes them made that close hang (one try
    in three). Ctrl-C stops this process, which closes them (``close``)."""
    import multiprocessing
    import signal
    import threading

    from distributed import Client, LocalCluster

    before = set(multiprocessing.active_children())
    main = threading.current_thread() is threading.main_thread()
    previous = signal.signal(signal.SIGINT, signal.SIG_IGN) if main else None
    try:  # the worker processes inherit the ignored signal (Python keeps SIG_IGN at start)
        cluster = LocalCluster(n_workers=workers or 2, threads_per_worker=1, processes=True,
                               dashboard_address=None)
    finally:
        if previous is not None:
            signal.signal(signal.SIGINT, previous)
    cluster.webline_processes = [p for p in multiprocessing.active_children()  # type: ignore[attr-defined]
                                 if p not in before]
    return Client(cluster), cluster


def close(client: Any, cluster: Any, *, hurry: bool = False) -> None:
    """Close ``client`` and its ``LocalCluster`` within about ``2 x CLOSE_SECONDS``, then
    kill any of its processes still alive; with ``hurry`` (Ctrl-C) kill them first, as the
    user asked to stop now and their chunks are lost anyway."""
    import contextlib

    if hurry:
        for process in getattr(cluster, "webline_processes", []):
            with contextlib.suppress(BaseException):
                process.kill()

    with contextlib.suppress(BaseException):
        client.close(timeout=CLOSE_SECONDS)
    with contextlib.suppress(BaseException):
        cluster.close(timeout=CLOSE_SECONDS)
    for process in getattr(cluster, "webline_processes", []):
        with contextlib.suppress(BaseException):
            if process.is_alive():
                process.kill()
                process.join(CLOSE_SECONDS)
