"""`webline replay` and `webline fit` (issue 24 items 1-3): outputs, and one clear line with
exit 2 for each kind of bad measurement file."""

from __future__ import annotations

import json

import numpy as np
import pytest
from typer.testing import CliRunner

from webline.cli import app
from webline.twin.traces.synthetic import synthetic_csv


def invoke(*args: str):
    return CliRunner().invoke(app, list(args))


@pytest.fixture(scope="module")
def log(tmp_path_factory):
    return synthetic_csv(tmp_path_factory.mktemp("log") / "log.csv", "converter",
                         changes={"rollers.infeed.inertia": 0.7}, duration=4.0,
                         scenario="startup", offset=12.0, seed=4)


def test_replay_writes_metrics_and_report(log, tmp_path):
    result = invoke("replay", "converter", str(log), "-s", "startup", "-o", str(tmp_path / "r"))
    assert result.exit_code == 0, result.output
    metrics = (tmp_path / "r" / "metrics.csv").read_text().splitlines()
    assert metrics[0] == "signal,unit,points,rms,max_abs,nrmse,bias,r2"
    assert len(metrics) == 1 + 4 + 8 + 5  # 4 loadcells, 8 roller speeds, 5 torques
    assert "time offset 12 s removed" in result.stdout
    assert (tmp_path / "r" / "report.html").stat().st_size > 10_000  # the inlined figure


def test_fit_writes_fitted_line_and_json(log, tmp_path):
    out = tmp_path / "f"
    result = invoke("fit", "converter", str(log), "-s", "startup", "--free",
                    "rollers.infeed.inertia=0.1..2 kg*m**2", "-o", str(out))
    assert result.exit_code == 0, result.output
    data = json.loads((out / "fit.json").read_text())
    entry = data["parameters"]["rollers.infeed.inertia"]
    assert entry["identifiable"] and entry["ci95"][0] <= 0.7 <= entry["ci95"][1]
    assert (out / "fitted.toml").exists() and (out / "report.html").exists()


POOR = ("--starts", "2", "--free", "rollers.infeed.inertia=0.1..0.5 kg*m**2")


@pytest.fixture(scope="module")
def poor(log, tmp_path_factory):
    """The infeed's inertia is 0.7 kg m² in the log; bounds that stop at 0.5 leave it on its
    upper bound with residuals above the noise: a poor fit (issue 36 item 1)."""
    out = tmp_path_factory.mktemp("poor") / "fit"
    result = invoke("fit", "converter", str(log), "-s", "startup", *POOR, "-o", str(out))
    return result, out


def test_a_poor_fit_exits_4_and_says_so_in_every_file(poor, log, tmp_path):
    """Exit 4, POOR in fitted.toml and the report, the reasons in fit.json; --accept-poor
    exits 0."""
    result, out = poor
    assert result.exit_code == 4, result.output
    assert "warning: POOR FIT" in result.stderr and "at its upper bound" in result.stderr
    data = json.loads((out / "fit.json").read_text())
    assert data["verdict"] == "poor" and data["residual_scale"] > 1.5
    assert any("rollers.infeed.inertia at its upper bound" in r for r in data["reasons"])
    entry = data["parameters"]["rollers.infeed.inertia"]
    assert entry["at_bound"] == "high" and entry["interval"] == "one-sided"
    assert entry["ci95"][1] == pytest.approx(0.5)  # one-sided: up to the bound
    text = (out / "fitted.toml").read_text()
    assert "# VERDICT: POOR" in text and "POOR FIT to log.csv, not to be trusted" in text
    assert "95 % interval" not in text
    assert "POOR FIT" in (out / "report.html").read_text()
    accepted = invoke("fit", "converter", str(log), "-s", "startup", *POOR, "--accept-poor",
                      "-o", str(tmp_path / "accepted"))
    assert accepted.exit_code == 0, accepted.output


def test_tune_refuses_a_poor_fit(poor, tmp_path):
    """tune --fit builds on good fits only (issue 36 item 8): one line naming the file, the
    verdict and the way out, exit 2, before any candidate is simulated."""
    _, out = poor
    result = invoke("tune", "converter", "--fit", str(out / "fit.json"), "--out",
                    str(tmp_path / "tuned"))
    assert result.exit_code == 2, result.output
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and "fit.json: verdict: the fit is poor" in lines[0], result.stderr
    assert "--poor-fit widen" in lines[0]
    assert not (tmp_path / "tuned" / "tune.json").exists()


def bad_file(tmp_path, header, rows):
    path = tmp_path / "bad.csv"
    path.write_text(",".join(header) + "\n" + "\n".join(
        ",".join(f"{v:g}" for v in row) for row in rows) + "\n")
    return path


T = np.arange(0.0, 3.0, 0.01)
CASES = {
    "wrong unit": (["time [s]", "tension[process_span] [m/s]"], np.column_stack([T, T]),
                   "not a force"),
    "unknown column": (["time [s]", "tension[proces_span] [N]"], np.column_stack([T, T]),
                       "matches no signal"),
    "non-monotonic time": (["time [s]", "tension[process_span] [N]"],
                           np.column_stack([T[::-1], T]), "does not increase"),
    "too short": (["time [s]", "tension[process_span] [N]"],
                  np.column_stack([T[:30], T[:30]]), "too short to identify anything"),
}


@pytest.mark.parametrize("command", ["replay", "fit"])
@pytest.mark.parametrize("case", list(CASES))
def test_bad_measurement_files_one_line_exit_2(tmp_path, case, command):
    header, rows, fragment = CASES[case]
    path = bad_file(tmp_path, header, rows)
    extra = ["--free", "rollers.infeed.inertia=0.1..2 kg*m**2"] if command == "fit" else []
    result = invoke(command, "converter", str(path), *extra, "-o", str(tmp_path / "o"))
    assert result.exit_code == 2, result.output
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: "), result.stderr
    assert "bad.csv" in lines[0] and fragment in lines[0]
    assert "Traceback" not in result.output


def test_a_bad_free_option_is_one_line_exit_2(log, tmp_path):
    result = invoke("fit", "converter", str(log), "--free", "rollers.nope.inertia=1..2",
                    "-o", str(tmp_path / "o"))
    assert result.exit_code == 2
    assert len(result.stderr.strip().splitlines()) == 1
