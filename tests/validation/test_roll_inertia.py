"""A roll's inertia given as drives specify it (issue 21 item 8, docs/winder.md "Roll inertia
from totals", J1): totals at stated diameters, the core inertia and wound density derived.

Source: thesis Table 6.1 gives J0 = 8 lb-ft² (unwind, R0 = 1.25 ft) and J3 = 4 lb-ft²
(rewind, R3 = 0.67 ft), and says J0 is the initial value, updated with (6.1)-(6.2): totals.
"""

from __future__ import annotations

import math

import pytest
from typer.testing import CliRunner

import webline
from webline.cli import app
from webline.errors import LineFileError
from webline.model.operating_point import operating_point
from webline.spec.load import dump_spec, parse_text

LB_FT2 = 0.45359237 * 0.3048**2  # 1 lb·ft² (pound-mass) in kg·m²
FT = 0.3048
#: Table 6.1 read as two rolls of the same hardware and web: the roll weighs 4 lb-ft² at
#: 2 R3 = 1.34 ft and 8 lb-ft² at 2 R0 = 2.5 ft (docs/winder.md)
TABLE_6_1 = {"type": "totals", "empty": "4 lb*ft**2", "empty_diameter": "1.34 ft",
             "full": "8 lb*ft**2", "full_diameter": "2.5 ft"}


@pytest.fixture(scope="module")
def table_line():
    line = webline.load_line("hswl")
    return line.replace({"rollers.unwind.inertia": TABLE_6_1,
                         "rollers.rewind.inertia": TABLE_6_1})


def test_table_6_1_rolls_entered_as_totals_give_the_thesis_inertias(table_line):
    """J0 = 8 and J3 = 4 lb-ft² at the table's radii, in the operating point and in the
    compiled loop's own inertia (Result.inertia at t = 0). 1e-12: J1 recombines the totals
    with a few roundings (~1e-16 each); a misread diameter (radius for diameter) is 15x off."""
    op = operating_point(table_line)
    assert op.radius[0] == pytest.approx(1.25 * FT, rel=1e-15)
    assert op.radius[-1] == pytest.approx(0.67 * FT, rel=1e-15)
    assert op.inertia[0] == pytest.approx(8 * LB_FT2, rel=1e-12, abs=0)
    assert op.inertia[-1] == pytest.approx(4 * LB_FT2, rel=1e-12, abs=0)
    result = webline.simulate(table_line, 0.002)
    assert result.inertia[0, 0] == pytest.approx(8 * LB_FT2, rel=1e-12, abs=0)
    assert result.inertia[0, 1] == pytest.approx(4 * LB_FT2, rel=1e-12, abs=0)


def test_the_derived_core_and_density_solve_j1_by_hand(table_line):
    """J1 with two totals: (π/32) ρ w = ΔJ / ΔD⁴ and J_c = J_a - (π/32) ρ w (D_a⁴ - D_c⁴),
    computed here independently; webline says what it derived (Line.notes)."""
    factor = 4 * LB_FT2 / ((2.5 * FT) ** 4 - (1.34 * FT) ** 4)
    width = 6 * 0.0254
    core = 4 * LB_FT2 - factor * ((1.34 * FT) ** 4 - (6 * 0.0254) ** 4)
    density = factor * 32 / (math.pi * width)
    assert density == pytest.approx(36.42, abs=0.01)  # far below PET's 1390: a light roll
    note = table_line.notes[0]
    assert f"{core:.6g} kg*m**2" in note and f"wound density {density:.6g}" in note
    # between the two totals the roll grows with D⁴ as (6.2) says
    op = operating_point(table_line, unwind_radius=0.3)
    assert op.inertia[0] == pytest.approx(core + factor * (0.6**4 - (6 * 0.0254) ** 4),
                                          rel=1e-12)


def test_totals_of_the_web_reproduce_the_plain_reading():
    """Limiting case: hswl's rolls entered as the totals its own core inertia and web give
    (empty at the core, full at 0.8 m; and one total at 0.5 m with the web's density) are
    the same rolls: inertias equal at every radius to 1e-12."""
    line = webline.load_line("hswl")
    base = operating_point(line, unwind_radius=0.2, rewind_radius=0.25)
    web = line.spec.web

    def total(j_core, diameter, core_radius):
        return j_core + math.pi / 32 * web.density * web.width * (diameter**4
                                                                 - (2 * core_radius) ** 4)

    unwind, rewind = line.unwind, line.rewind
    changes = {
        "rollers.unwind.inertia": {"type": "totals", "empty": unwind.inertia,
                                   "full": total(unwind.inertia, 0.8, unwind.core_radius),
                                   "full_diameter": 0.8},
        "rollers.rewind.inertia": {"type": "total", "diameter": 0.5,
                                   "total": total(rewind.inertia, 0.5, rewind.core_radius)},
    }
    same = operating_point(line.replace(changes), unwind_radius=0.2, rewind_radius=0.25)
    assert same.inertia == pytest.approx(base.inertia, rel=1e-12, abs=0)


def test_totals_round_trip_through_a_dump(table_line):
    spec = table_line.spec
    assert parse_text(dump_spec(spec), "again.toml") == spec


@pytest.mark.parametrize(("inertia", "key", "words"), [
    ({"type": "total", "total": "8 lb*ft**2", "diameter": "2.5 ft"}, "rollers[0].inertia",
     "outweighs the total"),  # PET at 1390 kg/m³ weighs 166 lb-ft² on that roll
    ({**TABLE_6_1, "full": "3 lb*ft**2"}, "rollers[0].inertia.full", "heavier"),
    ({**TABLE_6_1, "empty_diameter": "2 in"}, "rollers[0].inertia.empty_diameter", "core"),
])
def test_totals_that_describe_no_roll_are_refused(inertia, key, words):
    line = webline.load_line("hswl")
    with pytest.raises(LineFileError) as error:
        line.replace({"rollers.unwind.inertia": inertia})
    assert key in str(error.value) and words in str(error.value)


def test_validate_says_what_it_derived(tmp_path):
    from pathlib import Path

    text = (Path(webline.__file__).parent / "data" / "lines" / "hswl.toml").read_text()
    text = text.replace('inertia = "8 lb*ft**2"', 'inertia = { type = "totals", empty = '
                        '"4 lb*ft**2", empty_diameter = "1.34 ft", full = "8 lb*ft**2", '
                        'full_diameter = "2.5 ft" }')
    path = tmp_path / "table61.toml"
    path.write_text(text)
    out = CliRunner().invoke(app, ["validate", str(path)])
    assert out.exit_code == 0, out.output
    assert "note:" in out.output and "unwind: inertia from its empty and full totals" in out.output
