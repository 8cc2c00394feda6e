"""Simulation: the plan (with its operating point), its linear models and fastest mode, the
compiled kernel, the reference path and results.

numba caches a compiled function next to its source file and revalidates it only against
that file; the compiled loop inlines controllers and physics from other files, so a change there
would leave a stale cache. The cache therefore lives in a folder named after a hash of every
source file the kernel is built from (unless the user sets NUMBA_CACHE_DIR).
"""

from __future__ import annotations

import hashlib
import os
from pathlib import Path

import numba


def _kernel_source_hash() -> str:
    root = Path(__file__).resolve().parent.parent
    digest = hashlib.sha256()
    for folder in ("sim", "physics"):
        for path in sorted((root / folder).rglob("*.py")):
            digest.update(path.read_bytes())
    return digest.hexdigest()[:16]


if "NUMBA_CACHE_DIR" not in os.environ:
    _base = Path(os.environ.get("XDG_CACHE_HOME", Path.home() / ".cache"))
    numba.config.CACHE_DIR = str(  # type: ignore[attr-defined]
        _base / "webline" / f"numba-{_kernel_source_hash()}")
