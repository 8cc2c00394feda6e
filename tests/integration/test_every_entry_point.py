"""Every public entry point on a single-path and a branched line (issue 33 part A, item 3):
``simulate``, ``Session``, ``sweep``, ``monte_carlo``, ``replay``, ``fit``, ``experiment``,
``tune``, ``benchmark``, gym ``make`` with ``randomize``, ``analyze`` and ``report`` on
``hswl``, ``converter``, ``laminator`` and ``slitter`` give the same result type with the same
methods (none is refused on a branched line any more).

Runs are short (0.1-0.3 s simulated; a tune of 2 evaluations): what is checked is the
interface, the physics of each entry point has its own tests.
"""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from typer.testing import CliRunner

import webline
from webline.cli import app

pytestmark = pytest.mark.slow

LINES = ("hswl", "converter", "laminator", "slitter")

#: what every run's result offers, whatever its line (``webline.RunResult``)
RUN_METHODS = (
    "status",
    "message",
    "verdict",
    "signals",
    "metrics",
    "metric_arrays",
    "summary",
    "plot",
    "to_dataframe",
    "to_xarray",
    "to_csv",
    "to_netcdf",
    "span_names",
    "drive_names",
    "node_names",
    "roll_names",
    "tension",
    "tension_ref",
    "torque",
    "drive_speed",
    "roll_radius",
)
#: signals every run records under the same name
COMMON_SIGNALS = (
    "tension",
    "omega",
    "speed",
    "radius",
    "torque",
    "torque_cmd",
    "control_radius",
    "web_stored",
)


def a_length(line) -> str:
    """The path of the first span's length: a value every line has."""
    return "webs[0].spans[0].length" if line.branched else "spans[0].length"


def check_run(result, line) -> None:
    """``result`` is a ``RunResult`` of ``line`` with every name and method of one."""
    assert isinstance(result, webline.RunResult)
    for name in RUN_METHODS:
        assert hasattr(result, name), name
    assert result.status in ("ok", "warning")
    n = len(result.time)
    assert n > 1 and result.tension.shape == (n, len(result.span_names))
    ds = result.signals
    assert isinstance(ds, xr.Dataset) and set(COMMON_SIGNALS) <= set(ds.data_vars)
    assert ds["tension"].attrs["units"] == "N"
    np.testing.assert_array_equal(ds["tension"].values, result.tension)
    frame = result.to_dataframe()  # one row per record, one column per signal and element
    assert len(frame) == n and frame.index.name == "time"
    columns = {c.split("[")[0] for c in frame.columns}
    assert set(COMMON_SIGNALS) <= columns
    assert frame.attrs["units"][f"tension[{result.span_names[0]}]"] == "N"
    metrics = result.metrics()
    assert list(metrics.columns) == ["element", "metric", "value", "unit"]
    assert set(metrics.element) == {*result.span_names, *result.drive_names, *result.node_names}
    assert metrics.attrs["status"] == result.status
    summary = result.summary()
    assert set(summary) == {"spans", "drives"} and set(summary["spans"]) == set(result.span_names)
    for span, stats in summary["spans"].items():  # the statistics are the records'
        k = result.span_names.index(span)
        assert stats["mean"] == pytest.approx(result.tension[:, k].mean(), rel=1e-12)
    assert result.plot(("tension", "speed", "torque", "radius")).axes
    assert f"line {line.name!r}" in repr(result) and result.status in repr(result)


@pytest.fixture(scope="module", params=LINES)
def line(request):
    return webline.load_line(request.param)


def test_simulate_session_and_report(line, tmp_path: Path) -> None:
    from webline.report import write_report

    result = webline.simulate(line, 0.3)
    check_run(result, line)
    session = webline.Session(line)
    session.step(50)
    check_run(session.result(), line)
    assert type(session.result()) is type(result)
    files = write_report(result, tmp_path, units="imperial")
    assert files.report.read_text(encoding="utf-8").count(line.name) >= 1
    assert json.loads(files.summary.read_text(encoding="utf-8"))  # strict JSON


def test_sweep_and_monte_carlo_give_the_same_metrics(line) -> None:
    path = a_length(line)
    swept = webline.sweep(line, {path: ["2 m", "2.2 m"]}, duration=0.2)
    drawn = webline.monte_carlo(line, {path: "normal(1, 1 %)"}, 2, seed=1, duration=0.2)
    single = webline.simulate(line.replace({path: "2 m"}), 0.2)
    for ds in (swept, drawn):
        assert {
            "tension_rms_error",
            "tension_max",
            "slack_time",
            "torque_limit_time",
            "status",
        } <= set(ds.data_vars)
        assert list(ds["span"].values) == single.span_names
    # the sweep's first case is the same run as simulate's (the metrics of one definition)
    np.testing.assert_allclose(
        swept["tension_max"].values[0], single.metric_arrays()["tension_max"], rtol=1e-9
    )


def test_replay_and_fit(line, tmp_path: Path) -> None:
    # (long enough to identify: 5 time constants of the slowest loop, 1.25 s on converter)
    run = webline.simulate(line, 1.5)
    logged = run.to_csv(tmp_path / "results.csv")
    replayed = webline.replay(line, logged)
    tension = replayed.metrics[replayed.metrics.signal.str.startswith("tension[")]
    assert len(tension) == len(run.span_names)
    # the line replays its own log: each tension within 0.1 % of its mean (RMS; the replay
    # drives the line by the logged references, the run by the file's profiles)
    assert (tension.rms.values < 1e-3 * run.tension.mean(axis=0)).all(), tension
    drive = run.drive_names[-1]
    fitted = webline.fit(
        line, logged, {f"rollers.{drive}.friction": "0.001 .. 1 N*m*s"}, max_simulations=6
    )
    assert type(fitted).__name__ == "FitResult"
    for entry, extra in (("replay", []), ("fit", ["--free", f"rollers.{drive}.friction="
                                                  "0.001..1 N*m*s", "--max-simulations",
                                                  "10", "--starts", "1", "--accept-poor"])):
        done = CliRunner().invoke(app, [entry, line.name, str(logged), "--out",
                                        str(tmp_path / entry), *extra])
        assert done.exit_code == 0, done.output
        assert (tmp_path / entry / "report.html").is_file()


def test_experiment_and_analyze_commands(line, tmp_path: Path) -> None:
    runner = CliRunner()
    done = runner.invoke(
        app, ["experiment", line.name, "tension-step", "--out", str(tmp_path / "exp")]
    )
    assert done.exit_code == 0, done.output
    data = (
        webline.load_measurements(tmp_path / "exp" / "results.csv", line)
        if not line.branched
        else None
    )
    header = (tmp_path / "exp" / "results.csv").read_text(encoding="utf-8").splitlines()[0]
    assert re.search(r"tension\[[^\]]+\] \[N\]", header)
    assert data is None or data.names
    done = runner.invoke(app, ["analyze", line.name, "--json"])
    assert done.exit_code == 0, done.output
    assert json.loads(done.output)


def test_tune(line) -> None:
    scenario = "start-up" if line.branched else "startup"
    tuned = webline.tune(
        line,
        [scenario] if scenario in line.spec.scenarios else None,
        evaluations=2,
        samples=2,
        seed=0,
        workers=1,
    )
    assert type(tuned).__name__ == "TuneResult" and tuned.before.objective >= 0.0


def test_gym_make_with_randomize(line) -> None:
    import gymnasium

    import webline.gym  # noqa: F401  (registers webline/Line-v0)

    randomize = {a_length(line): "normal(1, 5 %)"}
    env = gymnasium.make("webline/Line-v0", line=line.name, duration=0.05, randomize=randomize)
    observation, _ = env.reset(seed=0)
    observation, reward, *_ = env.step(env.action_space.sample() * 0.0)
    assert np.all(np.isfinite(observation)) and np.isfinite(reward)


def test_benchmark_runs_its_fixed_set_of_single_path_cases() -> None:
    """``benchmark`` takes no line: its standard set is single-path lines' cases (so none of
    the branched lines); a controller that fails fails each of them, one row each."""
    from webline.studies.benchmark.standard_set import CASES

    class Zero:
        def reset(self, context) -> None:
            raise RuntimeError("no controller here")

        def __call__(self, t, measurements, references):
            raise AssertionError

    result = webline.benchmark([Zero], quick=True, builtin=False)
    assert {c.line for c in CASES} <= {"hswl", "converter"}
    assert set(result.runs_table.status) == {"failed"}


def test_a_branched_runs_tension_reference_is_what_its_drives_set() -> None:
    """The laminator's loadcell spans carry their drives' set tensions (the file's 120 N and
    60 N on the unwinds' zones, constant); the other spans none (NaN, as a single-path
    run's). Their PI loops hold the tension within 0.1 % of it at the end of a 1 s run, and
    the metrics' errors exist on exactly those spans."""
    result = webline.simulate("laminator", 1.0)
    ref = dict(zip(result.span_names, result.tension_ref.T, strict=True))
    np.testing.assert_array_equal(ref["film_zone"], 120.0)
    np.testing.assert_array_equal(ref["foil_zone"], 60.0)
    cells = {"film_zone", "foil_zone", "laminate_zone"}
    assert {name for name, r in ref.items() if np.all(np.isfinite(r))} == cells
    assert all(np.all(np.isnan(r)) for name, r in ref.items() if name not in cells)
    for name in cells:
        k = result.span_names.index(name)
        assert abs(result.tension[-1, k] / ref[name][-1] - 1.0) < 1e-3, name
    rms = result.metrics_by_element()["tension_rms_error"]
    assert {name for name, v in rms.items() if np.isfinite(v)} == cells
