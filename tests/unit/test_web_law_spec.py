"""``web.stress_strain`` in a line file: each bad law is one line naming the file and the key,
exit 2 (docs/line-file.md, web.stress_strain)."""

from __future__ import annotations

from importlib import resources
from pathlib import Path

import pytest
from typer.testing import CliRunner

from webline.cli import app

HSWL = resources.files("webline.data.lines").joinpath("hswl.toml").read_text("utf-8")
TABLE = 'law = "table"\nstrain = [0.0, 0.01, 0.02]\n'

BAD = {
    "not monotonic": (TABLE + 'stress = ["0 MPa", "30 MPa", "20 MPa"]', True,
                      "web.stress_strain.stress[2]: must increase with strain"),
    "strain not increasing": ('law = "table"\nstrain = [0.0, 0.02, 0.01]\n'
                              'stress = ["0 MPa", "30 MPa", "40 MPa"]', True,
                              "web.stress_strain.strain[2]: strains must increase"),
    "negative strain": ('law = "table"\nstrain = [0.0, -0.01]\nstress = ["0 MPa", "30 MPa"]',
                        True, "web.stress_strain.strain[1]"),
    "stress in newtons": (TABLE + 'stress = ["0 MPa", "30 N", "40 MPa"]', True,
                          "web.stress_strain.stress[1]: expected a pressure"),
    "not from the origin": ('law = "table"\nstrain = [0.001, 0.01]\n'
                            'stress = ["0 MPa", "30 MPa"]', True,
                            "web.stress_strain.strain: the table starts at strain 0"),
    "both columns": (TABLE + 'stress = ["0 MPa", "30 MPa", "40 MPa"]\n'
                     'tension_per_width = [0, 500, 600]', True, "exactly one of 'stress'"),
    "table and modulus": (TABLE + 'stress = ["0 MPa", "30 MPa", "40 MPa"]', False,
                          "web.modulus: a table law gives the web's stiffness itself"),
    "power without exponent": ('law = "power"\nreference_strain = 0.01', False,
                               "web.stress_strain.exponent: a 'power' law needs its exponent"),
    "key of another law": ('law = "linear"\nexponent = 2.0', False,
                           "web.stress_strain.exponent: a 'linear' law has no exponent"),
    "no hardening": ('law = "bilinear"\nyield_strain = 0.01\nhardening = 0', False,
                     "web.stress_strain.hardening: must be > 0"),
    "unknown law": ('law = "cubic"', False, "web.stress_strain.law"),
}


def line_file(tmp_path: Path, law: str, drop_ea: bool) -> str:
    text = HSWL.replace('ea = "2000 lbf"\n', "" if drop_ea else 'ea = "2000 lbf"\n')
    text = text.replace("[control]\n", f"[web.stress_strain]\n{law}\n\n[control]\n", 1)
    path = tmp_path / "law.toml"
    path.write_text(text, encoding="utf-8")
    return str(path)


@pytest.mark.parametrize("case", sorted(BAD))
def test_bad_law_is_one_line_naming_file_and_key(tmp_path, case):
    law, drop_ea, fragment = BAD[case]
    result = CliRunner().invoke(app, ["validate", line_file(tmp_path, law, drop_ea)])
    assert result.exit_code == 2, result.output
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in result.output
    assert "law.toml" in lines[0] and fragment in lines[0], lines[0]


def test_good_laws_validate(tmp_path):
    for law, drop_ea in ((TABLE + 'tension_per_width = ["0 pli", "3 pli", "5 pli"]', True),
                         ('law = "power"\nexponent = 1.4\nreference_strain = 0.005', False),
                         ('law = "bilinear"\nyield_strain = 0.01\nhardening = 0.2', False)):
        result = CliRunner().invoke(app, ["validate", line_file(tmp_path, law, drop_ea)])
        assert result.exit_code == 0, result.output


def test_show_states_the_law(tmp_path):
    law = 'law = "power"\nexponent = 1.4\nreference_strain = 0.005\nyield_strain = 0.02'
    result = CliRunner().invoke(app, ["show", line_file(tmp_path, law, False)])
    assert result.exit_code == 0, result.output
    assert "power: σ = E ε_r (ε/ε_r)^1.4, ε_r = 0.005, yield at ε = 2 %" in result.output


def test_web_mass_is_stated_where_it_is_a_share_of_the_tension(tmp_path):
    """hswl at 4000 ft/min (20.3 m/s): ρA v² = 1390 x 12.7 µm x 6 in x 20.3² = 1.11 N, 1.7 %
    of its lowest tension, so validate says the span model leaves it out; the built-in lines
    at their speeds (<= 0.7 %) say nothing."""
    import webline

    for name in ("hswl", "rockwell", "converter"):
        assert not [w for w in webline.load_line(name).warnings if "momentum" in w]
    fast = webline.load_line("hswl").replace(speed="4000 ft/min")
    found = [w for w in fast.warnings if "momentum" in w]
    web = fast.spec.web
    flux = web.density * web.thickness * web.width * (4000 * 0.3048 / 60) ** 2
    assert len(found) == 1 and f"ρA v² = {flux:.4g} N" in found[0]
    path = tmp_path / "fast.toml"
    path.write_text(HSWL.replace('speed = "500 ft/min"', 'speed = "4000 ft/min"', 1),
                    encoding="utf-8")
    result = CliRunner().invoke(app, ["validate", str(path)])
    assert result.exit_code == 0 and "momentum flux ρA v²" in result.output, result.output
