"""A single-path line read as a line of one web (issue 33: "a chain is a line of one web").

A single-path line file gives its web in ``[web]``, its spans in ``[[spans]]`` and its
rollers in web order. The same line written with ``[[webs]]`` has one web, ``WEB``, whose
``path`` is every roller in that order and whose ``spans`` are the file's spans; every other
section (``[web]`` as the webs' default material, ``[[rollers]]``, ``speed``, ``control``,
``checks``, ``disturbances``, ``sensors``, ``scenarios``) is carried over as it is. What
names a span by path changes with it: a scenario's ``set`` key ``spans.X.tension`` becomes
``webs.web.spans.X.tension``. A span the file leaves unnamed is named as the single-path
line names it (``span1``, ``span2``, ...), so that breaks, loadcells and results keep finding
it by that name.

``one_web_data`` translates the data (a dict as read from TOML, or a dumped ``LineSpec``)
before the branched schema sees it, so the branched line's checks apply; ``one_web_spec``
checks the line as a single-path line first, translates it and validates the result, each
problem named at the key the user wrote (``chain_key``). What a single-path line may hold
and the line of webs does not run is refused there, in one line naming the key (encoder
sensors and sensor delays, ``spec.branched.check``).
"""

from __future__ import annotations

import copy
from collections.abc import Mapping
from typing import TYPE_CHECKING, Any

from webline.errors import LineFileError, Problem
from webline.spec.load import branched_from_dict, spec_from_dict
from webline.spec.locate import key_lines, locate

if TYPE_CHECKING:
    from webline.spec.branched.schema import BranchedLineSpec
    from webline.spec.schema import LineSpec

#: the name of the one web of a single-path line read as a line of webs
WEB = "web"

#: a path into the single-path line's spans, and the same place in the line of one web
_SPANS, _WEB_SPANS = "spans", f"webs.{WEB}.spans"


def span_name(spans: list[Any], k: int) -> str:
    """The name of span ``k`` of a single-path line's ``spans`` (dicts): its own, or
    ``span{k+1}`` as ``webline.line.Line.span_name`` names an unnamed one."""
    name = spans[k].get("name") if isinstance(spans[k], Mapping) else None
    return str(name) if name is not None else f"span{k + 1}"


def one_web_path(path: str) -> str:
    """A nested key path of a single-path line (``Line.replace``, a scenario's ``set``,
    ``--set``) as the line of one web names the same value: ``spans.span2.tension`` ->
    ``webs.web.spans.span2.tension``, ``spans[1].length`` -> ``webs.web.spans[1].length``;
    every other path (``rollers.X``, ``web.ea``, ``speed``) is the same in both."""
    if path == _SPANS or path.startswith((f"{_SPANS}.", f"{_SPANS}[")):
        return _WEB_SPANS + path[len(_SPANS):]
    return path


def chain_key(key: str) -> str:
    """A key of the line of one web (a problem's key, a path) as the single-path file names
    it: ``webs[0].spans[2].length`` -> ``spans[2].length``, ``webs[0].path`` ->
    ``rollers`` (the path is the rollers' order); the inverse of ``one_web_path``."""
    for prefix, chain in ((f"webs[0].{_SPANS}", _SPANS), (_WEB_SPANS, _SPANS),
                          ("webs[0].path", "rollers"), ("webs[0]", _SPANS),
                          ("webs", _SPANS)):
        if key == prefix or key.startswith((f"{prefix}.", f"{prefix}[")):
            return chain + key[len(prefix):]
    if ": " in key:  # a scenario's set: 'scenarios.X.set: webs.web.spans.Y'
        head, _, path = key.partition(": ")
        return f"{head}: {chain_key(path)}"
    return key


def one_web_data(data: Mapping[str, Any], file: str = "<dict>") -> dict[str, Any]:
    """The line file of one web (a dict, as ``[[webs]]`` files read) equivalent to the
    single-path line ``data`` (as read from TOML, or a dumped ``LineSpec``); ``data`` is left
    as it is. ``data`` should be a valid single-path line (``one_web_spec`` checks it
    first); ``LineFileError`` naming ``file`` and the key where ``data`` is no single-path
    line or where an unnamed span's name (``span{k+1}``) is another span's."""
    if not isinstance(data, Mapping):
        raise LineFileError(file, "(top level)", "a line file must be a table of keys")
    if "webs" in data:
        raise LineFileError(file, "webs", "already a line of webs ([[webs]]): nothing to "
                            "translate")
    out = copy.deepcopy(dict(data))
    spans, rollers = out.pop(_SPANS, None), out.get("rollers")
    if not isinstance(spans, list) or not spans:
        raise LineFileError(file, _SPANS, "required key is missing (a single-path line's "
                            "spans)")
    if not isinstance(rollers, list) or not all(
            isinstance(r, Mapping) and isinstance(r.get("name"), str) for r in rollers):
        raise LineFileError(file, "rollers", "every roller needs its name (the web's path)")
    given = [s.get("name") for s in spans if isinstance(s, Mapping)]
    for k, span in enumerate(spans):
        if isinstance(span, dict) and span.get("name") is None:
            name = span_name(spans, k)
            if name in given:
                raise LineFileError(file, f"spans[{k}].name", f"an unnamed span is "
                                    f"{name!r} on a single-path line, and another span has "
                                    "that name: name this one")
            span["name"] = name
    out["webs"] = [{"name": WEB, "path": [r["name"] for r in rollers], "spans": spans}]
    scenarios = out.get("scenarios")
    for scenario in scenarios.values() if isinstance(scenarios, dict) else ():
        changes = scenario.get("set") if isinstance(scenario, dict) else None
        if isinstance(changes, dict):
            scenario["set"] = {one_web_path(str(path)): value for path, value in changes.items()}
    return out


def one_web_spec(data: Mapping[str, Any], file: str = "<dict>", text: str | None = None
                 ) -> BranchedLineSpec:
    """The checked spec of the line of one web equivalent to the single-path line ``data``
    (``one_web_specs``)."""
    return one_web_specs(data, file, text)[1]


def one_web_specs(data: Mapping[str, Any], file: str = "<dict>", text: str | None = None
                  ) -> tuple[LineSpec, BranchedLineSpec]:
    """The checked spec of the line of one web equivalent to the single-path line ``data``
    (a dict as read from TOML, or a dumped ``LineSpec``; ``text``: the file's text, for the
    TOML line of a problem), with the single-path line's own spec. The line is checked as a
    single-path line first, then its translation (``one_web_data``) as a line of webs;
    either raises ``LineFileError`` naming ``file`` and each problem at the key the
    single-path file gives it."""
    lines = key_lines(text) if text is not None else {}
    try:
        single_path = spec_from_dict(data, file)  # valid, its problems at its own keys
    except LineFileError as exc:
        raise LineFileError.of(file, [Problem(p.key, p.problem, p.line or locate(lines, p.key))
                                      for p in exc.problems]) from None
    try:
        return single_path, branched_from_dict(one_web_data(data, file), file)
    except LineFileError as exc:  # the same problems, at the single-path file's keys
        problems = [Problem(chain_key(p.key), p.problem,
                            p.line or locate(lines, chain_key(p.key))) for p in exc.problems]
        raise LineFileError.of(file, problems) from None
