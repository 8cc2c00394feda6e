"""Shared fixtures: the built-in line and a 6-section line with a different tension per zone."""

from __future__ import annotations

import os

# The suite's matrices are small: one BLAS thread is faster than two fighting over 2 cores.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import tomllib
from importlib import resources

import pytest

import webline


def six_section_dict() -> dict:
    """Unwind, infeed (tension), master, two process rollers, an idler, rewind: five zones,
    each with its own tension reference; the infeed sits upstream of the master, so it
    regulates the zone downstream of it (the other sign of the trim)."""
    drive = {"ratio": 1.0, "torque_limit": "200 N*m", "torque_lag": "2 ms"}
    roller = {"radius": "0.1 m", "inertia": "0.08 kg*m**2", "friction": "0.6 N*m*s"}
    return {
        "name": "six",
        "speed": "300 m/min",
        "web": {"modulus": "4 GPa", "thickness": "25 um", "width": "0.5 m",
                "density": "1390 kg/m**3"},
        "rollers": [
            {"name": "unwind", "type": "unwind", "radius": "0.4 m", "core_radius": "0.08 m",
             "inertia": "0.5 kg*m**2", "friction": "0.5 N*m*s", "wound_in_tension": "150 N",
             "drive": {**drive, "ratio": 0.5, "torque_limit": "800 N*m"}},
            {"name": "infeed", "type": "driven", "role": "tension", **roller, "drive": drive},
            {"name": "master", "type": "driven", "role": "master", **roller, "drive": drive},
            {"name": "coater", "type": "driven", "role": "tension", **roller, "drive": drive},
            {"name": "dryer", "type": "driven", "role": "tension", **roller, "drive": drive},
            {"name": "idler", "type": "idle", "radius": "0.05 m", "inertia": "0.002 kg*m**2",
             "friction": "5e-4 N*m*s", "coulomb_friction": "0.01 N*m"},
            {"name": "rewind", "type": "rewind", "radius": "0.2 m", "core_radius": "0.08 m",
             "inertia": "0.3 kg*m**2", "friction": "0.5 N*m*s",
             "drive": {**drive, "ratio": 0.5, "torque_limit": "800 N*m"}},
        ],
        "spans": [
            {"length": "3 m", "tension": "180 N"},
            {"length": "5 m", "tension": "220 N"},
            {"length": "4 m", "tension": "260 N"},
            {"length": "8 m", "tension": "200 N"},
            {"length": "2 m"},
            {"length": "2 m", "tension": "240 N"},
        ],
    }


def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    """Under issue 33's migration switch (``WEBLINE_GENERAL_LOOP=1``) a test of the chain
    loop's own machinery is skipped: it goes with that loop (the ``chain_only`` marker)."""
    from webline.spec.source import general_loop

    if not general_loop():
        return
    for item in items:
        mark = item.get_closest_marker("chain_only")
        if mark is not None:
            reason = mark.args[0] if mark.args else mark.kwargs.get("reason", "")
            item.add_marker(pytest.mark.skip(reason=f"chain loop's machinery: {reason}"))


@pytest.fixture(scope="session")
def hswl() -> webline.Line:
    return webline.load_line("hswl")


@pytest.fixture(scope="session")
def six() -> webline.Line:
    return webline.load_line(six_section_dict())


@pytest.fixture(scope="session")
def hswl_dict() -> dict:
    text = resources.files("webline.data.lines").joinpath("hswl.toml").read_text("utf-8")
    return tomllib.loads(text)


@pytest.fixture(autouse=True)
def _own_allow_list(tmp_path_factory: pytest.TempPathFactory,
                    monkeypatch: pytest.MonkeyPatch) -> None:
    """Every test reads an empty per-user allow-list of code (docs/security.md), never the
    real one of whoever runs the suite (subprocesses inherit it)."""
    monkeypatch.setenv("XDG_CONFIG_HOME", str(tmp_path_factory.mktemp("config")))
