"""The CLI starts without the heavy libraries: `webline --version` and `--help` must not wait
for pint, numba, scipy, python-control, matplotlib or xarray (issue 12: at most 3x the time
of `python -c "import numpy"`; each of these costs 0.1-1.5 s to import)."""

from __future__ import annotations

import subprocess
import sys

HEAVY = ("pint", "numba", "scipy", "control", "matplotlib", "xarray", "pandas", "h5py",
         "distributed")


def test_cli_import_leaves_heavy_libraries_unloaded() -> None:
    code = ("import sys, webline, webline.cli; "
            f"print(','.join(m for m in {HEAVY!r} if m in sys.modules))")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          check=True)
    assert done.stdout.strip() == ""


def test_front_door_names_load_on_first_use() -> None:
    code = ("import sys, webline; before = 'numba' in sys.modules; webline.simulate; "
            "print(before, 'numba' in sys.modules)")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          check=True)
    assert done.stdout.split() == ["False", "True"]
