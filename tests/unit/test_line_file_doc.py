"""docs/line-file.md documents every key of the line-file schema with its right default."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from pydantic import BaseModel

from webline.spec import schema
from webline.spec.branched.schema import BranchedLineSpec

DOC = Path(__file__).resolve().parents[2] / "docs" / "line-file.md"


PROFILE_PARTS = ("Ramp", "Steps", "Step", "Table")


def model_name(model: type[BaseModel]) -> str:
    """A model's name; a profile part goes by its shape: ``Ramp[Speed]`` (generic) and
    ``SpeedRamp`` or ``StartStopTension`` (one class per quantity) are all ``Ramp``."""
    origin = getattr(model, "__pydantic_generic_metadata__", {}).get("origin")
    name = (origin or model).__name__
    for prefix in ("Speed", "Tension", "Torque"):
        if name.removeprefix(prefix) in PROFILE_PARTS:
            return name.removeprefix(prefix)
    return name


def sections() -> dict[str, list[list[str]]]:
    """Model name -> table rows (cells) of the section marked ``<!-- schema: Model -->``."""
    out = {}
    parts = re.split(r"<!-- schema: (\w+) -->", DOC.read_text(encoding="utf-8"))
    for name, body in zip(parts[1::2], parts[2::2], strict=True):
        body = body.split("\n#")[0]
        rows = [[c.strip() for c in line.strip().strip("|").split("|")]
                for line in body.splitlines() if line.startswith("| `")]
        out[name] = rows
    return out


def documented_models() -> list[type[BaseModel]]:
    """Every model reachable from LineSpec, once per name (a profile's step entries, documented
    in the text of its ``steps`` key, excepted)."""
    seen: dict[str, type[BaseModel]] = {}

    def visit(annotation: object) -> None:
        is_model = isinstance(annotation, type) and issubclass(annotation, BaseModel)
        if is_model and model_name(annotation) not in seen:  # type: ignore[arg-type]
            seen[model_name(annotation)] = annotation  # type: ignore[arg-type,assignment]
            for field in annotation.model_fields.values():  # type: ignore[union-attr]
                visit(field.annotation)
                for meta in field.metadata:
                    visit(meta)
        for arg in getattr(annotation, "__args__", ()) or ():
            visit(arg)
        origin = getattr(annotation, "__origin__", None)
        if origin is not None and origin is not annotation:
            visit(origin)

    visit(schema.LineSpec)
    visit(BranchedLineSpec)  # a branched line's keys (docs/line-file.md "webs")
    return [m for n, m in seen.items() if n != "Step"]


def test_every_schema_model_has_a_section():
    documented = sections()
    for model in documented_models():
        assert model_name(model) in documented, f"docs/line-file.md lacks {model_name(model)}"


@pytest.mark.parametrize("model", documented_models(), ids=model_name)
def test_section_lists_exactly_the_keys_with_their_defaults(model):
    rows = sections()[model_name(model)]
    keys = {key: row for row in rows for key in re.findall(r"`(\w+)`", row[0])}
    fields = {field.alias or key: field for key, field in model.model_fields.items()}
    assert set(keys) == set(fields), f"{model_name(model)}: documented {sorted(keys)}"
    for key, field in fields.items():
        row = keys[key]
        if len(re.findall(r"`(\w+)`", row[0])) > 1:
            continue  # a shared row pointing at another section
        default = row[2]
        if field.is_required():
            assert default == "required", f"{model_name(model)}.{key}"
            continue
        value = field.default
        token = re.match(r"`([^`]*)`", default)
        if value is None:
            assert default.startswith("none"), f"{model_name(model)}.{key}: {default}"
        elif isinstance(value, bool):
            assert token and token.group(1) == str(value).lower(), f"{model_name(model)}.{key}"
        elif isinstance(value, int | float):
            assert token and float(token.group(1)) == value, f"{model_name(model)}.{key}"
        elif isinstance(value, str):
            assert token and token.group(1) == f'"{value}"', f"{model_name(model)}.{key}"
        elif isinstance(value, list | dict):
            assert token and token.group(1) == ("[]" if isinstance(value, list) else "{}")
        else:
            assert default, f"{model_name(model)}.{key}: default not described"


# --- physical ranges ----------------------------------------------------------------------


def test_ranges_table_in_the_doc_is_the_one_in_the_code():
    from webline.spec.ranges import markdown

    text = DOC.read_text(encoding="utf-8")
    table = text.split("<!-- ranges:begin -->\n")[1].split("<!-- ranges:end -->")[0]
    assert table == markdown(), "run: python -m webline.spec.ranges, paste into the doc"


def _number_fields(model: type[BaseModel]) -> list[str]:
    """Fields of ``model`` that hold numbers (floats, ints, lists of them, profiles)."""
    out = []
    for name, field in model.model_fields.items():
        text = str(field.annotation)
        if any(word in text for word in ("float", "int", "Ramp", "Table")) and "bool" not in text:
            out.append(name)
    return out


@pytest.mark.parametrize("model", documented_models(), ids=model_name)
def test_every_number_of_the_schema_has_a_range(model):
    from webline.spec.ranges import PROFILE_VALUE_FIELDS, range_for

    for name in _number_fields(model):
        if name in PROFILE_VALUE_FIELDS:
            continue  # a profile's values take the range of the key holding the profile
        assert range_for(model, name) is not None, f"{model_name(model)}.{name} has no range"


def test_no_range_is_stale():
    from webline.spec.quantities import Step
    from webline.spec.ranges import RANGES, sections

    keys = {f"{section}.{name}" for model in [*documented_models(), Step]
            for name in model.model_fields for section in sections(model)}
    assert set(RANGES) <= keys, sorted(set(RANGES) - keys)
