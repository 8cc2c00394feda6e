"""Checks of a branched line's traction contacts, wraps, nips and measured friction (the
chain's keys, docs/slip.md and docs/winder.md "Nip", "Friction as drives measure it"; on a
branched line: docs/branching.md, "Slip and measured friction")."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, NoReturn

from webline.spec.friction import check_friction
from webline.spec.nip import check_nips

Fail = Callable[[str, str], NoReturn]


def check_traction(spec: Any, fail: Fail) -> None:
    """Fail on a traction contact without its wrap, with μ' > μ0, on a junction (a lamination
    nip or a slitter: a path's end, where the webs are gripped) or next to a Kelvin-Voigt
    span; on the chain's nip and friction-table checks (``spec.nip``, ``spec.friction``)."""
    check_nips(spec.rollers, fail)
    ends = {w.path[-1] for w in spec.webs} | {w.path[0] for w in spec.webs}
    for i, roller in enumerate(spec.rollers):
        check_friction(roller, f"rollers[{i}]", fail)
        contact = getattr(roller, "contact", None)
        if contact is None or contact.type != "traction":
            continue
        key = f"rollers[{i}]"
        if roller.wrap is None:
            fail(f"{key}.wrap", "a traction contact needs the wrap angle")
        kinetic = contact.kinetic_friction
        if kinetic is not None and kinetic > contact.friction:
            fail(f"{key}.contact.kinetic_friction",
                 f"must not exceed the static friction {contact.friction:g}")
        if roller.name in ends:
            fail(f"{key}.contact", f"{roller.name!r} is a junction (a lamination nip or a "
                 "slitter, where a path ends): it grips its webs; a traction contact is "
                 "modelled on a roller inside one web's path")
        for w, web in enumerate(spec.webs):
            if roller.name not in web.path:
                continue
            p = web.path.index(roller.name)
            for k in (p - 1, p):
                if web.spans[k].model != "elastic":
                    fail(f"webs[{w}].spans[{k}].model", f"a kelvin-voigt span next to a "
                         f"traction contact ({roller.name!r}) is not modelled; use an elastic "
                         "span there")
