"""The nip table of a roller (docs/line-file.md, nip): its checks name the key and the problem,
the spec round-trips, and the CLI refuses a bad nip in one line with exit 2."""

from __future__ import annotations

import pytest
from typer.testing import CliRunner

import webline
from webline.cli import app
from webline.errors import LineFileError
from webline.spec.load import dump_spec, spec_from_dict

NIP = {"load": "600 N", "radius": "40 mm", "inertia": "0.01 kg*m**2"}
TRACTION = {"type": "traction", "friction": 0.2, "viscous": "2000 N*s/m"}


def converter_with(roller: str, **keys: object) -> dict:
    data = webline.load_line("converter").spec.model_dump(exclude_none=True)
    index = next(i for i, r in enumerate(data["rollers"]) if r["name"] == roller)
    data["rollers"][index].update(keys)
    return data


@pytest.mark.parametrize(("roller", "keys", "key", "problem"), [
    ("dancer", {"nip": NIP}, "rollers[1].nip", "a dancer carries no nip"),
    ("infeed", {"nip": {**NIP, "grip": "traction"}, "contact": TRACTION, "wrap": 1.0},
     "rollers[3].nip.friction", "needs its friction coefficient"),
    ("infeed", {"nip": {**NIP, "grip": "traction", "friction": 0.5}},
     "rollers[3].nip.grip", "give the roller a traction contact"),
    ("infeed", {"nip": {**NIP, "grip": "traction", "friction": 0.5, "kinetic_friction": 0.6},
                "contact": TRACTION, "wrap": 1.0},
     "rollers[3].nip.kinetic_friction", "must not exceed the static friction 0.5"),
    ("guide_in", {"nip": NIP, "contact": TRACTION, "wrap": 1.0},
     "rollers[2].nip.grip", "contradicts the roller's traction contact"),
    ("infeed", {"nip": {**NIP, "load": "-3 N"}}, "rollers[3].nip.load", "must be > 0"),
    ("infeed", {"nip": {**NIP, "grip": "sticky"}}, "rollers[3].nip.grip", "gripped"),
])
def test_a_bad_nip_names_its_key(roller, keys, key, problem):
    with pytest.raises(LineFileError) as info:
        webline.load_line(converter_with(roller, **keys))
    text = str(info.value)
    assert key in text and problem in text, text


def test_a_nip_round_trips_and_is_on_an_idle_roller_too():
    data = converter_with("guide_out", nip={**NIP, "bearing_friction": "1e-3 N*m*s"})
    line = webline.load_line(data)
    nip = line.spec.rollers[6].nip
    assert (nip.load, nip.radius, nip.grip, nip.bearing_friction) == (600.0, 0.04, "gripped",
                                                                      1e-3)
    import tomllib

    assert spec_from_dict(tomllib.loads(dump_spec(line.spec))) == line.spec


def test_cli_refuses_a_bad_nip_in_one_line(tmp_path):
    import tomli_w

    path = tmp_path / "bad.toml"
    path.write_text(tomli_w.dumps(converter_with("dancer", nip=NIP)), encoding="utf-8")
    result = CliRunner().invoke(app, ["validate", str(path)])
    assert result.exit_code == 2
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and "rollers[1].nip" in lines[0] and "Traceback" not in result.output


def test_show_and_the_schematic_show_the_nip():
    """The roller table gains a nip column only for a line with a nip, with its load, grip and
    the inertia it adds (0.08 (100/60)² = 0.2222 kg·m²); the schematic draws one more circle."""
    from matplotlib.patches import Circle

    from webline.report.plots.schematic import schematic
    from webline.report.text.describe import line_tables
    from webline.report.text.display import Display

    def rollers(line):
        return next(t for t in line_tables(line, Display()) if t.key == "rollers")

    converter = webline.load_line("converter")
    table = rollers(converter)
    assert table.columns[-1] == "nip"
    infeed = table.rows[3][-1]
    assert infeed.startswith("gripped, 1300 N;") and "adds 0.2222 kg·m²" in infeed
    assert [row[-1] for row in table.rows].count("") == 7
    assert "nip" not in rollers(webline.load_line("hswl")).columns

    def circles(line):
        return sum(isinstance(p, Circle) for p in schematic(line).axes[0].patches)

    bare = converter.replace({"rollers.infeed.nip": None})
    assert circles(converter) == circles(bare) + 1
