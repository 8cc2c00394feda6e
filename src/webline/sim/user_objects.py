"""The controllers a line file names (``controller = { type = "python", object = ... }``, or
``function = ...`` for a compiled law): imported and made once per run, each bad name one
``LineFileError`` (exit 2)."""

from __future__ import annotations

import importlib
import importlib.util
import sys
from collections.abc import Mapping
from pathlib import Path
from types import ModuleType
from typing import TYPE_CHECKING

from webline.errors import LineFileError
from webline.line import Line
from webline.sim.compiled_control import CompiledController
from webline.sim.user_control import Controller
from webline.spec.schema import PythonControllerSpec

if TYPE_CHECKING:  # (a single-path run does not load the branched line's modules)
    from webline.model.web_graph import BranchedLine


def file_controllers(line: Line | BranchedLine) -> dict[int, Controller]:
    """The controller object of each drive (index into ``line.drives``) whose line-file
    controller is ``type = "python"``."""
    out: dict[int, Controller] = {}
    for d, i in enumerate(line.drives):
        spec = getattr(line.spec.rollers[i], "controller", None)
        if isinstance(spec, PythonControllerSpec) and spec.function is not None:
            out[d] = make_law(spec, line.source, f"rollers[{i}].controller")
        elif isinstance(spec, PythonControllerSpec):
            out[d] = make_controller(spec, line.source, f"rollers[{i}].controller")
    return out


def make_law(spec: PythonControllerSpec, source: str, key: str) -> CompiledController:
    """The ``CompiledController`` of the function ``spec.function`` names, with its
    ``params`` and ``states``; ``LineFileError`` naming ``source`` and ``key.function`` if
    the function cannot be had (numba's verdict on it comes when the run starts)."""
    assert spec.function is not None
    module_name, _, attribute = spec.function.partition(":")
    try:
        module = _module(module_name, source)
    except Exception as exc:  # an import runs the user's module: any error is theirs
        raise LineFileError(source, f"{key}.function", f"cannot import {module_name!r}: "
                            f"{type(exc).__name__}: {exc}") from None
    target: object = module
    for part in attribute.split("."):
        if not hasattr(target, part):
            raise LineFileError(source, f"{key}.function",
                                f"{module_name!r} has no {attribute!r}") from None
        target = getattr(target, part)
    if not callable(target) or isinstance(target, type):
        raise LineFileError(source, f"{key}.function", f"{spec.function!r} is not a "
                            f"function law(t, meas, refs, params, state, out)")
    return CompiledController(target, params=spec.params, state=spec.states,
                              name=attribute)


def make_controller(spec: PythonControllerSpec, source: str, key: str) -> Controller:
    """The object ``spec.object`` names, called with ``spec.parameters`` if it is a class or
    factory; ``LineFileError`` naming ``source`` and ``key`` if it cannot be had."""
    assert spec.object is not None
    module_name, _, attribute = spec.object.partition(":")

    def fail(where: str, problem: str) -> LineFileError:
        return LineFileError(source, f"{key}.{where}", problem)

    try:
        module = _module(module_name, source)
    except Exception as exc:  # an import runs the user's module: any error is theirs
        raise fail("object", f"cannot import {module_name!r}: {type(exc).__name__}: "
                   f"{exc}") from None
    target: object = module
    for part in attribute.split("."):
        if not hasattr(target, part):
            raise fail("object", f"{module_name!r} has no {attribute!r}") from None
        target = getattr(target, part)
    if isinstance(target, Controller) and not isinstance(target, type):
        if spec.parameters:
            raise fail("parameters", f"{attribute!r} is a controller object already; "
                       f"parameters need a class or factory")
        return target
    if not callable(target):
        raise fail("object", f"{spec.object!r} is neither a controller nor a class")
    try:
        made = target(**spec.parameters)
    except Exception as exc:  # the user's constructor
        raise fail("parameters", f"{attribute}(**parameters) raised {type(exc).__name__}: "
                   f"{exc}") from None
    if not isinstance(made, Controller):
        raise fail("object", f"{attribute}(...) gave a {type(made).__name__}, which lacks "
                   f"reset(context) and __call__(t, measurements, references)")
    return made


def _module(name: str, source: str) -> ModuleType:
    """Module ``name``: a ``.py`` file (relative to the line file's folder) or an importable
    module."""
    if not name.endswith(".py"):
        return importlib.import_module(name)
    path = Path(name)
    if not path.is_absolute():
        path = Path(source).parent / path
    if not path.is_file():
        raise FileNotFoundError(f"no file {path}")
    module_id = f"webline_user_{path.stem}_{abs(hash(str(path.resolve())))}"
    if module_id in sys.modules:
        return sys.modules[module_id]
    found = importlib.util.spec_from_file_location(module_id, path)
    assert found is not None and found.loader is not None
    module = importlib.util.module_from_spec(found)
    sys.modules[module_id] = module
    try:
        found.loader.exec_module(module)
    except BaseException:
        del sys.modules[module_id]
        raise
    return module


def branched_controllers(line: BranchedLine, controller: object | Mapping[str, object] | None
                         ) -> object | Mapping[str, object] | None:
    """The user controllers of a run of branched ``line``: its file's python controllers by
    drive name, under ``controller`` (one object for every drive replaces them all; a dict
    adds to them or replaces them by drive name); None where there are none."""
    if controller is not None and not isinstance(controller, Mapping):
        return controller
    merged: dict[str, object] = {line.spec.rollers[line.drives[d]].name: obj
                                 for d, obj in file_controllers(line).items()}
    merged.update(controller or {})
    return merged or None
