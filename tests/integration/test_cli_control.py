"""CLI access to the Ch. 6 controllers and certificate (issue 5)."""

from __future__ import annotations

import json

import xarray as xr
from typer.testing import CliRunner

from webline.cli import app


def invoke(*args: str):
    return CliRunner().invoke(app, list(args), catch_exceptions=False)


def test_run_with_each_controller_family(tmp_path):
    final_errors = {}
    for family in ("pi", "state-feedback", "adaptive", "mrac"):
        out = tmp_path / family
        result = invoke("run", "hswl", "--duration", "2", "--controller", family, "--out",
                        str(out), "--quiet")
        assert result.exit_code == 0, result.output
        data = xr.open_dataset(out / "results.nc")
        final_errors[family] = float(abs(data.tension - data.tension_ref).max("span")[-1])
        # the decentralized controllers record their equilibrium input, the PI does not
        assert (float(abs(data.equilibrium_input).max()) > 0) == (family != "pi")
        data.close()
    # from equilibrium with constant references every family holds the tensions
    assert max(final_errors.values()) < 1e-3


def test_unknown_controller_family_is_bad_input():
    result = CliRunner().invoke(app, ["run", "hswl", "--controller", "fuzzy"])
    assert result.exit_code == 2
    assert "Traceback" not in result.output


def test_analyze_certificate_json():
    result = invoke("analyze", "hswl", "--certificate", "--json")
    assert result.exit_code == 0, result.output
    cert = json.loads(result.output)["certificate"]
    assert [s["section"] for s in cert["sections"]] == ["unwind", "master", "process", "rewind"]
    assert all(s["N"] == 3 for s in cert["sections"])  # N = sections - 1 (E-6.12)
    # wherever the certificate holds, the interconnected sections are stable
    if cert["holds"]:
        assert cert["max_real"] < 0
    assert cert["worst_ratio"] == min(s["ratio"] for s in cert["sections"])


def test_certificate_of_a_line_that_cannot_run_state_feedback_says_why():
    """The converter's dancer trims a PI's speed (position control): Thm 6.2.1's state
    feedback cannot run there. One line naming the option and the reason, exit 2."""
    result = invoke("analyze", "converter", "--certificate")
    assert result.exit_code == 2
    lines = result.output.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: --certificate: thesis Thm 6.2.1")
    assert "dancer.use" in lines[0]


def test_analysis_time_takes_units_as_run_takes_its_duration():
    as_number = json.loads(invoke("analyze", "hswl", "-t", "2", "--json").output)
    with_unit = json.loads(invoke("analyze", "hswl", "-t", "2000 ms", "--json").output)
    assert as_number["operating_point"] == with_unit["operating_point"]
    negative = invoke("analyze", "hswl", "-t", "-1")
    assert negative.exit_code == 2 and "--time: must be >= 0 s" in negative.output
