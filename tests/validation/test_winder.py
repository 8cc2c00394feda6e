"""Winder functions (issue 15, docs/winder.md): taper tension."""

from __future__ import annotations

import numpy as np
import pytest

import webline
from webline.physics.taper import spec_factor


@pytest.fixture(scope="module")
def thick_hswl(hswl):
    """hswl winding a 1 mm web (EA kept): at 2.54 m/s the rewind's radius grows by about
    2 mm/s, 8 cm in 40 s, enough for its taper to move the set tension by tens of per cent."""
    return hswl.replace({"web.thickness": "1 mm", "web.modulus": None, "web.ea": hswl.ea})


@pytest.mark.parametrize("taper", [
    {"type": "linear", "taper": 0.5, "max_diameter": "0.5 m"},
    {"type": "hyperbolic", "taper": 0.8},
    {"type": "table", "diameter": ["0.4 m", "0.5 m"], "factor": [1.0, 0.6]},
])
def test_taper_followed_in_steady_winding(thick_hswl, taper):
    line = thick_hswl.replace({"rollers.rewind.taper": taper})
    result = webline.simulate(line, 40.0)
    rewind = line.rewind
    k = line.zones[line.controlled_zone(line.n_nodes - 1)].loadcell
    radius = result.radius[:, -1]
    factor = np.array([spec_factor(rewind.taper, rewind.core_radius, r) for r in radius])
    reference = line.spec.spans[k].tension * factor
    assert factor.max() - factor.min() > 0.05  # the taper moved the set tension
    np.testing.assert_allclose(result.tension_ref[:, k], reference, rtol=1e-12)
    steady = result.time > 2.0
    error = np.abs(result.tension[steady, k] / reference[steady] - 1.0)
    assert error.max() < 0.02  # issue 15: within 2 % in steady winding
