"""Checks of ``web.stress_strain`` and the law array it compiles to (``spec.web_law``)."""

from __future__ import annotations

from collections.abc import Callable
from typing import NoReturn

import numpy as np

from webline.spec.schema import WebSpec
from webline.spec.web_law import LINEAR, LINEAR_TABLE_RTOL, POWER, TABLE

_KEYS = {"linear": (), "power": ("exponent", "reference_strain", "yield_strain"),
         "bilinear": ("yield_strain", "hardening"),
         "table": ("strain", "stress", "tension_per_width", "yield_strain")}
_REQUIRED = {"power": ("exponent", "reference_strain"), "bilinear": ("yield_strain", "hardening"),
             "table": ("strain",)}


def table_points(web: WebSpec) -> tuple[np.ndarray, np.ndarray]:
    """(strain [-], tension [N]) of a table law: stress x thickness x width, or tension per
    width x width."""
    law = web.stress_strain
    assert law is not None and law.strain is not None
    strain = np.array(law.strain, dtype=float)
    if law.stress is not None:
        return strain, np.array(law.stress, dtype=float) * web.thickness * web.width
    assert law.tension_per_width is not None
    return strain, np.array(law.tension_per_width, dtype=float) * web.width


def table_modulus(web: WebSpec) -> float:
    """E·A [N] of a table law's first segment (the small-strain stiffness), computed as the
    modulus path computes it (slope x thickness x width) so an equal table gives equal bits."""
    law = web.stress_strain
    assert law is not None and law.strain is not None
    if law.stress is not None:
        return law.stress[1] / law.strain[1] * web.thickness * web.width
    assert law.tension_per_width is not None
    return law.tension_per_width[1] / law.strain[1] * web.width


def check_web_law(web: WebSpec, fail: Callable[[str, str], NoReturn]) -> None:
    """Raise through ``fail(key, problem)`` where ``web.stress_strain`` is not a law."""
    law = web.stress_strain
    if law is None:
        return
    key = "web.stress_strain"
    for name in ("exponent", "reference_strain", "yield_strain", "hardening", "strain",
                 "stress", "tension_per_width"):
        if getattr(law, name) is not None and name not in _KEYS[law.law]:
            fail(f"{key}.{name}", f"a '{law.law}' law has no {name}")
    for name in _REQUIRED.get(law.law, ()):
        if getattr(law, name) is None:
            fail(f"{key}.{name}", f"a '{law.law}' law needs its {name}")
    if law.law == "bilinear" and not (law.hardening or 0.0) > 0.0:
        fail(f"{key}.hardening", "must be > 0 (the slope beyond yield over E): a web with "
             f"none could carry no tension above its yield, got {law.hardening!r}")
    if law.law == "table":
        _check_table(web, fail)
    elif (web.modulus is None) == (web.ea is None):
        fail("web", "give exactly one of 'modulus' or 'ea'")


def _check_table(web: WebSpec, fail: Callable[[str, str], NoReturn]) -> None:
    law = web.stress_strain
    assert law is not None and law.strain is not None
    key = "web.stress_strain"
    if (law.stress is None) == (law.tension_per_width is None):
        fail(key, "a table gives exactly one of 'stress' [Pa] or 'tension_per_width' [N/m]")
    values = law.stress if law.stress is not None else law.tension_per_width
    name = "stress" if law.stress is not None else "tension_per_width"
    assert values is not None
    if len(law.strain) < 2 or len(values) != len(law.strain):
        fail(f"{key}.{name}", f"needs one value per strain (at least 2), got {len(values)} "
             f"values for {len(law.strain)} strains")
    if law.strain[0] != 0.0 or values[0] != 0.0:
        fail(f"{key}.strain", f"the table starts at strain 0 with {name} 0 (an unstrained web "
             f"carries nothing), got ({law.strain[0]!r}, {values[0]!r})")
    for j in range(1, len(law.strain)):
        if not law.strain[j] > law.strain[j - 1]:
            fail(f"{key}.strain[{j}]", f"strains must increase, got {law.strain[j]!r} after "
                 f"{law.strain[j - 1]!r}")
        if not values[j] > values[j - 1]:
            fail(f"{key}.{name}[{j}]", f"must increase with strain (a law that is not "
                 f"monotonic has no unique strain per tension), got {values[j]!r} after "
                 f"{values[j - 1]!r}")
    if web.modulus is not None or web.ea is not None:
        fail("web.modulus", "a table law gives the web's stiffness itself: leave out "
             "'modulus' and 'ea'")


def law_array(web: WebSpec, ea: float) -> np.ndarray:
    """The law of ``web`` as ``physics.web_law`` evaluates it, in stretch s = ``ea``·ε [N]:
    ``[LINEAR]`` for no law, the linear law and a table on T = EA ε."""
    law = web.stress_strain
    if law is None or law.law == "linear":
        return np.array([float(LINEAR)])
    if law.law == "power":
        assert law.reference_strain is not None and law.exponent is not None
        return np.array([float(POWER), ea * law.reference_strain, law.exponent])
    if law.law == "bilinear":
        assert law.yield_strain is not None and law.hardening is not None
        s_y = ea * law.yield_strain
        stretch = np.array([0.0, s_y, 2.0 * s_y])
        tension = np.array([0.0, s_y, s_y * (1.0 + law.hardening)])
    else:
        strain, tension = table_points(web)
        stretch = ea * strain
        if np.all(np.abs(tension - stretch) <= LINEAR_TABLE_RTOL * np.abs(stretch)):
            return np.array([float(LINEAR)])
    return np.concatenate(([float(TABLE), float(len(stretch))], stretch, tension))

