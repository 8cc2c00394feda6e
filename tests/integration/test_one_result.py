"""A line of one web gives what a single-path line gives (issue 33, item 4: one result).

hswl runs through the single-path loop and, written as a line of one web
(``tests/data/hswl_one_web.toml``), through the general loop; their trajectories agree to
1e-13 N (``test_one_web.py``). So their results must agree too: the same variable names,
dimensions, units and long names, the same metrics, summary keys and verdict lines, and the
same values. Every difference left is listed in ``EXPECTED_DIFFERENCES`` with its reason.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import webline
from webline.model.web_graph import load_branched

ONE_WEB = Path(__file__).parents[1] / "data" / "hswl_one_web.toml"

#: every hswl scenario, 3 s each: past the tension step at 2 s and into every ramp
SCENARIOS = (None, "startup", "speed-change", "disturbance", "roll-change", "tension-step",
             "speed-change-surge")
SECONDS = 3.0

#: Two results agree where |a - b| <= RTOL x the largest |a| of that signal over the run (or,
#: for a tension error or spread, of the tension itself: they are differences of 64 N
#: numbers): the loops agree to 1e-13 N on 64 N (2e-15), the same numbers summed in another
#: order.
RTOL = 1e-9

#: What a line of one web still gives otherwise than the single-path line, and why.
EXPECTED_DIFFERENCES: dict[str, str] = {
    # (1) not recorded by the general loop (loop/kernel.py records time, states, torque
    #     commands and calculator radii only; a record column each is the loop's work)
    "speed_ref": "not recorded by the general loop (summary's drive speed errors NaN)",
    "trim": "not recorded by the general loop (the tension loop's output)",
    "equilibrium_input": "not recorded by the general loop (decentralized controllers)",
    "friction_estimate": "not recorded by the general loop (adaptive controllers)",
    # (2) named per web: a web of a graph may start at a nip and end at a knife
    "web_unwound": "web_in over dimension web (a one-web line: web = ['web'])",
    "web_rewound": "web_out over dimension web (as web_unwound)",
    "web_stored": "over dimension web (a one-web line: web = ['web']); values equal",
    # (3) one name, two meanings: left for the switch (twin logs and sweeps read it)
    "radius": "single-path: each roller's effective radius over node; general: each "
              "roll's wound radius over roll (a shaft holds several lanes)",
    "roll": "a roll is named roller/web (unwind/web), so a shaft's lanes stay apart",
    # (4) what a graph of webs has and a single path has not
    "strain": "general only: per span (laminates, nonlinear webs)",
    "layer_tension": "general only: laminates (empty here)",
    "layer_strain": "general only: laminates (empty here)",
    "layer_in": "general only: laminates (empty here)",
    "layer_out": "general only: laminates (empty here)",
    "layer_stored": "general only: laminates (empty here)",
    "core_omega": "general only: differential shafts' clutch cores (empty here)",
    "web_in": "general only: see web_unwound",
    "web_out": "general only: see web_rewound",
    "radius_calc": "general only: the deprecated name of the calculator's radius",
}

#: summary entries the general result gives as NaN (``speed_ref`` is not recorded)
NAN_SUMMARY = {"mean_reference", "mean_error", "std_error", "max_abs_error"}

#: renamed variables: single-path name -> general name (values compared)
RENAMED = {"web_unwound": "web_in", "web_rewound": "web_out", "web_stored": "web_stored"}


@pytest.fixture(scope="module")
def pairs():
    one_web = load_branched(ONE_WEB)
    return {scenario: (webline.simulate("hswl", SECONDS, scenario=scenario),
                       webline.simulate(one_web, SECONDS, scenario=scenario))
            for scenario in SCENARIOS}


def _close(a: np.ndarray, b: np.ndarray, scale: float | None = None) -> bool:
    """Equal NaNs, and |a - b| within RTOL of ``scale`` (default: the largest |a|)."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    if a.shape != b.shape or not np.array_equal(np.isnan(a), np.isnan(b)):
        return False
    finite = np.isfinite(a)
    if scale is None:
        scale = float(np.max(np.abs(a[finite]), initial=0.0))
    return bool(np.all(np.abs(a[finite] - b[finite]) <= RTOL * scale))


def test_the_variables_are_the_same_but_the_listed_ones(pairs):
    chain, general = pairs[None]
    ours, theirs = set(chain.signals.data_vars), set(general.signals.data_vars)
    assert ours - theirs == {"speed_ref", "trim", "equilibrium_input", "friction_estimate",
                             "web_unwound", "web_rewound"}
    assert theirs - ours == {k for k, v in EXPECTED_DIFFERENCES.items()
                             if v.startswith("general only")}


@pytest.mark.parametrize("scenario", SCENARIOS)
def test_shared_variables_agree_in_dims_units_and_values(pairs, scenario):
    chain, general = pairs[scenario]
    a, b = chain.signals, general.signals
    shared = sorted(set(a.data_vars) & set(b.data_vars) - set(EXPECTED_DIFFERENCES))
    assert len(shared) >= 16  # tension, speed, torque, slack, slip, inertia ...
    for name in shared:
        assert a[name].dims == b[name].dims, name
        assert {k: a[name].attrs.get(k) for k in ("units", "long_name", "flag_meanings")} == \
               {k: b[name].attrs.get(k) for k in ("units", "long_name", "flag_meanings")}, name
        assert _close(a[name].values, b[name].values), (scenario, name)
    for old, new in RENAMED.items():  # one web: its only column
        assert _close(a[old].values, b[new].sel(web="web").values), (scenario, old)
    assert _close(chain.roll_radius, general.roll_radius)
    assert list(a.span.values) == list(b.span.values)
    assert list(a.node.values) == list(b.node.values)
    assert list(a.drive.values) == list(b.drive.values)


@pytest.mark.parametrize("scenario", SCENARIOS)
def test_metrics_summary_and_verdict_agree(pairs, scenario):
    chain, general = pairs[scenario]
    ours, theirs = chain.metric_arrays(), general.metric_arrays()
    assert ours.keys() == theirs.keys()
    tension = float(np.max(chain.tension))  # [N]: the scale of every tension error
    for name in ours:
        if name == "status":
            assert ours[name] == theirs[name]
        else:
            scale = tension if name.startswith("tension") else None
            assert _close(ours[name], theirs[name], scale), (scenario, name)
    a, b = chain.summary(), general.summary()
    assert a.keys() == b.keys()
    for group in a:
        assert a[group].keys() == b[group].keys()
        for element, row in a[group].items():
            assert row.keys() == b[group][element].keys()
            for key, value in row.items():
                other = b[group][element][key]
                if group == "drives" and key in NAN_SUMMARY:
                    assert np.isnan(other)
                else:
                    scale = tension if group == "spans" else None
                    assert _close(np.array(value), np.array(other), scale), (scenario, element,
                                                                             key)
    lines = [{(f.level, f.kind, f.message) for f in r.verdict.findings} for r in (chain, general)]
    assert lines[0] == lines[1]
    assert chain.status == general.status


def test_the_global_attributes_are_the_single_path_ones(pairs):
    chain, general = pairs["tension-step"]
    ours, theirs = dict(chain.signals.attrs), dict(general.signals.attrs)
    assert set(ours) <= set(theirs)
    assert set(theirs) - set(ours) == {"scenario", "failure"}
    for key in ("Conventions", "status", "message", "verdict", "webline_version",
                "setting_dt", "setting_duration"):
        assert ours[key] == theirs[key], key
    assert theirs["line_spec_toml"].startswith('name = "hswl_one_web"')
    assert general.signals.tension.attrs["units"] == "N"
    assert general.signals.span.attrs["long_name"] == chain.signals.span.attrs["long_name"]


def test_dataframe_columns_are_the_single_path_ones_but_the_listed(pairs):
    chain, general = pairs[None]
    ours = set(chain.to_dataframe().columns)  # a roll named roller/web ("roll" above):
    theirs = {c.replace("/web]", "]") for c in general.to_dataframe().columns}
    listed = set(EXPECTED_DIFFERENCES)
    assert {c.split("[")[0] for c in ours - theirs} <= listed
    assert {c.split("[")[0] for c in theirs - ours} <= listed
