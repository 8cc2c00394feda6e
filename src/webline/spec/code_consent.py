"""Consent to run the Python code a line file names (docs/security.md).

A line file is data: loading, validating, showing or analysing it never imports what its
``controller = { type = "python", object | function = "MODULE:NAME" }`` entries name. A run
imports such a module only where the user consented to it:

- ``--allow-code`` on the command line, ``allow_code=True`` in the API (``simulate``,
  ``Session``, the gym environment) or ``with allowing_code():`` around any other call: the
  ``.py`` files of the line file's own folder (and below it) may run;
- the per-user allow-list ``$XDG_CONFIG_HOME/webline/trusted.toml`` (default
  ``~/.config/webline/trusted.toml``): ``folders = [...]`` whose ``.py`` files, and
  ``modules = [...]`` (importable, a name covers its submodules) whose objects, may run
  without the flag; the only way to run a file outside the line file's folder (``../x.py``,
  an absolute path) or an installed module.

This module holds the decision and the import; which objects may then be called (the
controller protocol, checked before any call) is ``sim.user_objects``'s.
"""

from __future__ import annotations

import hashlib
import importlib
import importlib.util
import os
import sys
import tomllib
from collections.abc import Iterator
from contextlib import contextmanager
from contextvars import ContextVar
from dataclasses import dataclass
from pathlib import Path
from types import ModuleType

from webline.errors import LineFileError

#: consent given by the surrounding code (``allowing_code``; the CLI's ``--allow-code``)
_SCOPE: ContextVar[bool] = ContextVar("webline_allow_code", default=False)

#: how to consent, as every refusal says it
HOW = "run again with --allow-code (API: allow_code=True), or trust it in {file} (docs/security.md)"


@contextmanager
def allowing_code(allow: bool = True) -> Iterator[None]:
    """Within the block, runs may import the code of their line file's own folder (as
    ``allow_code=True`` does for one call); ``allow=False`` leaves consent as it was."""
    token = _SCOPE.set(_SCOPE.get() or allow)
    try:
        yield
    finally:
        _SCOPE.reset(token)


def consented(allow_code: bool | None) -> bool:
    """Whether a call consents to its line file's own code: ``allow_code`` if given, else
    the surrounding ``allowing_code`` scope."""
    return _SCOPE.get() if allow_code is None else bool(allow_code)


def trusted_file() -> Path:
    """The allow-list: ``$XDG_CONFIG_HOME/webline/trusted.toml`` (default
    ``~/.config/webline/trusted.toml``)."""
    base = os.environ.get("XDG_CONFIG_HOME") or str(Path.home() / ".config")
    return Path(base) / "webline" / "trusted.toml"


@dataclass(frozen=True)
class Trusted:
    """The allow-list: folders (resolved) whose ``.py`` files, and importable module names
    (with their submodules) whose objects, run without ``--allow-code``."""

    folders: tuple[Path, ...] = ()
    modules: tuple[str, ...] = ()

    def has_file(self, path: Path) -> bool:
        return any(path.is_relative_to(folder) for folder in self.folders)

    def has_module(self, name: str) -> bool:
        return any(name == m or name.startswith(m + ".") for m in self.modules)


def read_trusted(path: Path | None = None) -> Trusted:
    """The allow-list at ``path`` (default ``trusted_file()``); empty where there is none.
    ``LineFileError`` (exit 2) naming the file and key for a malformed one."""
    path = trusted_file() if path is None else path
    if not path.is_file():
        return Trusted()
    label = str(path)
    try:
        data = tomllib.loads(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError) as exc:
        raise LineFileError(label, "(file)", f"cannot read the allow-list: {exc}") from None
    unknown = sorted(set(data) - {"folders", "modules"})
    if unknown:
        raise LineFileError(
            label, unknown[0], "unknown key (the allow-list has folders and modules)"
        )
    lists: dict[str, list[str]] = {}
    for key in ("folders", "modules"):
        value = data.get(key, [])
        if not isinstance(value, list) or not all(isinstance(v, str) and v for v in value):
            raise LineFileError(label, key, "expected a list of non-empty strings")
        lists[key] = value
    folders = [Path(os.path.expanduser(given)) for given in lists["folders"]]
    for folder, given in zip(folders, lists["folders"], strict=True):
        if not folder.is_absolute():
            raise LineFileError(
                label, "folders", f"{given!r}: expected an absolute folder (or one under ~)"
            )
    return Trusted(tuple(f.resolve() for f in folders), tuple(lists["modules"]))


def refusal(source: str, key: str, named: str, where: str, how: str) -> LineFileError:
    """The one-line refusal: which code (``named``, found at ``where``) the line file's
    ``key`` names, and ``how`` to consent."""
    return LineFileError(
        source,
        key,
        f"names Python code {named!r} ({where}), which runs only with your consent: {how}",
    )


def permit(name: str, source: str, key: str, named: str, allow_code: bool | None) -> Path | None:
    """Decide, importing nothing, whether the module ``name`` that the line file ``source``
    names (its ``key`` names ``named``) may run (module docstring): the ``.py`` file's
    resolved path (relative to the line file's folder), None for an importable module;
    else a one-line ``LineFileError`` saying what would run and how to consent."""
    trusted = read_trusted()
    where_list = trusted_file()
    if not name.endswith(".py"):
        if not trusted.has_module(name):
            raise refusal(
                source,
                key,
                named,
                f"installed module {name}",
                f"add {name.split('.')[0]!r} to modules in {where_list} "
                "(docs/security.md); --allow-code covers only the line file's "
                "own folder",
            )
        return None
    folder = Path(source).parent.resolve()
    path = Path(name)
    path = (path if path.is_absolute() else folder / path).resolve()
    own = path.is_relative_to(folder)
    if not (trusted.has_file(path) or (own and consented(allow_code))):
        if own:
            raise refusal(source, key, named, f"file {path}", HOW.format(file=where_list))
        raise refusal(
            source,
            key,
            named,
            f"file {path}, outside the line file's folder {folder}",
            f"--allow-code covers only that folder; add its folder "
            f"to folders in {where_list} (docs/security.md)",
        )
    return path


def load_module(
    name: str, source: str, key: str, named: str, allow_code: bool | None
) -> ModuleType:
    """The module ``name`` of the line file ``source``, imported only where ``permit``
    allows it (nothing is imported before that decision)."""
    path = permit(name, source, key, named, allow_code)
    return importlib.import_module(name) if path is None else import_file(path)


def import_file(path: Path) -> ModuleType:
    """The module of the ``.py`` file ``path`` (imported once per process). No consent is
    asked here: callers ask first (``resolve``) or the user named the file themselves."""
    if not path.is_file():
        raise FileNotFoundError(f"no file {path}")
    digest = hashlib.sha1(str(path).encode(), usedforsecurity=False).hexdigest()[:12]
    module_id = f"webline_user_{path.stem}_{digest}"
    if module_id in sys.modules:
        return sys.modules[module_id]
    found = importlib.util.spec_from_file_location(module_id, path)
    assert found is not None and found.loader is not None
    module = importlib.util.module_from_spec(found)
    sys.modules[module_id] = module
    try:
        found.loader.exec_module(module)
    except BaseException:
        del sys.modules[module_id]
        raise
    return module
