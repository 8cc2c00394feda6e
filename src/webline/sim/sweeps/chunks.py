"""Studies that survive a killed run, locally or on a Dask cluster.

The cases are cut into chunks; each chunk is one task (``run_cases`` on its cases) and its
Dataset is written to ``STORE/chunk-NNNNNN.nc`` atomically as soon as it is done, by the
process that asked for the study (never by a worker), so a file is either whole or absent. A
study started again with ``resume=True`` runs only the chunks without a file; its record
(``study.json``: the resolved line's values and hash, webline's version, the cases and
settings; ``study_record``) refuses to resume a different study or a changed line. The chunks are
merged in case order at the end: every case once, none lost.

On Dask (``dask.distributed``) a chunk is a task submitted with retries, so a chunk whose
worker dies is recomputed on another; ``scheduler`` is a ``Client``, an address, or
``"local"`` for a ``LocalCluster`` of ``workers`` single-threaded processes.

A study that stops early (a full disk, its workers lost, Ctrl-C) says how many chunks are
saved and that ``--resume`` continues from them (``StudyError``, ``StudyInterrupted``); a
saved chunk that cannot be read is named before any case runs.
"""

from __future__ import annotations

import json
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

from webline.errors import ArgumentError, StudyError, StudyInterrupted
from webline.files import atomic_write, atomic_write_text, write_failure
from webline.line import Line
from webline.model.lines import load_line
from webline.sim.simulate import deferred_interrupt
from webline.sim.sweeps.study_record import check_resume, study_record, write_text

if TYPE_CHECKING:  # annotations only: a single-path study never loads the branched line
    from webline.model.web_graph import BranchedLine

#: cases per chunk (task): large enough that a task's overhead (ms) is negligible
CHUNK = 256
#: kernel work a Dask task holds at least [RK4 steps]: about a second of one core (HSWL's
#: loop runs ~5e6 steps/s on the project's machine), so that a task's own costs (a worker
#: process importing and loading the loop once, the chunk file, the scheduler's round trip)
#: stay small beside it (issue 37: 32-case chunks of 10 s HSWL ran at 0.31 of the local
#: batch's speed)
TASK_RK4_STEPS = 5_000_000
#: the store's record of its study (cases and settings), checked by ``resume``
STUDY_FILE = "study.json"
#: how often Dask retries a chunk whose worker died
RETRIES = 3
#: the chunk files' format: NetCDF-3 through scipy writes and reads a chunk of 256 cases in
#: about 13 ms, HDF5 (h5netcdf) in about 300 ms, which was a quarter of the chunk's own work
ENGINE = "scipy"


def task_chunk(n_cases: int, case_steps: int) -> int:
    """Cases per chunk of a study run on Dask: ``CHUNK``, or more where ``CHUNK`` cases hold
    less than ``TASK_RK4_STEPS`` of kernel work (``case_steps`` [RK4 steps] each, the study's
    estimate, ``study_work``); then the cases are split into as many chunks as hold that much
    each (one chunk if the whole study holds less), the last at least half as large as the
    others, so that no task is left nearly empty."""
    if CHUNK * case_steps >= TASK_RK4_STEPS:
        return CHUNK
    tasks = max(1, n_cases * case_steps // TASK_RK4_STEPS)
    even = -(-n_cases // tasks)
    # chunks are a fixed stride of cases: the first size from ``even`` up whose remainder
    # (the last chunk) is none or at least half a chunk
    return next((size for size in range(even, 2 * even)
                 if n_cases % size == 0 or n_cases % size >= size / 2), even)


def stored_chunk(store: Path) -> int | None:
    """The chunk size recorded in ``store``'s study record, None without a readable one (a
    resumed study keeps the chunks it was started with, whichever scheduler runs it now)."""
    try:
        chunk = json.loads((store / STUDY_FILE).read_text()).get("chunk")
    except (OSError, ValueError, AttributeError):
        return None
    return chunk if isinstance(chunk, int) and chunk > 0 else None


def _read_chunk(path: Path) -> Any:
    """A chunk file's Dataset, with the types NetCDF-3 does not keep (64-bit integers, numpy
    strings) given back, so the merged study equals a study run at once."""
    import numpy as np
    import xarray as xr

    with xr.open_dataset(path, engine=ENGINE) as part:
        ds = part.load()
    typed = {name: ds[name].values.astype(str if ds[name].dtype == object else np.int64)
             for name in ds.variables if ds[name].dtype in (object, np.int32)}
    # along their own dimensions: a bare array would make a label (a table, a choice) a
    # dimension of its own, detached from ``case``
    coords = {name: (ds[name].dims, value, ds[name].attrs) for name, value in typed.items()
              if name in ds.coords}
    ds = ds.assign_coords(coords)
    for name, value in typed.items():
        if name not in coords:
            ds[name] = (ds[name].dims, value, ds[name].attrs)
    return ds


def _read_saved(path: Path, n_cases: int) -> Any:
    """``_read_chunk``, or ``StudyError`` naming a damaged file (cut short, overwritten, not a
    chunk of ``n_cases`` cases) and what to do."""
    try:
        ds = _read_chunk(path)
        if ds.sizes.get("case") != n_cases:
            raise ValueError(f"{ds.sizes.get('case')} cases where {n_cases} were saved")
    except Exception as exc:  # xarray, scipy and numpy raise many types for a damaged file
        raise StudyError(f"{path}: a saved chunk is damaged ({type(exc).__name__}: "
                         f"{str(exc)[:120]}); delete it and --resume will compute its "
                         f"{n_cases} cases again") from None
    return ds


def resume_hint(store: Path, saved: int, total: int) -> str:
    """What ``--resume`` will continue from: "--resume will continue from 5 saved chunks of
    12 in STORE"."""
    return f"--resume will continue from {saved} saved chunks of {total} in {store}"


def _plain_attrs(ds: Any) -> Any:
    ds.attrs = {k: (json.dumps(v) if isinstance(v, list | dict) else v)
                for k, v in ds.attrs.items()}
    return ds


def chunk_path(store: Path, k: int) -> Path:
    """The file of chunk ``k`` in ``store``."""
    return store / f"chunk-{k:06d}.nc"


def store_files(store: Path) -> list[Path]:
    """Every file a study wrote into ``store``: its ``STUDY_FILE`` and its chunks."""
    return sorted([*store.glob(STUDY_FILE), *store.glob("chunk-*.nc")])


def _chunk_task(run: Callable[..., Any], line: Line | BranchedLine, cases: list[dict[str, object]],
                offset: int, options: dict[str, Any]) -> Any:
    """Run one chunk with ``run`` (``sweep.run_cases``; in a worker or here), its cases
    numbered from ``offset``. On a Dask worker the chunk uses the worker's threads, not every
    core of the machine (its processes share the cores)."""
    if "workers" not in options:
        try:
            from distributed import get_worker

            options = {**options, "workers": get_worker().state.nthreads}
        except (ImportError, ValueError, AttributeError):
            pass  # not on a Dask worker
    ds = run(line, cases, **options)
    return _plain_attrs(ds.assign_coords(case=ds.case.values + offset))


def _client(scheduler: Any, workers: int | None) -> tuple[Any, Any]:
    """(client, cluster to close or None) for ``scheduler``."""
    from webline.extras import require

    require("distributed")  # without Dask: MissingExtra, one line naming webline[dask]
    from distributed import Client

    if isinstance(scheduler, Client):
        return scheduler, None
    if scheduler == "local":
        from webline.sim.sweeps.dask_run import start_local

        return start_local(workers)
    from webline.sim.sweeps.scheduler import connect

    return connect(str(scheduler)), None  # probed first: a silent port or a web server refused


def run_chunked(run: Callable[..., Any], line: Line | BranchedLine | str | Path,
                cases: Sequence[Mapping[str, object]], *, store: str | Path,
                resume: bool = False, scheduler: Any = None, workers: int | None = None,
                chunk: int | None = None, case_steps: int | None = None,
                progress: Callable[[int, int], None] | None = None,
                attrs: Mapping[str, Any] | None = None, **options: Any) -> Any:
    """``run`` (``sweep.run_cases``) of ``line`` over ``cases`` chunk by chunk into ``store``
    (module docstring); ``options`` are ``run_cases``'s (duration, scenario, record). Without
    ``scheduler`` the chunks run here on ``workers`` threads. ``chunk``: cases per chunk;
    default the resumed store's, else ``CHUNK``, on a ``scheduler`` ``task_chunk`` of
    ``case_steps`` (a case's RK4 steps, as the study's check estimated them). Returns the
    merged Dataset."""
    import xarray as xr

    source: Any = line
    line = load_line(source)
    store = Path(store)
    if chunk is None:
        chunk = stored_chunk(store) if resume else None
    if chunk is None:
        chunk = CHUNK if scheduler is None or case_steps is None else task_chunk(
            len(cases), case_steps)
    store.mkdir(parents=True, exist_ok=True)
    record = study_record(line, cases, chunk, options)
    manifest_path = store / STUDY_FILE
    if manifest_path.exists():
        check_resume(manifest_path, record, resume)  # the same line, webline and cases
    else:
        if any(store.glob("chunk-*.nc")):  # not this study's: never merged into it
            raise ArgumentError(f"{store}: holds chunk files but no study record "
                                f"({STUDY_FILE}); remove them or choose another folder")
        atomic_write_text(manifest_path, write_text(record))
    starts = list(range(0, len(cases), chunk))

    def path(k: int) -> Path:
        return chunk_path(store, k)

    todo = [k for k, _ in enumerate(starts) if not path(k).exists()]
    done = len(cases) - sum(min(chunk, len(cases) - starts[k]) for k in todo)
    for k in sorted(set(range(len(starts))) - set(todo)):  # damaged: say so before running
        _read_saved(path(k), min(chunk, len(cases) - starts[k]))
    saved = len(starts) - len(todo)

    def save(k: int, ds: Any) -> None:
        nonlocal done, saved
        # Ctrl-C waits for the write (ms): raised inside it, it left xarray's file lock held
        # and the file's close waited on it for ever (one try in three)
        with deferred_interrupt() as interrupted:
            try:
                atomic_write(path(k), lambda tmp: ds.to_netcdf(tmp, engine=ENGINE))
            except OSError as exc:  # a full disk: the chunks saved so far stay whole
                hint = resume_hint(store, saved, len(starts))
                raise StudyError(write_failure(exc, f"free some space: {hint}")) from None
        saved += 1
        if interrupted():
            raise KeyboardInterrupt
        done += ds.sizes["case"]
        if progress is not None:
            progress(done, len(cases))

    def task_args(k: int) -> tuple[Any, Line | BranchedLine, list[dict[str, object]], int,
                                   dict[str, Any]]:
        lo = starts[k]
        return run, line, [dict(c) for c in cases[lo:lo + chunk]], lo, options

    try:
        if scheduler is None:
            for k in todo:
                save(k, _chunk_task(*task_args(k)[:4], {**options, "workers": workers}))
        elif todo:
            from webline.sim.sweeps.dask_run import run_on_dask

            run_on_dask(_client(scheduler, workers), _chunk_task, {k: task_args(k) for k in todo},
                        save, RETRIES, lambda: resume_hint(store, saved, len(starts)))
    except KeyboardInterrupt:
        raise StudyInterrupted(f"interrupted: {resume_hint(store, saved, len(starts))}") from None
    parts = [_read_saved(path(k), min(chunk, len(cases) - starts[k]))
             for k in range(len(starts))]
    ds = xr.concat(parts, dim="case", data_vars="all", coords="different",
                   compat="equals", combine_attrs="override")
    ds.attrs = {k: (json.loads(v) if k in ("parameters", "shape") else v)
                for k, v in ds.attrs.items()}
    ds.attrs.update(attrs or {})
    return ds
