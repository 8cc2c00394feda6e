"""The CLI starts without the heavy libraries: `webline --version` and `--help` must not wait
for pint, numba, scipy, python-control, matplotlib or xarray (issue 12: at most 3x the time
of `python -c "import numpy"`; each of these costs 0.1-1.5 s to import)."""

from __future__ import annotations

import subprocess
import sys

import pytest

# serial: start-up is what these tests guard; run beside the parallel suite's workers they
# would compete for its cores (and later tests here time it)
pytestmark = pytest.mark.serial

HEAVY = ("pint", "numba", "scipy", "control", "matplotlib", "xarray", "pandas", "h5py",
         "distributed")


def test_cli_import_leaves_heavy_libraries_unloaded() -> None:
    code = ("import sys, webline, webline.cli; "
            f"print(','.join(m for m in {HEAVY!r} if m in sys.modules))")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          check=True)
    assert done.stdout.strip() == ""


def test_front_door_names_load_on_first_use() -> None:
    code = ("import sys, webline; before = 'numba' in sys.modules; webline.simulate; "
            "print(before, 'numba' in sys.modules)")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          check=True)
    assert done.stdout.split() == ["False", "True"]


def test_the_cli_ends_as_system_exit_would_with_exit_handlers_and_buffers() -> None:
    """``end_process`` (the end of ``webline.cli.main``) skips module teardown only: an exit
    handler still runs, buffered output still arrives, and the status is SystemExit's."""
    for code, status, stderr in (("None", 0, ""), ("3", 3, ""), ("'bad input'", 1, "bad input")):
        script = ("import atexit, sys; from webline.cli import end_process; "
                  "atexit.register(lambda: print('handler ran')); "
                  f"sys.stdout.write('buffered'); end_process({code})")
        done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True)
        assert done.returncode == status
        assert done.stdout == "bufferedhandler ran\n"
        assert done.stderr.strip() == stderr


def test_a_single_path_run_imports_neither_xarray_nor_the_branched_line() -> None:
    """The main job's steps for a single-path line (load, simulate, results file, report)
    leave xarray/pandas (0.5 s of CPU: the report's process imported them through the
    branched result until session 9) and the branched line's schema and modules unloaded."""
    code = ("import sys, tempfile, pathlib; from webline.cli_common import _load; "
            "from webline.sim.simulate import simulate; "
            "from webline.report.results_file import write_results; "
            "import webline.report.writer; "
            "r = simulate(_load('hswl', None), 0.05); "
            "write_results(r, pathlib.Path(tempfile.mkdtemp())); "
            "print(','.join(m for m in sys.modules if m in ('xarray', 'pandas') or m.startswith("
            "('webline.spec.branched', 'webline.model.web_graph', 'webline.sim.branches'))))")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          check=True)
    assert done.stdout.strip() == ""


def test_run_forks_its_report_process_once_the_line_and_the_simulation_are_loaded(
        tmp_path) -> None:
    """``webline run`` forks the report's process after loading the line and importing the
    simulation, before simulating (issue 37): the copy shares pydantic, the line's schema and
    numba (forked before them, it imported them again to read the result: about a CPU-second
    more per run on a loaded machine) and imports only matplotlib and the report's modules
    while the line is simulated."""
    code = ("import sys; import webline.report.early as early\n"
            "real = early.Reporter.start.__func__\n"
            "def spy(cls):\n"
            "    seen = [m for m in ('pydantic', 'webline.spec.schema', 'numba', "
            "'webline.sim.simulate', 'matplotlib') if m in sys.modules]\n"
            "    print('at fork:', ','.join(seen), file=sys.stderr, flush=True)\n"
            "    return real(cls)\n"
            "early.Reporter.start = classmethod(spy)\n"
            "from webline.cli import main; sys.argv[0] = 'webline'; main()")
    done = subprocess.run([sys.executable, "-c", code, "run", "hswl", "-d", "0.05", "-q",
                           "--out", str(tmp_path / "run")], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert ("at fork: pydantic,webline.spec.schema,numba,webline.sim.simulate"
            in done.stderr.splitlines()), done.stderr
    assert (tmp_path / "run" / "report.html").is_file()


def test_a_single_path_study_imports_neither_the_branched_line_nor_scipy_optimize(
        tmp_path) -> None:
    """A Monte Carlo study of a single-path line, run at once and chunk by chunk into a store
    (the path each Dask worker takes), loads neither the branched line's schema and kernel nor
    ``scipy.optimize`` (issue 37: 0.4-0.6 s of CPU per process and per Dask worker)."""
    code = ("import sys, webline; d = {'web.ea': 'uniform(1800 lbf, 2200 lbf)'}; "
            "webline.monte_carlo('hswl', d, 2, seed=1, duration=0.05, workers=1); "
            f"webline.monte_carlo('hswl', d, 2, seed=1, duration=0.05, workers=1, "
            f"store={str(tmp_path / 'store')!r}); "
            "print(','.join(m for m in sys.modules if m.startswith(('scipy.optimize', "
            "'webline.spec.branched', 'webline.model.web_graph', 'webline.sim.branches'))))")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          check=True)
    assert done.stdout.strip() == ""


def _cpu_seconds(command: list[str]) -> float:
    """User + system CPU time [s] of ``command`` and every process it waited for (the report's
    copies), run to success."""
    import os
    import resource

    # as a user's Python runs: writing its .pyc files (without them every module is compiled
    # from source in every process, about 0.3 s of the main job's CPU)
    env = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    subprocess.run(command, check=True, capture_output=True, env=env)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return after.ru_utime - before.ru_utime + after.ru_stime - before.ru_stime


def test_the_main_job_needs_at_most_35_imports_of_numpy_in_cpu_time(tmp_path) -> None:
    """``webline run hswl --scenario speed-change`` (warm numba cache) in CPU time, the
    command's and its report processes', against ``import numpy``'s in the same test: a
    ratio, so that a machine slowed by other work moves both (session 12, load 9 on 2 cores:
    2.8 s against 0.08 s, 35x; quieter, 2.3-2.5 s against 0.11 s, about 22x; issue 37's goal
    is 1.6 s, about 13x). Since the report's process forks after the line and the simulation
    are loaded (``report.early``), measured at load 8-14 on 2 cores: 5.8-6.1 s against
    0.22-0.25 s, 23-24x (30x before, in the same conditions). The bound, 35x, catches a
    regression of about a CPU-second (a library imported for nothing or twice, a compiled
    function compiled again) without failing on a loaded machine."""
    numpy = min(_cpu_seconds([sys.executable, "-c", "import numpy"]) for _ in range(3))
    job = [sys.executable, "-c", "from webline.cli import main; main()", "run", "hswl",
           "--scenario", "speed-change", "-q", "--out", str(tmp_path / "run")]
    _cpu_seconds(job)  # compiles and caches the loop for this line's structure if need be
    cpu = min(_cpu_seconds(job) for _ in range(2))
    assert cpu <= 35 * numpy, f"main job {cpu:.2f} s CPU, import numpy {numpy:.3f} s"
