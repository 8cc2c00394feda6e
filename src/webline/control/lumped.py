"""The lumped line of thesis Ch. 6: idle rollers removed, each zone one span.

Table 6.1 lumps the spans between two driven rollers into one ("the length of web between two
driven rollers is considered a single span", Ch. 4). ``without_idlers`` builds that line from a
line with idle rollers, so that the section models of ``webline.control.sections`` and the full
``webline.linearize`` describe the same plant and can be compared term by term.
"""

from __future__ import annotations

from webline.line import Line
from webline.spec.load import spec_from_dict


def without_idlers(line: Line) -> Line:
    """``line`` with every idle roller removed and the two spans it separated merged into one
    of their total length, carrying the tension reference of the one that had it.

    The merged span is named by the common prefix of the two names ("span3a" + "span3b" ->
    "span3") when that prefix is a new name, else by the name of the span with the loadcell.
    Scenarios are dropped, and so are disturbances that name a removed roller (an eccentric
    idler): both describe the line with its idlers.
    """
    data = line.spec.model_dump(exclude_none=True)
    rollers, spans = data["rollers"], data["spans"]
    removed = set()
    i = 1
    while i < len(rollers) - 1:
        if rollers[i]["type"] != "idle":
            i += 1
            continue
        removed.add(rollers[i]["name"])
        up, down = spans[i - 1], spans[i]
        merged = {"length": up["length"] + down["length"]}
        tension = down.get("tension", up.get("tension"))
        if tension is not None:
            merged["tension"] = tension
        merged["name"] = _merged_name(up, down, spans)
        spans[i - 1:i + 1] = [merged]
        del rollers[i]
    data["disturbances"] = [d for d in data.get("disturbances", [])
                            if d.get("roller") not in removed]
    data.pop("scenarios", None)
    return Line(spec_from_dict(data, f"{line.source} [without idlers]"), line.source)


def _merged_name(up: dict, down: dict, spans: list[dict]) -> str:
    a, b = up.get("name") or "", down.get("name") or ""
    size = min(len(a), len(b))
    size = next((k for k in range(size) if a[k] != b[k]), size)
    prefix = a[:size]
    others = {s.get("name") for s in spans if s is not up and s is not down}
    if prefix and prefix not in others:
        return prefix
    carrier = down if "tension" in down else up
    return str(carrier.get("name") or f"span{spans.index(carrier) + 1}")
