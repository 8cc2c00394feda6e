"""Checks of a branched line's web laws (docs/branching.md, "Web laws"): each material's
``stress_strain`` (the chain's ``spec.web_law_checks``, keys named under the material's own
key) and each span's Kelvin-Voigt ``model`` and ``retardation``."""

from __future__ import annotations

from collections.abc import Callable
from typing import NoReturn

from webline.spec.branched.schema import BranchedLineSpec
from webline.spec.web_law_checks import check_web_law

Fail = Callable[[str, str], NoReturn]


def check_web_laws(spec: BranchedLineSpec, fail: Fail) -> None:
    """Raise through ``fail(key, problem)`` for the first bad law or span model."""
    materials = [("web", spec.web)] + [(f"webs[{w}].web", web.web)
                                       for w, web in enumerate(spec.webs)]
    for key, material in materials:
        if material is None or material.stress_strain is None:
            continue

        def under(name: str, problem: str, key: str = key) -> NoReturn:
            fail(key + name[len("web"):], problem)  # 'web.stress_strain.x' under its key

        check_web_law(material, under)
    for w, web in enumerate(spec.webs):
        for k, span in enumerate(web.spans):
            key = f"webs[{w}].spans[{k}].retardation"
            if span.model == "kelvin-voigt" and span.retardation is None:
                fail(key, "a kelvin-voigt span needs its retardation time (tau = viscosity / "
                     "modulus, e.g. '5 ms')")
            if span.model == "elastic" and span.retardation is not None:
                fail(key, "only a span with model = 'kelvin-voigt' has one")
