"""``webline benchmark`` and ``webline.benchmark``: the quick subset ranks the built-in
families and the example user PI, which scores what the built-in PI scores; the outputs carry
the set's version and hash; a failing controller is scored "failed" in its case while the rest
goes on; bad input is one line, exit 2."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from typer.testing import CliRunner

import webline
from webline.cli import app
from webline.studies.benchmark.contenders import BUILTIN
from webline.studies.benchmark.scores import METRICS
from webline.studies.benchmark.standard_set import BENCHMARK_VERSION, cases, set_hash

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
USER_PI = f"{EXAMPLES / 'user_pi.py'}:CascadedPI"


@pytest.fixture(scope="module")
def quick_run(tmp_path_factory: pytest.TempPathFactory) -> tuple[object, Path]:
    out = tmp_path_factory.mktemp("benchmark")
    result = CliRunner().invoke(app, ["benchmark", "--quick", "--controller", USER_PI,
                                      "--out", str(out), "--quiet"])
    return result, out


def test_cli_quick_ranks_builtins_and_the_user_pi(quick_run) -> None:
    result, out = quick_run
    assert result.exit_code == 0, result.output
    names = [c.name for c in BUILTIN] + ["CascadedPI"]
    for name in names:  # the printed ranking lists every contender
        assert name in result.stdout
    table = pd.read_csv(out / "benchmark.csv")
    runs = pd.read_csv(out / "runs.csv")
    quick = cases(quick=True)
    assert set(runs.contender) == set(names) and set(runs.case) == {c.name for c in quick}
    assert len(runs) == len(names) * len(quick)  # no case dropped, none silently
    assert set(table.metric) <= set(METRICS) and set(table.unit) <= {m.unit for m in
                                                                     METRICS.values()}
    report = (out / "benchmark.md").read_text(encoding="utf-8")
    for metric in METRICS.values():  # each metric's definition is stated (| escaped)
        assert metric.definition.replace("|", "\\|") in report
    assert "Rule: " in report and "| 1 |" in report


def test_outputs_carry_the_version_and_the_set_hash(quick_run) -> None:
    _, out = quick_run
    digest = set_hash(cases(quick=True))
    for name in ("benchmark.csv", "runs.csv"):
        table = pd.read_csv(out / name, dtype=str)
        assert set(table.benchmark_version) == {BENCHMARK_VERSION}
        assert set(table.set_hash) == {digest}
        assert set(table.webline_version) == {webline.__version__}
    report = (out / "benchmark.md").read_text(encoding="utf-8")
    assert f"v{BENCHMARK_VERSION}" in report and digest in report
    assert webline.__version__ in report


def test_user_pi_scores_what_the_builtin_pi_scores(quick_run) -> None:
    """examples/user_pi.py is the built-in cascaded PI in Python and reproduces its runs to
    round-off (docs/controllers.md), so every metric of every quick case agrees to 1e-9
    relative (a settling time of exactly 0 to 1e-12 absolute)."""
    _, out = quick_run
    table = pd.read_csv(out / "benchmark.csv")
    builtin = table[table.contender == "cascaded PI"].set_index(["case", "metric"]).value
    user = table[table.contender == "CascadedPI"].set_index(["case", "metric"]).value
    assert len(builtin) == len(user) > 10
    user = user.loc[builtin.index]
    np.testing.assert_allclose(user.to_numpy(), builtin.to_numpy(), rtol=1e-9, atol=1e-12)


class RaisesAboveSpeed:
    """The example PI, which raises once the speed reference passes 4 m/s (only the
    speed-change case goes there: 1000 ft/min = 5.08 m/s)."""

    def __init__(self) -> None:
        import importlib.util

        spec = importlib.util.spec_from_file_location("bench_user_pi", EXAMPLES / "user_pi.py")
        assert spec is not None and spec.loader is not None
        module = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(module)
        self.inner = module.CascadedPI()

    def reset(self, context) -> None:
        self.inner.reset(context)
        self.speed = context.index(f"{context.drives[0].name}.speed_reference")

    def __call__(self, t, measurements, references):
        if references[self.speed] > 4.0:
            raise RuntimeError("gain table ends at 4 m/s")
        return self.inner(t, measurements, references)


class ReturnsNaN:
    def reset(self, context) -> None:
        self.torques = np.array([d.equilibrium_command for d in context.drives])

    def __call__(self, t, measurements, references):
        return self.torques * (math.nan if t > 0.5 else 1.0)


class ResetRaises(ReturnsNaN):
    def reset(self, context) -> None:
        raise RuntimeError("no gains for this line")


def test_a_failing_controller_fails_its_case_and_the_rest_goes_on() -> None:
    result = webline.benchmark({"raises": RaisesAboveSpeed, "nan": ReturnsNaN(),
                                "reset": ResetRaises()}, quick=True, builtin=False)
    runs = result.runs_table.set_index(["case", "contender"])
    failed = runs.loc[("hswl/speed-change", "raises")]
    assert failed.status == "failed"
    assert "controller" in failed.note and "RuntimeError: gain table ends at 4 m/s" in \
        failed.note and "at tick" in failed.note
    assert runs.loc[("hswl/tension-step", "raises")].status == "ok"
    assert runs.loc[("hswl/monte-carlo", "raises")].status == "ok"
    assert set(runs.xs("nan", level="contender").status) == {"failed"}
    assert "non-finite torque" in runs.loc[("hswl/tension-step", "nan")].note
    assert set(runs.xs("reset", level="contender").status) == {"failed"}
    assert "RuntimeError: no gains for this line" in runs.loc[("hswl/tension-step",
                                                                "reset")].note
    ranking = result.ranking.set_index("contender")
    assert ranking.loc["raises", "failed"] == 1 and ranking.loc["nan", "failed"] == 3
    assert ranking.loc["raises", "place"] == 1  # fewer failures, better ranks


@pytest.mark.parametrize(("spec", "fragment"), [
    ("nofile.py:X", "no file nofile.py"),
    (f"{EXAMPLES / 'user_pi.py'}:Missing", "has no 'Missing'"),
    ("math:pi", "neither a controller"),
    ("no_colon", "expected FILE.py:NAME"),
])
def test_bad_controller_is_one_line_exit_2(tmp_path: Path, spec: str, fragment: str) -> None:
    result = CliRunner().invoke(app, ["benchmark", "--quick", "--controller", spec,
                                      "--out", str(tmp_path / "out")])
    assert result.exit_code == 2, result.output
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: ") and fragment in lines[0]
    assert not (tmp_path / "out").exists()  # refused before anything ran or was written


def test_no_contenders_is_one_line_exit_2(tmp_path: Path) -> None:
    result = CliRunner().invoke(app, ["benchmark", "--no-builtin", "--out",
                                      str(tmp_path / "out")])
    assert result.exit_code == 2 and result.stderr.count("\n") == 1
    assert "--no-builtin needs at least one --controller" in result.stderr
    assert not (tmp_path / "out").exists()


def test_a_family_the_line_refuses_is_na_with_its_reason() -> None:
    """The converter's dancer trims a cascaded PI, so the decentralized families are n/a
    there, with the line's own reason; the case keeps their rows (nothing silently dropped)
    and they are left out of its ranks. Nothing is simulated: the refusal comes first."""
    from webline.studies.benchmark.records import case_ranks
    from webline.studies.benchmark.run import case_lines, run_case
    from webline.studies.benchmark.standard_set import CASES

    case = next(c for c in CASES if c.name == "converter/flying-splice")
    lines = case_lines(case)
    runs = [run_case(case, lines, c) for c in BUILTIN if c.name != "cascaded PI"]
    assert {r.status for r in runs} == {"n/a"}
    assert all("dancer" in r.note and r.scores == {} for r in runs)
    assert case_ranks(runs, [case]).empty


def test_api_result_has_a_tidy_table_and_a_report() -> None:
    result = webline.benchmark([ReturnsNaN], quick=True, builtin=False)
    assert isinstance(result.table, pd.DataFrame) and result.table.empty  # all failed
    assert list(result.runs_table.status) == ["failed"] * len(cases(quick=True))
    report = result.to_markdown()
    assert "ReturnsNaN" in report and "non-finite torque" in report
