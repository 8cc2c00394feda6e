"""The front door names the twin layer's functions without importing the layer above it."""

from __future__ import annotations

import subprocess
import sys


def test_front_door_names_are_the_twin_functions():
    import webline
    from webline.twin.fit import fit
    from webline.twin.measurements import load_measurements
    from webline.twin.replay import replay

    assert webline.fit is fit
    assert webline.replay is replay
    assert webline.load_measurements is load_measurements
    assert {"fit", "replay", "load_measurements"} <= set(dir(webline))


def test_import_webline_does_not_import_the_twin_layer():
    code = "import sys, webline; print('webline.twin' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True)
    assert out.stdout.strip() == "False"
