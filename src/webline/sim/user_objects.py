"""The controllers a line file names (``controller = { type = "python", object = ... }``, or
``function = ...`` for a compiled law): the one place that resolves them, imported only with
the user's consent (``spec.code_consent``, docs/security.md) and made once per run, each
bad name or refusal one ``LineFileError`` (exit 2)."""

from __future__ import annotations

import inspect
from collections.abc import Mapping
from types import ModuleType
from typing import TYPE_CHECKING

from webline.errors import LineFileError
from webline.line import Line
from webline.sim.compiled_control import CompiledController
from webline.sim.user_control import Controller
from webline.spec.code_consent import load_module, permit
from webline.spec.schema import PythonControllerSpec

if TYPE_CHECKING:  # (a single-path run does not load the branched line's modules)
    from webline.model.web_graph import BranchedLine


def file_controllers(line: Line | BranchedLine, allow_code: bool | None = None
                     ) -> dict[int, Controller]:
    """The controller object of each drive (index into ``line.drives``) whose line-file
    controller is ``type = "python"``; its code is imported only with the user's consent
    (``allow_code``, else the surrounding ``spec.code_consent.allowing_code``; or the
    allow-list), else one ``LineFileError`` saying what would run and how to consent."""
    out: dict[int, Controller] = {}
    for d, i in enumerate(line.drives):
        spec = getattr(line.spec.rollers[i], "controller", None)
        if isinstance(spec, PythonControllerSpec) and spec.function is not None:
            out[d] = make_law(spec, line.source, f"rollers[{i}].controller", allow_code)
        elif isinstance(spec, PythonControllerSpec):
            out[d] = make_controller(spec, line.source, f"rollers[{i}].controller",
                                     allow_code)
    return out


def named_code(line: Line | BranchedLine) -> list[tuple[str, str]]:
    """(key, "MODULE:NAME") of each Python object ``line``'s file names, e.g.
    ("rollers[4].controller.object", "pi.py:PI"), nothing imported: what ``validate`` and
    ``show`` point out."""
    out = []
    for i, roller in enumerate(line.spec.rollers):
        spec = getattr(roller, "controller", None)
        if isinstance(spec, PythonControllerSpec):
            field = "function" if spec.function is not None else "object"
            out.append((f"rollers[{i}].controller.{field}", str(getattr(spec, field))))
    return out


def check_consent(line: Line | BranchedLine, allow_code: bool | None = None) -> None:
    """Refuse (``LineFileError``, one line) a line whose named code the user has not
    consented to, importing nothing: what a command checks before it writes anything."""
    for key, text in named_code(line):
        permit(text.partition(":")[0], line.source, key, text, allow_code)


def _resolve(text: str, source: str, key: str, allow_code: bool | None
             ) -> tuple[ModuleType, object, str]:
    """The module, object and attribute path ``text`` ("MODULE:NAME") names, imported with
    consent (``spec.code_consent.load_module``); ``LineFileError`` naming ``key`` if it
    cannot be had. Nothing of it is called here."""
    module_name, _, attribute = text.partition(":")
    try:
        module = load_module(module_name, source, key, text, allow_code)
    except LineFileError:
        raise
    except Exception as exc:  # an import runs the user's module: any error is theirs
        raise LineFileError(source, key, f"cannot import {module_name!r}: "
                            f"{type(exc).__name__}: {exc}") from None
    target: object = module
    for part in attribute.split("."):
        if not hasattr(target, part):
            raise LineFileError(source, key, f"{module_name!r} has no {attribute!r}") from None
        target = getattr(target, part)
    return module, target, attribute


def _own(target: object, module: ModuleType) -> bool:
    """Whether ``target`` (a class or function) is defined in ``module`` itself (not
    imported into it: ``from shutil import rmtree`` gives no object to a line file)."""
    return getattr(target, "__module__", None) == module.__name__


def _is_controller_class(target: object) -> bool:
    """A class that defines ``reset`` and ``__call__`` (``object``'s own do not count)."""
    if not isinstance(target, type):
        return False
    mro = [k for k in target.__mro__ if k is not object]
    return all(any(name in vars(k) for k in mro) for name in ("reset", "__call__"))


def make_law(spec: PythonControllerSpec, source: str, key: str,
             allow_code: bool | None = None) -> CompiledController:
    """The ``CompiledController`` of the function ``spec.function`` names, with its
    ``params`` and ``states``; ``LineFileError`` naming ``source`` and ``key.function`` if
    the function cannot be had or is not a Python function ``law(t, meas, refs, params,
    state, out)`` of that module (numba's verdict on it comes when the run starts)."""
    assert spec.function is not None
    module, target, attribute = _resolve(spec.function, source, f"{key}.function", allow_code)
    py_func = getattr(target, "py_func", target)  # (a numba.njit law)
    if not (inspect.isfunction(py_func) and _own(py_func, module)
            and _positional(py_func) == 6):
        raise LineFileError(source, f"{key}.function", f"{spec.function!r} is not a "
                            f"function law(t, meas, refs, params, state, out) defined in "
                            f"its module")
    return CompiledController(target, params=spec.params, state=spec.states,  # type: ignore[arg-type]
                              name=attribute, checked=spec.checked)


def _positional(function: object) -> int:
    """How many positional parameters ``function`` takes (-1 with ``*args``)."""
    try:
        parameters = inspect.signature(function).parameters.values()  # type: ignore[arg-type]
    except (TypeError, ValueError):
        return -1
    kinds = [p.kind for p in parameters]
    if inspect.Parameter.VAR_POSITIONAL in kinds:
        return -1
    return sum(k in (inspect.Parameter.POSITIONAL_ONLY, inspect.Parameter.POSITIONAL_OR_KEYWORD)
               for k in kinds)


def make_controller(spec: PythonControllerSpec, source: str, key: str,
                    allow_code: bool | None = None) -> Controller:
    """The object ``spec.object`` names: a controller object, or a controller class or a
    factory function of that module called with ``spec.parameters`` (checked before the
    call: nothing else is called, so ``os:system`` never runs); ``LineFileError`` naming
    ``source`` and ``key`` if it cannot be had."""
    assert spec.object is not None

    def fail(where: str, problem: str) -> LineFileError:
        return LineFileError(source, f"{key}.{where}", problem)

    module, target, attribute = _resolve(spec.object, source, f"{key}.object", allow_code)
    if isinstance(target, Controller) and not isinstance(target, type):
        if spec.parameters:
            raise fail("parameters", f"{attribute!r} is a controller object already; "
                       f"parameters need a class or factory")
        return target
    if not ((_is_controller_class(target) or inspect.isfunction(target))
            and _own(target, module)):
        raise fail("object", f"{spec.object!r} is neither a controller nor a controller "
                   f"class or factory function defined in its module (reset(context) and "
                   f"__call__(t, measurements, references))")
    try:
        made = target(**spec.parameters)  # type: ignore[operator]
    except Exception as exc:  # the user's constructor
        raise fail("parameters", f"{attribute}(**parameters) raised {type(exc).__name__}: "
                   f"{exc}") from None
    if not isinstance(made, Controller):
        raise fail("object", f"{attribute}(...) gave a {type(made).__name__}, which lacks "
                   f"reset(context) and __call__(t, measurements, references)")
    return made


def branched_controllers(line: BranchedLine, controller: object | Mapping[str, object] | None,
                         allow_code: bool | None = None) -> object | Mapping[str, object] | None:
    """The user controllers of a run of branched ``line``: its file's python controllers by
    drive name, under ``controller`` (one object for every drive replaces them all; a dict
    adds to them or replaces them by drive name); None where there are none."""
    if controller is not None and not isinstance(controller, Mapping):
        return controller
    merged: dict[str, object] = {line.spec.rollers[line.drives[d]].name: obj
                                 for d, obj in file_controllers(line, allow_code).items()}
    merged.update(controller or {})
    return merged or None
