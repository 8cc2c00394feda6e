"""``modelDescription.xml`` of a line's FMU, FMI 2.0 or 3.0 co-simulation (docs/fmu.md)."""

from __future__ import annotations

import datetime
from xml.etree import ElementTree as ET

from webline.fmu.variables import Variable
from webline.version import __version__

#: SI base-unit exponents of the units the variables use (FMI's UnitDefinitions)
UNITS: dict[str, dict[str, int]] = {
    "s": {"s": 1}, "N": {"kg": 1, "m": 1, "s": -2}, "m": {"m": 1}, "m/s": {"m": 1, "s": -1},
    "N.m": {"kg": 1, "m": 2, "s": -2}, "kg.m2": {"kg": 1, "m": 2},
    "N.m.s/rad": {"kg": 1, "m": 2, "s": -1, "rad": -1}, "N.m.s/m": {"kg": 1, "m": 1, "s": -1},
    "N.m/m": {"kg": 1, "m": 1, "s": -2}, "m/(s.N)": {"kg": -1, "s": 1},
    "m/(s2.N)": {"kg": -1},
}


def model_description(fmi: int, name: str, guid: str, step: float,
                      variables: list[Variable], description: str) -> bytes:
    """The XML of the FMI ``fmi`` (2 or 3) co-simulation FMU of line ``name`` with
    communication step ``step`` [s] (the default experiment's step size; any whole number of
    controller periods works) and ``variables`` (value reference = position)."""
    root = ET.Element("fmiModelDescription", {
        "fmiVersion": "2.0" if fmi == 2 else "3.0", "modelName": name,
        ("guid" if fmi == 2 else "instantiationToken"): guid,
        "description": description, "generationTool": f"webline {__version__}",
        "generationDateAndTime": datetime.datetime.now(datetime.UTC).strftime(
            "%Y-%m-%dT%H:%M:%SZ"),
        "variableNamingConvention": "flat"})
    cs = {"modelIdentifier": _identifier(name), "canHandleVariableCommunicationStepSize": "true",
          "canGetAndSetFMUstate": "false", "canSerializeFMUstate": "false"}
    if fmi == 2:
        cs["canNotUseMemoryManagementFunctions"] = "true"
    else:
        cs["providesIntermediateUpdate"] = "false"
        cs["hasEventMode"] = "false"
    ET.SubElement(root, "CoSimulation", cs)
    used = sorted({v.unit for v in variables if v.unit})
    units = ET.SubElement(root, "UnitDefinitions")
    for unit in used:
        ET.SubElement(ET.SubElement(units, "Unit", {"name": unit}), "BaseUnit",
                      {k: str(e) for k, e in UNITS[unit].items()})
    ET.SubElement(root, "DefaultExperiment", {"startTime": "0", "stepSize": repr(step)})
    mv = ET.SubElement(root, "ModelVariables")
    for vr, v in enumerate(variables):
        if fmi == 3 or v.causality != "independent":
            _variable(mv, fmi, vr, v)
    structure = ET.SubElement(root, "ModelStructure")
    outputs = [vr for vr, v in enumerate(variables) if v.causality == "output"]
    if fmi == 2:
        out = ET.SubElement(structure, "Outputs")
        for vr in outputs:
            ET.SubElement(out, "Unknown", {"index": str(vr + 1)})
        init = ET.SubElement(structure, "InitialUnknowns")
        for vr in outputs:
            ET.SubElement(init, "Unknown", {"index": str(vr + 1)})
    else:
        for vr in outputs:
            ET.SubElement(structure, "Output", {"valueReference": str(vr)})
        for vr in outputs:
            ET.SubElement(structure, "InitialUnknown", {"valueReference": str(vr)})
    ET.indent(root)
    return bytes(ET.tostring(root, encoding="UTF-8", xml_declaration=True))


def _variable(parent: ET.Element, fmi: int, vr: int, v: Variable) -> None:
    attrs = {"name": v.name, "valueReference": str(vr), "description": v.text,
             "causality": v.causality}
    if v.causality == "parameter":
        attrs.update(variability="fixed", initial="exact")  # (start state computed at export)
    elif v.causality == "input":
        attrs["variability"] = "continuous" if v.kind == "Real" else "discrete"
    else:
        attrs["variability"] = "continuous" if v.kind == "Real" else "discrete"
    type_attrs = {"unit": v.unit} if v.unit else {}
    if v.low is not None:
        type_attrs["min"] = repr(v.low)
    start = {"start": repr(v.start)} if v.causality in ("input", "parameter") else {}
    if v.causality == "independent":
        del attrs["variability"]
        attrs["variability"] = "continuous"
    if fmi == 2:
        element = ET.SubElement(parent, "ScalarVariable", attrs)
        ET.SubElement(element, v.kind, {**type_attrs, **start})
    else:
        tag = {"Real": "Float64", "Boolean": "Boolean", "Integer": "Int32"}[v.kind]
        ET.SubElement(parent, tag, {**attrs, **type_attrs, **start})


def _identifier(name: str) -> str:
    """A C identifier from line ``name`` (the shared library's name)."""
    out = "".join(c if c.isalnum() or c == "_" else "_" for c in name)
    return out if out and not out[0].isdigit() else f"line_{out}"
