"""The report, schematic and show of a branched line (docs/branching.md, "Report"): the files
a run writes hold the verdict and every web; the schematic draws one path per web through its
rollers and marks the junctions where the topology has them; captions state the run's numbers."""

from __future__ import annotations

import json
import re
from html import unescape

import numpy as np
import pytest
from branch_support import laminated_then_slit
from matplotlib.lines import Line2D
from matplotlib.patches import Circle, Rectangle
from typer.testing import CliRunner

import webline
from webline.cli import app
from webline.model.web_graph import load_branched
from webline.report.plots.branch_figures import (
    largest_deviation,
    radii_caption,
    speeds_caption,
    tensions_caption,
    torques_caption,
)
from webline.report.plots.branch_schematic import branch_schematic
from webline.sim.branches.loop import layout as B


@pytest.fixture(scope="module")
def upset():
    return webline.simulate("laminator", 3.0, scenario="layer-upset")


def _by_gid(fig, kind):
    """Artists of ``fig``'s axes whose gid starts with ``kind:``, by the rest of the gid."""
    ax = fig.axes[0]
    found = {}
    for artist in [*ax.lines, *ax.patches, *ax.texts]:
        gid = artist.get_gid() or ""
        if gid.startswith(kind + ":"):
            found[gid[len(kind) + 1:]] = artist
    return found


@pytest.mark.parametrize("name", ["laminator", "slitter"])
def test_the_schematic_draws_each_web_through_its_rollers_and_the_junctions_where_they_are(name):
    line = load_branched(name)
    fig = branch_schematic(line)
    webs, rollers = _by_gid(fig, "web"), _by_gid(fig, "roller")
    assert set(webs) == {w.name for w in line.spec.webs}  # one path per web, no more
    assert all(isinstance(p, Line2D) for p in webs.values())
    assert set(rollers) == {r.name for r in line.spec.rollers}
    for web in line.spec.webs:
        xs, ys = webs[web.name].get_data()
        assert len(xs) == len(web.path)
        for x, y, roller in zip(xs, ys, web.path, strict=True):
            circle = rollers[roller]
            assert isinstance(circle, Circle)
            cx, cy = circle.center
            # each point of the path lies on its roller: at its centre, or (lanes side by side
            # on one shaft) within its drawn circle
            assert x == pytest.approx(cx, abs=1e-12)
            assert abs(y - cy) < circle.radius
    # the junctions where the topology has them, each at its roller and named for its kind
    junctions = _by_gid(fig, "junction")
    expected = {line.spec.rollers[i].name for i in line.junctions}
    assert set(junctions) == expected and expected
    for roller, marker in junctions.items():
        assert marker.get_xdata()[0] == pytest.approx(rollers[roller].center[0], abs=1e-12)
    labels = [t.get_text() for t in fig.axes[0].texts]
    kind = "lamination nip" if name == "laminator" else "slitter"
    assert labels.count(kind) == 1
    # every roller labelled with its name; every loadcell span marked
    assert {n: t.get_text().split("\n")[0] for n, t in _by_gid(fig, "label").items()} == {
        r.name: r.name for r in line.spec.rollers}
    cells = {s.name for s in line.spans if line.span_tension_spec(s.index) is not None}
    assert set(_by_gid(fig, "loadcell")) == cells


def test_lanes_on_one_shaft_are_one_roll_with_its_lanes_stacked():
    line = load_branched("slitter")
    fig = branch_schematic(line)
    lanes = _by_gid(fig, "lane")
    assert set(lanes) == {"rewind_shaft:lane_1", "rewind_shaft:lane_2"}  # not lane_3's roll
    assert all(isinstance(p, Rectangle) for p in lanes.values())
    # one roll drawn for the shaft, the two lanes ending on it at distinct heights
    webs = _by_gid(fig, "web")
    ends = [webs[n].get_data()[1][-1] for n in ("lane_1", "lane_2")]
    assert ends[0] != ends[1]
    assert sum(1 for gid in _by_gid(fig, "roller") if gid == "rewind_shaft") == 1


def test_the_tension_caption_states_the_runs_largest_deviation(upset):
    ds = upset.dataset
    t = ds["time"].values
    # the references written in the line file: film 120 N stepping to 150 N at 2 s, foil
    # 60 N, laminate 180 N (computed here from the file, not from the plan's tables)
    refs = {"film_zone": np.where(t >= 2.0, 150.0, 120.0), "foil_zone": 60.0 + 0 * t,
            "laminate_zone": 180.0 + 0 * t}
    errors = {k: np.abs(ds["tension"].sel(span=k).values - r) for k, r in refs.items()}
    span = max(errors, key=lambda k: errors[k].max())
    i = int(np.argmax(errors[span]))
    caption = tensions_caption(upset)
    # the caption prints 4 significant digits: it must state exactly the dataset's to those
    assert (f"Largest deviation from a reference: {errors[span][i]:.4g} N in {span} at "
            f"t = {t[i]:.4g} s.") in caption


def test_the_torque_and_radius_captions_state_the_runs_numbers(upset):
    ds = upset.dataset
    torque = np.abs(ds["torque"].values).max(axis=0)
    limits = upset.plan.df[:, B.D_LIMIT]
    caption = torques_caption(upset)
    for name, peak, limit in zip(ds["drive"].values, torque, limits, strict=True):
        assert f"{name} {peak:.4g} N·m of {limit:.4g}" in caption
    share = torque / limits
    assert f"{ds['drive'].values[np.argmax(share)]} at {100 * share.max():.3g} %" in caption
    # the master (the nip) against the line file's speed, 150 m/min = 2.5 m/s throughout
    error = np.abs(ds["speed"].sel(node="nip").values - 2.5).max()
    assert f"The master nip follows the reference within {error:.4g} m/s." in speeds_caption(
        upset)
    radius = ds["radius"].values * 1e3
    caption = radii_caption(upset)
    for j, name in enumerate(ds["roll"].values):
        assert f"{name} {radius[0, j]:.4g} → {radius[-1, j]:.4g} mm" in caption


def test_webline_run_writes_a_report_with_the_verdict_and_every_web(tmp_path):
    out = tmp_path / "run"
    result = CliRunner().invoke(app, ["run", "slitter", "-s", "thickness-profile", "-d", "2",
                                      "-o", str(out)])
    assert result.exit_code == 0, result.output
    summary = json.loads((out / "summary.json").read_text("utf-8"))
    page = unescape((out / "report.html").read_text("utf-8"))
    headline = summary["verdict"]["status"]
    assert headline == "ok" and "ok: no instability, failure or warning found" in page
    rows = re.findall(r'<table id="verdict">(.*?)</table>', page, re.S)[0]
    for web in ("base", "lane_1", "lane_2", "lane_3"):
        assert f'<td class="text">{web}</td>' in rows
    # the single-path report's summary: every span's tension, every drive, the events
    assert '<table id="summary-spans">' in page and '<table id="summary-drives">' in page
    spans = [s.name for s in load_branched("slitter").spans]
    assert list(summary["summary"]["spans"]) == spans
    assert summary["summary"]["drives"]["rewind_3"]["mean_reference"] is None  # not recorded
    for key in ("schematic", "tensions", "speeds", "radii", "torques"):
        assert (out / "figures" / f"{key}.png").stat().st_size > 5_000
        assert f'id="fig-{key}"' in page
    line_table = re.findall(r'<table id="line">(.*?)</table>', page, re.S)[0]
    # the line's description and source, as the file gives them
    spec = load_branched("slitter").spec
    assert f'<td class="text">{spec.description}</td>' in line_table
    assert f'<td class="text">{spec.source}</td>' in line_table
    # a lane's largest deviation in the verdict table is the summary's, to its 4 digits
    lane = summary["webs"][1]["spans"]["lane_1_span"]["max_deviation_N"]
    assert f"lane_1_span {lane:.4g}" in rows
    assert "Report: " in result.output


def test_webline_show_prints_a_branched_line_and_draws_its_schematic(tmp_path):
    target = tmp_path / "laminator.svg"
    result = CliRunner().invoke(app, ["show", "laminator", "--schematic", str(target)])
    assert result.exit_code == 0, result.output
    for text in ("film", "foil", "laminate", "lamination nip", "laminate_zone"):
        assert text in result.output
    assert target.read_text("utf-8").lstrip().startswith("<?xml")
    bad = CliRunner().invoke(app, ["show", "laminator", "--schematic", str(tmp_path / "a.txt")])
    assert bad.exit_code == 2 and "Traceback" not in bad.output
    assert len(bad.stderr.strip().splitlines()) == 1


def test_a_notebook_shows_a_branched_line_and_its_run(upset):
    line_view = load_branched("slitter")._repr_html_()
    assert "<svg" in line_view and "lanes on one shaft: lane_1 + lane_2" in line_view
    run_view = upset._repr_html_()
    assert upset.verdict.headline in unescape(run_view)
    assert all(w in run_view for w in ("film", "foil", "laminate"))


def test_webline_show_draws_a_single_path_lines_schematic_too(tmp_path):
    target = tmp_path / "hswl.png"
    result = CliRunner().invoke(app, ["show", "hswl", "--schematic", str(target)])
    assert result.exit_code == 0, result.output
    assert target.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and target.stat().st_size > 10_000
    # in the units asked for: the loadcells' references in lbf (none in the SI drawing)
    vector = tmp_path / "hswl.svg"
    result = CliRunner().invoke(app, ["show", "hswl", "--units", "imperial", "--schematic",
                                      str(vector)])
    assert result.exit_code == 0 and " lbf" in vector.read_text("utf-8")
    si = tmp_path / "hswl-si.svg"
    assert CliRunner().invoke(app, ["show", "hswl", "--schematic", str(si)]).exit_code == 0
    assert " lbf" not in si.read_text("utf-8")


def test_the_captions_of_lanes_on_one_shaft_state_their_sum_and_their_drift():
    result = webline.simulate("slitter", 2.0, scenario="thickness-profile")
    ds = result.dataset
    lanes = ds["tension"].sel(span=["lane_1_span", "lane_2_span"]).values
    # both lanes' references are 100 N: the shaft's drive holds their sum at 200 N
    error = np.abs(lanes.sum(axis=1) - 200.0).max()
    assert f"rewind_shaft holds the sum of lane_1_span + lane_2_span within {error:.4g} N" in (
        tensions_caption(result))
    # lane_1 is 1 % thicker: its roll grows faster; the caption gives the gap at the end
    radius = ds["radius"].sel(roll=["rewind_shaft/lane_1", "rewind_shaft/lane_2"]).values
    gap = 1e3 * (radius[-1].max() - radius[-1].min())
    assert gap > 0 and f"The lanes on rewind_shaft end {gap:.3g} mm apart." in radii_caption(
        result)


def test_the_report_states_a_warning_and_the_drive_it_concerns():
    from webline.report.branch_report import report_html

    line = webline.load_line("laminator")
    data = line.spec.model_dump(exclude_none=True)
    # the rewind needs 15.96 N·m steady at 2.5 m/s (test_branches' torque-limit test) and more
    # to accelerate: a 16.2 N·m limit is reached during the ramp
    data["rollers"][6]["drive"]["torque_limit"] = 16.2
    data["speed"] = {"type": "ramp", "initial": 2.0, "final": 2.5, "start": 0.5,
                     "duration": 0.5}
    result = webline.simulate(webline.load_line(data), 2.0, raise_on_failure=False)
    page = unescape(report_html(result, {}))
    finding = next(f for f in result.verdict.findings if f.kind == "torque_limit")
    assert 'class="status warning"' in page and result.verdict.headline in page
    table = re.findall(r'<table id="drive_findings">(.*?)</table>', page, re.S)[0]
    assert finding.message in table and '<td class="text">rewind</td>' in table
    # the torque caption names the drive at its limit: 100 % of it, to the printed digits
    peak = np.abs(result.dataset["torque"].sel(drive="rewind").values).max()
    assert f"rewind at {100 * peak / 16.2:.3g} %" in torques_caption(result)


def test_a_run_stopped_early_is_reported_as_such_and_marked_on_every_time_plot(upset):
    import dataclasses

    from webline.report.branch_report import report_html
    from webline.report.plots.branch_figures import branch_figure_jobs

    # the records of a run that stopped at 1 s (its first 1001 records), as the loop hands
    # them over when the state runs away
    stopped = dataclasses.replace(upset, rec=upset.rec[:1001],
                                  failure="the state ran away at t = 1 s")
    page = unescape(report_html(stopped, {}))
    assert 'class="status failed"' in page
    assert "The run stopped early: the state ran away at t = 1 s" in page
    for job in branch_figure_jobs(stopped):
        for fig in job():
            if fig.key == "schematic":
                continue
            for ax in fig.figure.axes:  # a vertical line at the last record, t = 1 s
                assert any(list(line.get_xdata()) == [1.0, 1.0] for line in ax.lines)


def test_the_schematic_caption_names_the_junctions_and_shafts_the_topology_has():
    from webline.report.plots.branch_figures import schematic_caption

    caption = schematic_caption(webline.simulate("slitter", 0.01))
    assert "slitter at slitter" in caption
    assert "lane_1 and lane_2 on one shaft at rewind_shaft" in caption and "lane_3 on" not in (
        caption)


def test_run_svg_writes_vector_figures_and_quiet_prints_only_the_report(tmp_path):
    out = tmp_path / "run"
    result = CliRunner().invoke(app, ["run", "laminator", "-d", "0.2", "--svg", "-q",
                                      "-o", str(out)])
    assert result.exit_code == 0, result.output
    assert result.stdout.strip() == str(out / "report.html")
    for key in ("schematic", "tensions", "layers", "speeds", "radii", "torques"):
        assert (out / "figures" / f"{key}.svg").read_text("utf-8").lstrip().startswith("<?xml")
    manifest = (out / ".webline-manifest.json").read_text("utf-8")
    assert "figures/torques.svg" in manifest and "report.html" in manifest


def test_write_report_writes_a_branched_runs_report_from_python(tmp_path, upset):
    from webline.report import write_report

    files = write_report(upset, tmp_path / "mine")
    summary = json.loads(files.summary.read_text("utf-8"))
    assert summary["scenario"] == "layer-upset" and summary["verdict"]["status"] == "ok"
    assert upset.verdict.headline in unescape(files.report.read_text("utf-8"))
    assert {p.name for p in files.figures} == {f"{k}.png" for k in (
        "schematic", "tensions", "layers", "speeds", "radii", "torques")}
    per_width = write_report(upset, tmp_path / "other", units="si-per-width")
    assert "N/m" in unescape(per_width.report.read_text("utf-8"))
    with pytest.raises(webline.ArgumentError, match="expected one of"):
        write_report(upset, tmp_path / "bad", units="pli")  # type: ignore[arg-type]


def test_the_report_in_imperial_units_shows_the_runs_numbers_converted(upset):
    """``--units imperial`` (docs/branching.md, "Report"): every drawn tension is the run's
    [N] times 1/4.4482216 lbf/N (exactly: pint's factor), the caption's largest deviation
    the SI one converted, the tables' forces in lbf, torques in lbf·ft, radii in inches."""
    from webline.report.plots.branch_figures import tensions_figure
    from webline.report.text.branch_tables import line_tables
    from webline.report.text.display import Display

    imperial = Display("imperial")
    lbf = 1.0 / 4.4482216152605
    fig = tensions_figure(upset, imperial)
    drawn = np.concatenate([ln.get_ydata() for ax in fig.axes for ln in ax.get_lines()])
    si = np.concatenate([ln.get_ydata() for ax in tensions_figure(upset).axes
                         for ln in ax.get_lines()])
    assert np.allclose(drawn, si * lbf, rtol=1e-12, atol=0.0)
    assert fig.axes[0].get_ylabel() == "tension [lbf]"
    error, _, _ = largest_deviation(upset)
    assert f"{error * lbf:.4g} lbf" in tensions_caption(upset, imperial)
    webs, rollers, drives = (next(t for t in line_tables(upset.plan.line, imperial)
                                  if t.key == key) for key in ("webs", "rollers", "drives"))
    assert "EA [lbf]" in webs.columns and "radius [in]" in rollers.columns
    assert "torque limit [lbf·ft]" in drives.columns
    nip = next(r for r in rollers.rows if r[0] == "nip")
    assert float(nip[2]) == pytest.approx(100 / 25.4, rel=1e-3)  # 100 mm, 4 digits shown


def test_run_and_show_take_units_for_a_branched_line(tmp_path):
    result = CliRunner().invoke(app, ["run", "laminator", "-d", "0.2", "--out",
                                      str(tmp_path / "run"), "--units", "imperial"])
    assert result.exit_code == 0, result.output
    assert "lbf" in result.output and "units: imperial" in (
        tmp_path / "run" / "report.html").read_text("utf-8")
    shown = CliRunner().invoke(app, ["show", "slitter", "--units", "imperial"])
    assert shown.exit_code == 0 and "EA [lbf]" in shown.output


LBF, INCH = 4.4482216152605, 0.0254  # [N], [m]: pint's
PLI = LBF / INCH  # 1 pli in N/m (175.13)


def test_per_width_units_divide_each_web_and_lane_by_its_own_width() -> None:
    """``--units si-per-width`` / ``imperial-per-width`` on a branched line (issue 33 item 3):
    each web's and lane's tensions are divided by its own width (the slitter: base 1.25 m,
    lanes 0.4 m; a laminate: its narrower layer's), as ``webline analyze`` already does;
    lengths and torques stay in the base system."""
    from webline.report.plots.branch_figures import tensions_figure
    from webline.report.text.branch_tables import line_tables
    from webline.report.text.display import Display

    run = webline.simulate("slitter", 0.3)
    line = run.plan.line
    widths = [m.width for m in line.materials]
    assert widths == [1.25, 0.4, 0.4, 0.4]
    per_width = Display("si-per-width", 1.0)
    drawn = tensions_figure(run, per_width)
    si = tensions_figure(run)
    for w, (ax, ax_si) in enumerate(zip(drawn.axes, si.axes, strict=True)):  # one per web
        for ln, ln_si in zip(ax.get_lines(), ax_si.get_lines(), strict=True):
            np.testing.assert_allclose(ln.get_ydata(), ln_si.get_ydata() / widths[w],
                                       rtol=1e-12, atol=0.0)
        assert ax.get_ylabel() == "tension [N/m]"
    webs = next(t for t in line_tables(line, Display("imperial-per-width", 1.0))
                if t.key == "webs")
    assert "EA [pli]" in webs.columns
    for row, m in zip(webs.rows, line.materials, strict=True):
        assert float(row[4]) == pytest.approx(m.ea / m.width / PLI, rel=1e-3)  # 4 digits


def test_run_and_show_in_pli_on_the_slitter(tmp_path) -> None:
    # the slitter's lanes hold 100 N on 400 mm: 250 N/m = 1.4275 pli each; its unwind zone
    # 300 N on 1.25 m: 240 N/m = 1.370 pli (docs/branching.md, "Report")
    shown = CliRunner().invoke(app, ["show", "slitter", "--units", "imperial-per-width"])
    assert shown.exit_code == 0, shown.output
    assert f"{240 / PLI:.4g} pli" in shown.output and f"{250 / PLI:.4g} pli" in shown.output
    run = CliRunner().invoke(app, ["run", "slitter", "-d", "0.3", "--out", str(tmp_path / "r"),
                                   "--units", "imperial-per-width"])
    assert run.exit_code == 0, run.output
    lane = next(ln for ln in run.output.splitlines() if ln.startswith("lane lane_3"))
    low, high = (float(v) for v in lane.split()[-2].split("-"))
    assert low == pytest.approx(250 / PLI, rel=2e-3) and high == pytest.approx(250 / PLI,
                                                                               rel=2e-3)
    assert lane.endswith("pli")
    report = unescape((tmp_path / "r" / "report.html").read_text("utf-8"))
    assert "units: imperial-per-width" in report and "pli" in report


def test_a_tree_that_merges_then_splits_is_drawn_with_both_junctions_in_their_places():
    from webline.report.plots.branch_schematic import web_rows

    line = laminated_then_slit()
    fig = branch_schematic(line)
    webs, rollers = _by_gid(fig, "web"), _by_gid(fig, "roller")
    assert set(webs) == {"film", "foil", "laminate", "lane_a", "lane_b"}
    junctions = _by_gid(fig, "junction")
    assert set(junctions) == {"nip", "knife"}
    labels = [t.get_text() for t in fig.axes[0].texts]
    assert labels.count("lamination nip") == 1 and labels.count("slitter") == 1
    # the layers on either side of the laminate's row, the two lanes on one row (one shaft)
    rows = dict(zip([w.name for w in line.spec.webs], web_rows(line), strict=True))
    assert rows["film"] > rows["laminate"] > rows["foil"]
    assert rows["lane_a"] == rows["lane_b"]
    assert set(_by_gid(fig, "lane")) == {"rewind:lane_a", "rewind:lane_b"}
    # the nip left of the knife, the knife left of the rewind: the tree runs left to right
    x = {name: rollers[name].center[0] for name in ("nip", "knife", "rewind")}
    assert x["nip"] < x["knife"] < x["rewind"]


def test_the_report_lists_the_lines_closed_loop_modes_and_names_the_least_damped(upset):
    from webline.analysis.modes import closed_loop_modes
    from webline.report.branch_report import report_html

    page = unescape(report_html(upset, {}))
    table = re.findall(r'<table id="modes">(.*?)</table>', page, re.S)[0]
    modes = closed_loop_modes(upset.plan.line, 0.0)  # at speed from t = 0: analysed there
    assert table.count("<tr>") == len(modes) + 1  # a row per mode, and the header
    oscillating = [m for m in modes if m.oscillatory]
    weakest = min(oscillating, key=lambda m: m.damping)
    assert (f"Least damped oscillating mode: ζ = {weakest.damping:.3g} at ωn = "
            f"{weakest.natural_frequency:.4g} rad/s, mostly in {weakest.dominant}.") in page
    # every mode of the built-in laminator decays (docs/branching.md, "Linear models")
    assert all(m.eigenvalue.real < 0 for m in modes)
    assert "No closed-loop mode grows, in the continuous model or in the loop as sampled " \
        "(1000 Hz, torque held)." in page


def test_the_report_names_a_growing_closed_loop_mode():
    from webline.report.branch_report import report_html

    data = webline.load_line("laminator").spec.model_dump(exclude_none=True)
    # the rewind's tension gain 40x its tuned 7.6e-5 (m/s)/N: a 38 Hz mode of the rewind and
    # the laminate zone grows (docs/branching.md, "Linear models": +18.56 1/s continuous with
    # the line's exact transport; +18.54 first-order, which printed 18.5)
    data["rollers"][6]["controller"]["tension_kp"] = 3e-3
    result = webline.simulate(webline.load_line(data), 0.2, raise_on_failure=False)
    page = unescape(report_html(result, {}))
    assert "Unstable: closed-loop mode λ = 18.6 ± " in page
    assert "No closed-loop mode grows" not in page
