"""Writing a file whole or not at all: a temporary file in the same folder, renamed into place.

``os.replace`` swaps the directory entry, so a reader (or a crash, or a Ctrl-C) sees either the
previous file or the complete new one, never a truncated one; and it replaces a symlink at the
final name rather than writing through it. The temporary file is created with ``O_EXCL``
(``tempfile.mkstemp``), so it cannot be a pre-planted link either.
"""

from __future__ import annotations

import errno
import os
import tempfile
from collections.abc import Callable
from pathlib import Path

from webline.errors import WeblineError

#: prefix of the temporary files (hidden; a leftover is recognisable)
TEMP_PREFIX = ".webline-tmp-"


def _file_mode() -> int:
    """Permissions of a new file under the process umask (``mkstemp`` makes 0600 files)."""
    mask = os.umask(0o022)
    os.umask(mask)
    return 0o666 & ~mask


class OutputError(WeblineError):
    """An output file or folder cannot be written safely (exit status 2)."""

    exit_code = 2


def refuse_symlink(path: Path) -> None:
    """Raise ``OutputError`` if ``path`` is a symbolic link (webline never writes through one)."""
    if path.is_symlink():
        raise OutputError(f"{path}: is a symbolic link; webline does not write through links "
                          "(remove it or choose another output)")


def atomic_write(path: str | Path, write: Callable[[Path], object]) -> Path:
    """Call ``write(tmp)`` on a fresh temporary file next to ``path``, then rename it to
    ``path``. On any exception (KeyboardInterrupt included) the temporary file is removed and
    ``path`` is left as it was; an ``OSError`` (a full disk) is raised again naming ``path``. A
    symlink at ``path`` is refused (``OutputError``)."""
    path = Path(path)
    refuse_symlink(path)
    fd, name = tempfile.mkstemp(prefix=TEMP_PREFIX, suffix=path.suffix, dir=path.parent)
    os.close(fd)
    tmp = Path(name)
    try:
        os.chmod(tmp, _file_mode())
        write(tmp)
        os.replace(tmp, path)
    except OSError as exc:  # a full disk: named by the file the user asked for, not the temp
        tmp.unlink(missing_ok=True)
        if exc.errno is None:
            raise
        raise OSError(exc.errno, exc.strerror, str(path)) from exc
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise
    return path


def atomic_write_bytes(path: str | Path, data: bytes | memoryview) -> Path:
    """Write ``data`` to ``path`` atomically (see ``atomic_write``)."""
    return atomic_write(path, lambda tmp: tmp.write_bytes(data))


def atomic_write_text(path: str | Path, text: str) -> Path:
    """Write ``text`` (UTF-8) to ``path`` atomically (see ``atomic_write``)."""
    return atomic_write(path, lambda tmp: tmp.write_text(text, encoding="utf-8"))


def write_failure(exc: OSError, then: str | None = None) -> str:
    """One line for a file that could not be written: the file, the system's reason and, for a
    full disk, what to do (``then``, else free some space and run again)."""
    where = exc.filename or "writing a file"
    hint = ""
    if exc.errno in (errno.ENOSPC, errno.EDQUOT):
        hint = "; " + (then or "free some space (or choose another --out) and run again")
    return f"{where}: {exc.strerror or exc}{hint}"
