"""``webline analyze`` of a branched line: operating point, closed-loop modes and the verdict,
computed from the linear model (docs/branching.md, "Linear models")."""

from __future__ import annotations

import json

import numpy as np
from typer.testing import CliRunner

from webline.cli import app
from webline.sim.branches.linear import linear_model


def _run(*args: str):
    return CliRunner().invoke(app, list(args))


def test_analyze_laminator_prints_its_modes_and_a_stable_verdict():
    result = _run("analyze", "laminator")
    assert result.exit_code == 0, result.output
    assert "Closed-loop modes" in result.output and "verdict: ok" in result.output
    assert "rewind_tension_integral" in result.output  # the slowest mode's dominant state


def test_analyze_json_modes_are_the_linear_model_eigenvalues():
    result = _run("analyze", "slitter", "--scenario", "start-up", "--json")
    assert result.exit_code == 0, result.output
    payload = json.loads(result.output)
    # a start from rest is analysed at the end of its ramp (1 s + 10 s), at top speed
    assert payload["analysis_time_s"] == 11.0
    speeds = {r["roller"]: r["speed_m_s"] for r in payload["operating_point"]["rollers"]}
    assert abs(speeds["pull"] - 5.0) < 1e-9  # the master at 300 m/min
    values = np.linalg.eigvals(linear_model("slitter").a)  # same references at top speed
    listed = [complex(m["eigenvalue_real"], m["eigenvalue_imag"])
              for m in payload["closed_loop_modes"]]
    upper = values[values.imag >= 0.0]
    assert len(listed) == len(upper)
    # the same matrix (at rest-then-ramped the line is the plain one at 300 m/min): each
    # printed mode is an eigenvalue to round-off (1e-9 of the largest, |λ| ~ 640 1/s)
    for value in listed:
        assert np.min(np.abs(upper - value)) < 1e-9 * np.max(np.abs(values))
    assert payload["verdict"]["status"] == "ok"


def test_analyze_branched_refuses_what_it_does_not_support_in_one_line():
    result = _run("analyze", "slitter", "--across-roll")
    assert result.exit_code == 2
    assert "--across-roll: not yet supported for a branched line" in result.output
    assert "Traceback" not in result.output


def test_analyze_finds_an_overtuned_tension_loop_unstable_as_the_run_does(tmp_path):
    import tomllib
    from pathlib import Path

    import tomli_w

    from webline.data import lines
    from webline.sim.branches.run import simulate_branches

    data = tomllib.loads((Path(lines.__file__).parent / "laminator.toml").read_text())
    data.pop("scenarios")
    rewind = next(r for r in data["rollers"] if r["name"] == "rewind")
    rewind["controller"]["tension_kp"] = 3e-3  # [(m/s)/N], 40x the tuned 7.6e-5
    path = tmp_path / "overtuned.toml"
    path.write_bytes(tomli_w.dumps(data).encode())
    result = _run("analyze", str(path))
    assert result.exit_code == 3, result.output
    # the model: a 38.6 Hz mode growing at +18.5 1/s, in the laminate zone's states
    assert "verdict: unstable" in result.output and "38.6 Hz" in result.output
    # the run agrees: from the operating point (deviations ~1e-4 N) the laminate zone's
    # tension swings by more than 10 N within 0.4 s (the stock line: < 1e-3 N in 10 ms and a
    # 0.022 N ramp over 2 s, tests/integration/test_branches.py)
    ds = simulate_branches(data, 0.4, raise_on_failure=False).dataset
    swing = np.ptp(ds["tension"].sel(span="laminate_zone").values)
    assert swing > 10.0
