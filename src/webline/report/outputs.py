"""The output folder of a run: a safe default name, refusal of links and of folders webline did
not write, and a manifest so that a rerun leaves no stale files.

The manifest (``.webline-manifest.json``) lists every file webline wrote in the folder, relative
to it, and the kind of output the folder holds (``run``, ``sweep``, ``study NAME``). Before a
file is written its name joins the manifest (so even an interrupted run leaves every file it
created listed); ``finish`` then removes the files of the previous run that this run did not
rewrite and writes the manifest of this run. What a command may remove or overwrite is only
what the manifest lists: a folder of another kind is refused unless ``force`` (which takes it
over: its listed files may be replaced or removed), and a file the manifest does not list is
never overwritten, not even with ``force``.
"""

from __future__ import annotations

import json
import re
import unicodedata
from dataclasses import dataclass
from pathlib import Path

from webline.files import OutputError, atomic_write_text, refuse_symlink

MANIFEST = ".webline-manifest.json"
#: longest default folder name [characters]
NAME_LIMIT = 80
#: characters replaced in a folder name: separators, characters Windows forbids, and ``$``
#: (shell expansion)
_UNSAFE = re.compile(r'[/\\:*?"<>|$`]')


def safe_name(text: str, limit: int = NAME_LIMIT) -> str:
    """``text`` made into one harmless folder name: path separators and characters that are
    special to shells or file systems become ``_``, control and format characters are dropped,
    leading dots and spaces stripped (no ``..``, no hidden folder), at most ``limit``
    characters; letters of any script are kept. Never empty (``"line"``)."""
    text = unicodedata.normalize("NFC", text)
    kept = "".join("_" if _UNSAFE.match(c) or c.isspace() else c for c in text
                   if unicodedata.category(c)[0] != "C")
    kept = re.sub(r"_+", "_", kept).lstrip("._-").rstrip(". ")[:limit].rstrip(". ")
    return kept or "line"


def default_folder(line_name: str, scenario: str | None = None,
                   root: Path = Path("out")) -> Path:
    """``root/LINE[-SCENARIO]`` with both names made safe: always a direct child of ``root``."""
    name = safe_name(line_name) + (f"-{safe_name(scenario)}" if scenario else "")
    return root / safe_name(name)


@dataclass(frozen=True)
class ReportFiles:
    """What ``writer.write_report`` wrote."""

    report: Path  #: the HTML report
    summary: Path  #: the summary, operating point and modes as JSON (chosen units)
    figures: tuple[Path, ...]  #: every figure as PNG (and SVG on request)


class OutputFolder:
    """A folder webline writes one kind of output into (see the module docstring).

    ``open`` refuses (``OutputError``, exit 2) a folder that is a symbolic link, a path that is
    not a folder, and, unless ``force``, a non-empty folder without a manifest and a folder
    holding another kind of output. ``claim`` refuses a file the manifest does not list."""

    def __init__(self, path: Path, previous: list[str], kind: str = "run") -> None:
        self.path = path
        self.previous = previous  #: files of the previous run's manifest
        self.written: list[str] = []  #: files this run wrote (relative paths)
        self.kind = kind  #: the command whose output this is: run, sweep, study NAME

    @classmethod
    def open(cls, path: Path, *, kind: str = "run", force: bool = False,
             writes: tuple[str, ...] = ()) -> OutputFolder:
        """Check and create ``path`` for writing the output of ``kind`` (``run``, ``sweep``,
        ``study NAME``); read its manifest. ``writes``: files the command will write, refused
        here, before anything is computed, where one is in the way (``claim``)."""
        refuse_symlink(path)
        if path.exists() and not path.is_dir():
            raise OutputError(f"{path}: cannot write to the output folder (not a folder)")
        try:
            path.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise OutputError(f"{path}: cannot write to the output folder "
                              f"({exc.strerror or exc})") from None
        manifest = path / MANIFEST
        refuse_symlink(manifest)
        previous: list[str] = []
        if manifest.exists():
            try:
                data = json.loads(manifest.read_text("utf-8"))
                previous = [str(p) for p in data["files"]]
                held = data.get("kind") or _legacy_kind(previous)
            except (ValueError, KeyError, TypeError, AttributeError, OSError) as exc:
                raise OutputError(f"{manifest}: unreadable manifest ({exc}); remove it or "
                                  "use --force") from None
            if held is not None and held != kind and not force:
                listed = ", ".join(previous[:3]) + (", ..." if len(previous) > 3 else "")
                raise OutputError(
                    f"{path}: holds the output of `webline {held}` ({listed}), which "
                    f"`webline {kind}` would replace or remove; choose another folder, or use "
                    f"--force to replace it")
        elif any(path.iterdir()) and not force:
            raise OutputError(f"{path}: folder is not empty and webline did not write it (no "
                              f"{MANIFEST}); choose an empty folder or use --force")
        folder = cls(path, previous, kind)
        for relative in writes:
            folder.refuse_foreign(relative)
        return folder

    def refuse_foreign(self, relative: str) -> None:
        """Raise ``OutputError`` if a file at ``relative`` exists that webline did not write:
        one the manifest does not list (nor this run wrote). Such a file is never replaced."""
        target = self.path / relative
        if ((target.exists() or target.is_symlink()) and relative not in self.previous
                and relative not in self.written):
            raise OutputError(f"{target}: a file webline did not write is in the way (not in "
                              f"{MANIFEST}); webline never replaces such a file, not even with "
                              "--force: move it or choose another folder")

    def claim(self, relative: str) -> Path:
        """The path of ``relative`` in the folder, recorded in the manifest before it is
        written; its parent folder is created (a symlinked parent is refused). A file there
        that webline did not write is refused (``refuse_foreign``)."""
        self.refuse_foreign(relative)
        return self.adopt(relative)

    def adopt(self, relative: str) -> Path:
        """``claim`` for a file the command's own machinery wrote since the folder was
        opened, before it could be listed (a study's chunks, ``cli_sweep``)."""
        target = self.path / relative
        for parent in reversed(target.relative_to(self.path).parents[:-1]):
            refuse_symlink(self.path / parent)
            (self.path / parent).mkdir(exist_ok=True)
        refuse_symlink(target)
        if relative not in self.written:
            self.written.append(relative)
            self._save(sorted(set(self.previous) | set(self.written)))
        return target

    def recover_claims(self) -> None:
        """Adopt what another process of this command (the report's copy, ``report.early``)
        listed in the manifest on disk before it failed: those files are this run's."""
        try:
            listed = json.loads((self.path / MANIFEST).read_text("utf-8"))["files"]
        except (ValueError, KeyError, TypeError, OSError):
            return
        self.written.extend(str(f) for f in listed
                            if f not in self.previous and f not in self.written)

    def finish(self) -> list[Path]:
        """Remove the previous run's files that this run did not write, write this run's
        manifest; returns the removed paths."""
        removed = []
        for relative in sorted(set(self.previous) - set(self.written)):
            target = self.path / relative
            if _inside(self.path, target) and (target.is_file() or target.is_symlink()):
                target.unlink()
                removed.append(target)
        self._save(sorted(self.written))
        self.previous = list(self.written)
        return removed

    def _save(self, files: list[str]) -> None:
        atomic_write_text(self.path / MANIFEST,
                          json.dumps({"kind": self.kind, "files": files}, indent=1) + "\n")


def _legacy_kind(files: list[str]) -> str | None:
    """The kind of output a manifest without one (webline before the kinds) lists: a sweep's
    or a run's by their files; None where it cannot tell (a study, whose name it lacks)."""
    if "sweep.nc" in files or any(f.startswith("chunks/") for f in files):
        return "sweep"
    if "summary.json" in files or "results.nc" in files or "results.csv" in files:
        return "run"
    return None


def _inside(folder: Path, target: Path) -> bool:
    """Whether ``target`` lies in ``folder`` (a tampered manifest cannot delete elsewhere)."""
    try:
        target.parent.resolve().relative_to(folder.resolve())
    except ValueError:
        return False
    return ".." not in Path(target).relative_to(folder).parts
