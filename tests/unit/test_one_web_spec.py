"""A single-path line read as a line of one web (``spec.one_web``, issue 33): the translation
of the file's keys, and problems named at the keys the single-path file gives them."""

from __future__ import annotations

import copy
import tomllib
from pathlib import Path

import pytest

from webline.errors import LineFileError
from webline.model.one_web import load_general, load_one_web
from webline.spec.load import branched_from_dict, read_any, spec_from_dict
from webline.spec.one_web import WEB, chain_key, one_web_data, one_web_path, one_web_spec

HAND_WRITTEN = Path(__file__).parents[1] / "data" / "hswl_one_web.toml"


@pytest.fixture(scope="module")
def hswl() -> dict:
    return read_any("hswl")[0]


def test_the_spans_become_one_web_on_the_rollers_path(hswl):
    out = one_web_data(hswl)
    assert "spans" not in out and out["web"] == hswl["web"]  # [web]: the webs' default
    (web,) = out["webs"]
    assert web["name"] == WEB
    assert web["path"] == [r["name"] for r in hswl["rollers"]]
    assert web["spans"] == hswl["spans"]
    assert "spans" in hswl and "webs" not in hswl  # (the input is left as it was)


@pytest.mark.parametrize(("chain", "general"), [
    ("spans.span2.tension", "webs.web.spans.span2.tension"),
    ("spans[1].length", "webs.web.spans[1].length"),
    ("spans.1.length", "webs.web.spans.1.length"),
    ("spans", "webs.web.spans"),
    ("rollers.process.controller.tension_bandwidth",
     "rollers.process.controller.tension_bandwidth"),
    ("web.ea", "web.ea"),
    ("spans_extra.x", "spans_extra.x"),  # (only the key 'spans' itself moves)
])
def test_paths_into_the_spans_move_under_the_web_and_back(chain, general):
    assert one_web_path(chain) == general
    assert chain_key(general) == chain


def test_a_scenarios_set_paths_are_renamed(hswl):
    out = one_web_data(hswl)
    assert list(out["scenarios"]["tension-step"]["set"]) == ["webs.web.spans.span2.tension"]
    assert out["scenarios"]["speed-change-surge"]["set"] == hswl["scenarios"][
        "speed-change-surge"]["set"]  # roller paths unchanged


def test_an_unnamed_span_keeps_the_name_the_single_path_line_gives_it(hswl):
    """A break, a loadcell and the results name an unnamed span k 'span{k+1}' on a
    single-path line (``Line.span_name``); a line of webs would name it 'web[k]'."""
    data = copy.deepcopy(hswl)
    del data["spans"][2]["name"]  # span3a -> 'span3'
    data["scenarios"]["break"] = {"duration": 1.0, "break": {"span": "span3", "at": 0.5}}
    spec = one_web_spec(data)
    assert [s.name for s in spec.webs[0].spans] == ["span1", "span2", "span3", "span3b"]
    assert spec.scenarios["break"].break_.span == "span3"


def test_an_unnamed_spans_name_taken_by_another_span_is_refused(hswl):
    data = copy.deepcopy(hswl)
    del data["spans"][0]["name"]  # 'span1' on a single-path line ...
    data["spans"][1]["name"] = "span1"  # ... and span 2's name
    with pytest.raises(LineFileError) as caught:
        one_web_data(data, "x.toml")
    assert caught.value.key == "spans[0].name"


def test_a_single_path_lines_problem_is_named_in_its_own_keys(hswl):
    data = copy.deepcopy(hswl)
    data["spans"][1]["length"] = "-3 m"
    with pytest.raises(LineFileError) as caught:
        one_web_spec(data, "x.toml")
    assert caught.value.key == "spans[1].length"


def test_sensors_are_carried_over_with_their_calibration_and_delay(hswl):
    """An encoder's scale and a loadcell's delay act on the general loop too (issue 36 item
    10): the translation carries each sensor over as the single-path file gives it, never
    dropped (the loop's equality with the chain: test_branch_sensors)."""
    data = copy.deepcopy(hswl)
    data["sensors"] = [
        {"name": "enc", "type": "encoder", "roller": "process", "scale": 1.01, "delay": "2 ms"},
        {"name": "cell", "type": "loadcell", "span": "span2", "gain": 0.97, "delay": "3 ms"}]
    spec_from_dict(data)  # (a valid single-path line)
    sensors = one_web_spec(data, "x.toml").sensors
    assert [(s.name, s.type) for s in sensors] == [("enc", "encoder"), ("cell", "loadcell")]
    assert sensors[0].scale == 1.01 and sensors[0].delay == pytest.approx(2e-3)
    assert sensors[1].gain == 0.97 and sensors[1].delay == pytest.approx(3e-3)


def test_a_problem_of_the_line_of_webs_in_its_spans_names_the_single_path_key(hswl):
    """A kelvin-voigt span beside a traction roller, refused by the branched checks at
    ``webs[0].spans[k].model``, is named at ``spans[k].model``."""
    data = copy.deepcopy(hswl)
    data["rollers"][3]["contact"] = {"type": "traction", "friction": 0.3, "viscous": 100.0}
    data["rollers"][3]["wrap"] = 3.0
    data["spans"][2].update(model="kelvin-voigt", retardation="5 ms")
    with pytest.raises(LineFileError) as caught:  # (the chain refuses it too, at its key)
        one_web_spec(data, "x.toml")
    assert caught.value.key == "spans[2].model"


def test_a_line_of_webs_is_not_translated_again():
    with pytest.raises(LineFileError) as caught:
        one_web_data({"webs": []}, "x.toml")
    assert caught.value.key == "webs"


def test_a_file_and_its_loaded_line_give_the_same_line_of_one_web():
    """From the built-in's TOML (units as written) or from its ``Line`` (a dumped spec, SI):
    the same spec."""
    import webline

    by_name, by_line = load_one_web("hswl"), load_one_web(webline.load_line("hswl"))
    assert by_name.spec == by_line.spec
    assert by_name.source == by_line.source == "hswl.toml (built-in)"


def test_load_general_translates_single_path_lines_only():
    """What the general loop runs (``load_general``, the FMU export's loader): a line of webs
    as it is, untranslated; a single-path line, by name, file, dict or ``Line``, as its line
    of one web."""
    import webline

    laminator, translated = load_general("laminator")
    assert not translated and laminator is load_general(laminator)[0]
    assert laminator.spec == load_general(read_any("laminator")[0])[0].spec
    for source in ("hswl", read_any("hswl")[0], webline.load_line("hswl")):
        line, translated = load_general(source)
        assert translated and line.spec == load_one_web("hswl").spec
        assert [w.name for w in line.spec.webs] == [WEB]


def test_the_generated_hswl_is_the_hand_written_one():
    """``tests/data/hswl_one_web.toml`` (hswl written by hand as a line of one web, issue 33)
    is what the translation makes of hswl: the same spec, but for its name and the web's
    material given in the web rather than as the line's default."""
    hand = tomllib.loads(HAND_WRITTEN.read_text(encoding="utf-8"))
    hand["web"] = hand["webs"][0].pop("web")
    hand["name"] = "hswl"
    generated = load_one_web("hswl").spec
    assert generated == branched_from_dict(hand)
