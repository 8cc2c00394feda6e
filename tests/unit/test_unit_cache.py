"""pint's registry from webline's disk cache: the same units as parsing the definitions, and a
broken cache falls back to parsing instead of failing a command (webline.units._registry)."""

from __future__ import annotations

from pathlib import Path

import pytest

from webline import units


@pytest.fixture
def cache(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    folder = tmp_path / "pint-cache"
    monkeypatch.setattr(units, "_cache_folder", lambda: folder)
    monkeypatch.delenv(units.NO_CACHE_VARIABLE, raising=False)
    return folder


def _parses(registry) -> None:
    registry.define("pli = pound_force / inch")
    # 1 lbf/in = 4.4482216152605 N / 0.0254 m, exact by definition of both units
    assert registry("1 pli").to("N/m").magnitude == pytest.approx(4.4482216152605 / 0.0254,
                                                                  rel=1e-12)
    assert registry("500 ft/min").to("m/s").magnitude == pytest.approx(2.54, rel=1e-12)


def test_the_first_registry_builds_the_cache_whole_and_the_next_reads_it(cache: Path) -> None:
    _parses(units._registry())
    assert cache.is_dir() and list(cache.glob("*.pickle"))
    assert not list(cache.parent.glob(".building-*")), "the private build folder is renamed"
    _parses(units._registry())


def test_a_broken_cache_falls_back_to_parsing(cache: Path) -> None:
    units._registry()
    for pickle in cache.glob("*.pickle"):
        pickle.write_bytes(pickle.read_bytes()[:10])  # half a file, as a crash would leave
    _parses(units._registry())


def test_an_unwritable_cache_place_falls_back_to_parsing(tmp_path: Path,
                                                        monkeypatch: pytest.MonkeyPatch) -> None:
    blocker = tmp_path / "file"
    blocker.write_text("not a folder")
    monkeypatch.setattr(units, "_cache_folder", lambda: blocker / "pint")
    _parses(units._registry())
