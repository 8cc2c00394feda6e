"""webline's optional parts (``pyproject.toml``'s extras) and the one-line error when one is
used without its packages: ``require`` for the places that import them, ``missing_extra`` for
a ``ModuleNotFoundError`` met elsewhere (the command line turns either into one line, exit 2).
"""

from __future__ import annotations

import importlib
from types import ModuleType

from webline.errors import MissingExtra

#: top-level module -> (extra that installs it, what needs it)
OPTIONAL: dict[str, tuple[str, str]] = {
    "distributed": ("dask", "a sweep on a Dask cluster (scheduler)"),
    "dask": ("dask", "a sweep on a Dask cluster (scheduler)"),
    "jupytext": ("notebook", "running the tutorial notebooks"),
    "nbclient": ("notebook", "running the tutorial notebooks"),
    "mkdocs": ("docs", "building the documentation site"),
    "pyarrow": ("parquet", "reading a Parquet measurement file"),
    "gymnasium": ("gym", "the Gymnasium environment webline/Line-v0"),
}


def install_hint(module: str) -> str:
    """The one-line message for optional ``module`` (a top-level name of ``OPTIONAL``)."""
    extra, purpose = OPTIONAL[module]
    return (f"{purpose} needs the optional package {module!r}, which is not installed: "
            f"pip install 'webline[{extra}]'")


def require(module: str) -> ModuleType:
    """Import ``module`` (a name or dotted path whose top level is in ``OPTIONAL``), or raise
    ``MissingExtra`` naming the extra to install."""
    try:
        return importlib.import_module(module)
    except ModuleNotFoundError as exc:
        raise missing_extra(exc) or exc from None


def missing_extra(exc: BaseException) -> MissingExtra | None:
    """``MissingExtra`` for a ``ModuleNotFoundError`` of an optional package (its top-level
    name in ``OPTIONAL``), else None."""
    if not isinstance(exc, ModuleNotFoundError) or not exc.name:
        return None
    top = exc.name.split(".")[0]
    return MissingExtra(install_hint(top)) if top in OPTIONAL else None
