"""What a notebook shows (issue 23, item 2): a line's schematic and key tables, and short plain
reprs of lines and results (a dataclass repr printed the whole spec or every array)."""

from __future__ import annotations

import re

import webline
from webline import line as line_module


def test_line_html_shows_the_schematic_and_key_tables() -> None:
    """``Line._repr_html_``: one inline SVG (the report's schematic, with every roller's name
    as text) and the overview, rollers, spans, drives and zones tables, nothing else."""
    line = webline.load_line("hswl")
    page = line._repr_html_()
    assert page.count("<svg") == 1 and "<?xml" not in page
    for i in range(line.n_nodes):
        assert line.node_name(i) in page
    assert re.findall(r'<table id="(\w+)"', page) == ["line", "rollers", "spans", "drives",
                                                      "zones"]
    assert page == line._repr_html_()  # the same line draws the same text (fixed SVG ids)


def test_the_html_view_is_a_named_hook(monkeypatch) -> None:
    """The line layer names its view ("module:function") instead of importing the report; a
    user may point it at their own."""
    monkeypatch.setattr(line_module, "HTML_VIEW", "builtins:repr")
    assert webline.load_line("hswl")._repr_html_().startswith("<webline Line 'hswl'")


def test_line_and_result_reprs_are_a_few_lines() -> None:
    """``repr`` of a line and of a result: at most four lines, under 400 characters, naming
    the line, its size, and for a result its span of time and status."""
    line = webline.load_line("converter")
    text = repr(line)
    assert len(text) < 400 and len(text.splitlines()) <= 4
    assert "'converter'" in text and f"{line.n_spans} spans" in text
    result = webline.simulate(line, "0.1 s")
    text = repr(result)
    assert len(text) < 400 and len(text.splitlines()) <= 4
    assert "'converter'" in text and "0.1 s simulated" in text and "status: ok" in text


def test_linear_model_repr_is_one_line() -> None:
    """``repr`` of the numpy linear model behind ``linearize``: its size and first names, one
    line (its matrices are in ``.a``, ``.b``, ``.c``)."""
    from webline.sim.linear.linearize import linear_model

    model = linear_model(webline.load_line("hswl"))
    text = repr(model)
    assert len(text.splitlines()) == 1 and len(text) < 300
    assert f"{len(model.states)} states" in text and model.inputs[0] in text


def test_linearize_returns_a_statespace_with_a_short_repr() -> None:
    """``linearize``'s system is a python-control ``StateSpace`` (slicing, feedback work) whose
    ``repr`` is one line (python-control's printed every matrix, 13 kB for the HSWL)."""
    import control

    system = webline.linearize("hswl")
    assert isinstance(system, control.StateSpace)
    text = repr(system)
    assert len(text.splitlines()) == 1 and len(text) < 300
    assert f"{system.nstates} states" in text and "zone1_tension_ref" in text
    path = system[system.output_labels.index("span2_tension"),
                  system.input_labels.index("zone2_tension_ref")]
    assert control.feedback(path, 0.0).nstates == system.nstates  # python-control as usual
    assert "Inputs (5)" in str(system)  # print() still lists the signals
