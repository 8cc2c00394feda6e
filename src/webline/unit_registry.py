"""pint's unit registry for webline (``webline.units.ureg``), built on first use with
webline's units added, its parsed definition files kept in a disk cache that a reader never
sees half-written."""

from __future__ import annotations

import functools
import os
import shutil
import sys
import tempfile
from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import pint

#: set to any value to build pint's registry from its definition files every time, and to
#: convert every quantity through pint (no factors read or written)
NO_CACHE_VARIABLE = "WEBLINE_NO_UNIT_CACHE"
#: units webline adds to pint's
DEFINITIONS = ("fpm = foot / minute", "pli = pound_force / inch", "rpm_ = revolution / minute")


@functools.cache
def pint_version() -> str:
    """pint's installed version, without importing pint: the name of its
    ``pint-X.Y.Z.dist-info`` folder beside the package (importlib.metadata costs 70 ms of a
    command's start-up), else importlib.metadata."""
    import importlib.util

    spec = importlib.util.find_spec("pint")
    if spec is not None and spec.origin:
        site = os.path.dirname(os.path.dirname(spec.origin))
        found = [e for e in os.listdir(site) if e.startswith("pint-")
                 and e.endswith(".dist-info")]
        if len(found) == 1:
            return found[0][len("pint-"):-len(".dist-info")]
    from importlib.metadata import version

    return version("pint")


def cache_folder() -> Path:
    """Where pint's parsed definitions are kept: one folder per pint and Python version,
    since the cache is a pickle."""
    import platformdirs

    tag = f"pint-{pint_version()}-py{sys.version_info.major}.{sys.version_info.minor}"
    return platformdirs.user_cache_path("webline") / tag


def registry() -> pint.UnitRegistry:
    """pint's registry, its parsed definition files loaded from a disk cache (0.3 s of a
    command's start-up otherwise). pint writes its cache files in place, so a reader beside a
    writer (two commands, Dask workers) could see half a file: the cache is built in a private
    folder and renamed into place whole, and only a complete folder is ever read. Any problem
    with the cache falls back to parsing the definitions."""
    import pint

    if os.environ.get(NO_CACHE_VARIABLE):
        return pint.UnitRegistry()
    try:
        folder = cache_folder()
        if folder.is_dir():
            return pint.UnitRegistry(cache_folder=folder)
        folder.parent.mkdir(parents=True, exist_ok=True)
        building = Path(tempfile.mkdtemp(prefix=".building-", dir=folder.parent))
        made: pint.UnitRegistry = pint.UnitRegistry(cache_folder=building)
        try:
            building.rename(folder)
        except OSError:  # another process put its complete cache there first
            shutil.rmtree(building, ignore_errors=True)
        return made
    except Exception:  # the cache only saves time: never fail a command for it
        return pint.UnitRegistry()


@functools.cache
def ureg() -> pint.UnitRegistry:
    """webline's registry (``ureg``), built on first use."""
    built = registry()
    for definition in DEFINITIONS:
        built.define(definition)
    return built
