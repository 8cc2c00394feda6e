"""``webline taper`` on the built-in converter (docs/wound-roll.md, "Taper for a good roll"):
the designed taper meets the roll's limits in the simulated roll, and a taper it rejects
breaks them."""

from __future__ import annotations

import pytest
from typer.testing import CliRunner

import webline
from webline.cli import app
from webline.line import load_line

# PET film stack (Pfeiffer K1, K2 assumed, docs/wound-roll.md), fibre core, and a stated hoop
# compression limit of 0.2 MPa
ROLL = (
    '{k1 = "1.5 kPa", k2 = 120, core = {modulus = "3 GPa", inner_radius = "76 mm"}, '
    'min_hoop = "-0.2 MPa"}'
)


@pytest.fixture(scope="module")
def designed(tmp_path_factory: pytest.TempPathFactory) -> tuple[object, str]:
    out = tmp_path_factory.mktemp("taper") / "converter-taper.toml"
    run = CliRunner().invoke(
        app,
        [
            "taper",
            "converter",
            "--set",
            f"rollers.rewind.roll_stress={ROLL}",
            "-o",
            str(out),
            "--duration",
            "4 s",
        ],
    )
    return run, str(out)


def test_designed_taper_meets_the_limits_in_the_simulated_roll(designed) -> None:
    run, out = designed
    assert run.exit_code == 0, run.output
    assert "meets the limits" in run.output
    line = load_line(out)  # the file runs as it is
    taper = line.rewind.taper
    assert taper is not None and taper.type == "hyperbolic"
    assert 0.1 < taper.taper < 0.6  # film is wound with 20-40 % taper (docs/winder.md)
    result = webline.simulate(line, 4.0)
    assert not [
        f for f in result.verdict.findings if f.kind in ("roll_hoop", "roll_pressure", "roll_core")
    ]
    assert result.wound_roll.stress.hoop.min() >= -0.2e6


def test_a_rejected_taper_breaks_them(designed) -> None:
    _, out = designed
    line = load_line(out)
    less = line.replace({"rollers.rewind.taper.taper": line.rewind.taper.taper - 0.05})
    result = webline.simulate(less, 4.0)
    hoop = [f for f in result.verdict.findings if f.kind == "roll_hoop"]
    assert len(hoop) == 1 and hoop[0].details["min_hoop_Pa"] < -0.2e6
    assert result.status == "warning"


def test_no_roll_stress_table_is_one_clear_line() -> None:
    run = CliRunner().invoke(app, ["taper", "converter"])
    assert run.exit_code == 2
    assert "roll_stress" in run.output and "Traceback" not in run.output


@pytest.mark.parametrize(
    ("args", "says"),
    [
        (["--form", "spiral"], "--form 'spiral'"),
        (["--diameter", "big"], "--diameter 'big'"),
        (["--diameter", "0.1 m"], "must be larger than the core"),
        (["--roll", "unwind"], "--roll 'unwind': converter winds one roll, on 'rewind'"),
    ],
)
def test_bad_options_are_one_clear_line(args: list[str], says: str, tmp_path) -> None:
    run = CliRunner().invoke(
        app,
        [
            "taper",
            "converter",
            "--set",
            f"rollers.rewind.roll_stress={ROLL}",
            "-o",
            str(tmp_path / "x.toml"),
            "--no-check",
            *args,
        ],
    )
    assert run.exit_code == 2, run.output
    assert says in run.output and "Traceback" not in run.output
