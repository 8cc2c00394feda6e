"""pint's registry from webline's disk cache: the same units as parsing the definitions, and a
broken cache falls back to parsing instead of failing a command (webline.unit_registry.registry)."""

from __future__ import annotations

import json
import math
import os
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import pytest

from webline import unit_registry, units


@pytest.fixture
def cache(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    folder = tmp_path / "pint-cache"
    monkeypatch.setattr(unit_registry, "cache_folder", lambda: folder)
    monkeypatch.delenv(units.NO_CACHE_VARIABLE, raising=False)
    return folder


def _parses(registry) -> None:
    registry.define("pli = pound_force / inch")
    # 1 lbf/in = 4.4482216152605 N / 0.0254 m, exact by definition of both units
    assert registry("1 pli").to("N/m").magnitude == pytest.approx(4.4482216152605 / 0.0254,
                                                                  rel=1e-12)
    assert registry("500 ft/min").to("m/s").magnitude == pytest.approx(2.54, rel=1e-12)


def test_the_first_registry_builds_the_cache_whole_and_the_next_reads_it(cache: Path) -> None:
    _parses(unit_registry.registry())
    assert cache.is_dir() and list(cache.glob("*.pickle"))
    assert not list(cache.parent.glob(".building-*")), "the private build folder is renamed"
    _parses(unit_registry.registry())


def test_a_broken_cache_falls_back_to_parsing(cache: Path) -> None:
    unit_registry.registry()
    for pickle in cache.glob("*.pickle"):
        pickle.write_bytes(pickle.read_bytes()[:10])  # half a file, as a crash would leave
    _parses(unit_registry.registry())


def test_an_unwritable_cache_place_falls_back_to_parsing(tmp_path: Path,
                                                        monkeypatch: pytest.MonkeyPatch) -> None:
    blocker = tmp_path / "file"
    blocker.write_text("not a folder")
    monkeypatch.setattr(unit_registry, "cache_folder", lambda: blocker / "pint")
    _parses(unit_registry.registry())


# --- the factors of unit strings met before (webline.units._conversions) -------------------

@pytest.fixture
def memo(cache: Path) -> Iterator[Path]:
    """An empty conversions memo in a private cache folder, forgotten again afterwards."""
    units._conversions.cache_clear()
    yield units._conversions_path()
    units._conversions.cache_clear()


def test_a_factor_is_computed_once_written_and_read_back(memo: Path) -> None:
    # 500 ft/min = 500 * 0.3048 / 60 m/s = 2.54 m/s exactly (the foot is 0.3048 m by definition)
    assert units.to_si("500 ft/min", "speed") == pytest.approx(2.54, rel=1e-15)
    assert json.loads(memo.read_text())["speed|ft/min"] == pytest.approx(0.3048 / 60, rel=1e-15)
    units._conversions.cache_clear()  # a new process: the factor comes from the file
    assert units.to_si("250 ft/min", "speed") == pytest.approx(1.27, rel=1e-15)
    # through the memo a value is the number times the factor, bit for bit
    assert units.to_si("7.5 pli", "force_per_width") == 7.5 * units.to_si("1 pli",
                                                                         "force_per_width")


def test_memoised_values_equal_pint_conversions(memo: Path) -> None:
    cases = [("2000 lbf", "force", "N"), ("3 lb*ft**2", "inertia", "kg*m**2"),
             ("12 in", "length", "m"), ("5 %", "dimensionless", "dimensionless"),
             ("50 N/cm", "stiffness", "N/m")]
    for text, kind, si in cases:
        expected = units.ureg.Quantity(text).to(si).magnitude
        for _ in range(2):  # computed, then from the memo
            assert units.to_si(text, kind) == pytest.approx(expected, rel=1e-14)
    # frequencies count cycles: 6 Hz is 2π·6 rad/s
    assert units.to_si("6 Hz", "angular_frequency") == pytest.approx(12 * math.pi, rel=1e-15)
    assert units.per_width_to_si("2 N/cm") == pytest.approx(200.0, rel=1e-15)
    assert units.per_width_to_si("2 N") is None  # a force, not a force per width
    assert units.per_width_to_si("2 N") is None  # and remembered as such
    assert units.display_factor("speed", "imperial") == pytest.approx((60 / 0.3048, "ft/min"))


def test_a_wrong_unit_is_refused_every_time_and_never_remembered(memo: Path) -> None:
    for _ in range(2):
        with pytest.raises(ValueError, match="expected a speed"):
            units.to_si("3 kg", "speed")
        with pytest.raises(ValueError, match="cannot read '3 furlongz'"):
            units.to_si("3 furlongz", "length")
    assert not memo.exists() or not any(
        key.startswith(("speed|kg", "length|furlongz")) for key in json.loads(memo.read_text()))


def test_a_broken_memo_file_is_ignored(memo: Path) -> None:
    memo.parent.mkdir(parents=True, exist_ok=True)
    memo.write_text('{"speed|ft/min": "half a fi')
    assert units.to_si("500 ft/min", "speed") == pytest.approx(2.54, rel=1e-15)
    memo.write_text('{"speed|ft/min": "not a number", "length|in": 1e400}')
    units._conversions.cache_clear()
    assert units.to_si("500 ft/min", "speed") == pytest.approx(2.54, rel=1e-15)
    assert units.to_si("10 in", "length") == pytest.approx(0.254, rel=1e-15)


def test_without_the_cache_nothing_is_written(memo: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv(units.NO_CACHE_VARIABLE, "1")
    units._conversions.cache_clear()
    assert units.to_si("500 ft/min", "speed") == pytest.approx(2.54, rel=1e-15)
    assert not memo.exists()


def test_a_run_whose_units_are_known_does_not_import_pint(tmp_path: Path) -> None:
    """The point of the memo: loading, simulating and reporting a line whose unit strings were
    met before leaves pint (and the dask it imports where installed) out of the process."""
    script = ("import sys, pathlib, webline\n"
              "import webline.units as units, webline.unit_registry as registry\n"
              f"registry.cache_folder = lambda: pathlib.Path({str(tmp_path)!r}) / 'pint'\n"
              "line = webline.load_line('hswl')\n"
              "webline.simulate(line, 0.05)\n"
              "units.display_factor('speed', 'imperial')\n"
              "print('pint' in sys.modules)")
    env = {k: v for k, v in os.environ.items() if k != units.NO_CACHE_VARIABLE}
    runs = [subprocess.run([sys.executable, "-c", script], env=env, capture_output=True,
                           text=True, check=True).stdout.split()[-1] for _ in range(2)]
    assert runs == ["True", "False"]  # the first run meets the units, the second knows them


def test_the_cache_is_keyed_by_the_installed_pint_read_without_importlib_metadata() -> None:
    """The fast reading of pint's version (its dist-info folder) agrees with the metadata."""
    from importlib.metadata import version

    unit_registry.pint_version.cache_clear()
    assert unit_registry.pint_version() == version("pint")
    assert unit_registry.cache_folder().name.startswith(f"pint-{version('pint')}-py")
