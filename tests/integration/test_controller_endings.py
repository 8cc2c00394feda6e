"""Every way a user's controller can end a run is a clean failure (issue 34): ``sys.exit``,
``SystemExit(0)`` mid-run, ``breakpoint()``, a debugger's ``BdbQuit``, ``GeneratorExit``
and a raising ``reset`` end with one ``ControllerError`` naming the controller, its drive and
the tick, the partial results kept (written by the CLI) and a non-zero exit; a compiled law
that numba cannot compile is bad input (exit 2); a law's checked mode names an out-of-bounds
write that would otherwise corrupt memory."""

from __future__ import annotations

import bdb
import sys
from pathlib import Path

import numpy as np
import pytest
import tomli_w
import xarray as xr
from typer.testing import CliRunner

import webline
from webline.cli import app
from webline.errors import ControllerError, LawCompileError
from webline.sim.compiled_control import CompiledController

ENDINGS = (
    "import sys\n"
    "class Ends:\n"
    "    def __init__(self, how='exit', at=20):\n"
    "        self.how, self.at = how, at\n"
    "    def reset(self, context):\n"
    "        self.dt = context.sample_period\n"
    "        self.torque = context.drives[0].equilibrium_command\n"
    "        if self.how == 'reset':\n"
    "            raise ValueError('bad gains')\n"
    "    def __call__(self, t, m, r):\n"
    "        if round(t / self.dt) == self.at:\n"
    "            if self.how == 'exit':\n"
    "                raise SystemExit(0)\n"
    "            if self.how == 'sys.exit':\n"
    "                sys.exit()\n"
    "            if self.how == 'breakpoint':\n"
    "                breakpoint()\n"
    "            if self.how == 'generator':\n"
    "                raise GeneratorExit\n"
    "            if self.how == 'bdbquit':\n"
    "                import bdb\n"
    "                raise bdb.BdbQuit\n"
    "        return self.torque\n"
)


def line_file(folder: Path, controller: dict[str, object]) -> Path:
    source = webline.load_line("hswl")
    rollers = [r.model_dump(exclude_none=True) for r in source.spec.rollers]
    rollers[-1]["controller"] = {"type": "python", **controller}
    (folder / "ends.py").write_text(ENDINGS)
    path = folder / "line.toml"
    path.write_bytes(
        tomli_w.dumps(source.spec.model_dump(exclude_none=True) | {"rollers": rollers}).encode()
    )
    return path


class Ends:
    """As ``ENDINGS``' class, for the API."""

    def __init__(self, exc: BaseException, at: int = 20) -> None:
        self.exc, self.at = exc, at

    def reset(self, context: object) -> None:
        self.dt = context.sample_period  # type: ignore[attr-defined]
        self.torque = context.drives[0].equilibrium_command  # type: ignore[attr-defined]
        if self.at < 0:
            raise self.exc

    def __call__(self, t: float, m: np.ndarray, r: np.ndarray) -> float:
        if round(t / self.dt) == self.at:
            raise self.exc
        return self.torque


@pytest.mark.parametrize("exc", [SystemExit(0), SystemExit("bye"), GeneratorExit(), bdb.BdbQuit()])
@pytest.mark.parametrize("branched", [False, True])
def test_base_exceptions_of_user_code_are_controller_errors(
    exc: BaseException, branched: bool
) -> None:
    """Raised at tick 20: a ControllerError naming the controller (its drive), the tick and
    the exception; the partial result holds ticks 0..19 (chain: its time ends at 19 dt)."""
    line, drive = ("laminator", "rewind") if branched else ("hswl", "rewind")
    with pytest.raises(ControllerError) as info:
        webline.simulate(line, 0.1, controller={drive: Ends(exc)})
    message = str(info.value)
    assert f"controller '{drive}'" in message and "tick 20" in message
    assert f"raised {type(exc).__name__}" in message and "\n" not in message
    partial = info.value.partial
    assert partial is not None
    if not branched:
        assert partial.time[-1] == pytest.approx(19 * partial.plan.dt)


@pytest.mark.parametrize("branched", [False, True])
def test_a_raising_reset_is_a_controller_error_at_tick_0(branched: bool) -> None:
    """Named, at tick 0; the partial result holds the start (one record, t = 0)."""
    line = "laminator" if branched else "hswl"
    with pytest.raises(ControllerError) as info:
        webline.simulate(line, 0.1, controller={"rewind": Ends(ValueError("bad gains"), -1)})
    assert len(info.value.partial.time) == 1 and info.value.partial.time[0] == 0.0
    message = str(info.value)
    assert (
        "controller 'rewind'" in message
        and "raised ValueError: bad gains in reset(context) at tick 0" in message
    ), message
    with pytest.raises(ControllerError, match="in reset"):
        webline.Session(line, controller={"rewind": Ends(SystemExit(0), -1)}).step(1)


def test_a_raising_reset_of_a_compiled_run_is_a_controller_error() -> None:
    def law(t, meas, refs, params, state, out):  # type: ignore[no-untyped-def]
        out[0] = params[0]

    def params(context: object) -> list[float]:
        raise SystemExit(3)

    with pytest.raises(ControllerError, match=r"raised SystemExit: 3 in reset\(context\)"):
        webline.simulate("hswl", 0.1, controller={"rewind": CompiledController(law, params=params)})


@pytest.mark.parametrize(
    ("how", "says"),
    [
        ("exit", "raised SystemExit: 0 at tick 20"),
        ("sys.exit", "raised SystemExit at tick 20"),
        ("breakpoint", "raised RuntimeError: breakpoint() called during a command-line run"),
        ("reset", "raised ValueError: bad gains in reset(context) at tick 0"),
    ],
)
def test_cli_run_that_a_controller_ends_fails_with_its_results_written(
    tmp_path: Path, how: str, says: str
) -> None:
    """``webline run``: exit 1 (a failed run, never 0), the controller and tick named, and
    the results so far written (results.nc with the ticks before it, summary failed).
    ``breakpoint()`` opens no prompt: it fails the run (the test would hang otherwise)."""
    path = line_file(tmp_path, {"object": "ends.py:Ends", "parameters": {"how": how}})
    out = tmp_path / "out"
    ran = CliRunner().invoke(
        app, ["run", str(path), "-d", "0.1", "-o", str(out), "-q", "--allow-code"]
    )
    assert ran.exit_code == 1, ran.output
    assert says in ran.output and "controller 'rewind'" in ran.output, ran.output
    import json

    summary = json.loads((out / "summary.json").read_text())
    assert summary["verdict"]["status"] == "failed"
    written = xr.open_dataset(out / "results.nc")
    assert written.sizes["time"] == (1 if how == "reset" else 20)  # (reset: the start)
    written.close()
    assert sys.breakpointhook is sys.__breakpointhook__  # put back after the command


def test_sys_exit_named_by_a_line_file_is_refused_before_any_call(tmp_path: Path) -> None:
    """``object = "sys:exit"``, even with ``sys`` trusted: no controller, refused (exit 2)
    before it is called; nothing written."""
    from webline.spec.code_consent import trusted_file

    trusted_file().parent.mkdir(parents=True, exist_ok=True)
    trusted_file().write_text('modules = ["sys", "builtins"]\n')
    for obj in ("sys:exit", "builtins:breakpoint"):
        path = line_file(tmp_path, {"object": obj})
        ran = CliRunner().invoke(
            app, ["run", str(path), "-d", "0.1", "-o", str(tmp_path / "o"), "--allow-code"]
        )
        errors = [s for s in ran.output.splitlines() if s.startswith("error")]
        assert ran.exit_code == 2 and len(errors) == 1 and "neither a controller" in errors[0], (
            ran.output
        )


def test_a_law_numba_cannot_compile_is_bad_input(tmp_path: Path) -> None:
    (tmp_path / "laws.py").write_text(
        "def law(t, meas, refs, params, state, out):\n    out[0] = 'fast'\n"
    )
    path = line_file(tmp_path, {"function": "laws.py:law"})
    with pytest.raises(LawCompileError, match="numba cannot compile") as info:
        webline.simulate(path, 0.1, allow_code=True)
    assert info.value.exit_code == 2


def writes_out_of_bounds(t, meas, refs, params, state, out):  # type: ignore[no-untyped-def]
    if t > 0.01:
        out[3] = 1.0  # one drive: out has one entry
    out[0] = params[0]


def test_checked_mode_names_an_out_of_bounds_write() -> None:
    """In checked mode a law writing past ``out`` ends the run at that tick with an
    IndexError named (unchecked, numba writes over memory); the unchecked law's error
    recommends checked mode."""

    def params(context: object) -> list[float]:
        return [context.drives[0].equilibrium_command]  # type: ignore[attr-defined]

    with pytest.raises(ControllerError) as info:
        webline.simulate(
            "hswl",
            0.1,
            controller={
                "rewind": CompiledController(writes_out_of_bounds, params=params, checked=True)
            },
        )
    message = str(info.value)
    assert "IndexError" in message and "tick 11" in message and "checked mode" not in message, (
        message
    )


def nan_state(t, meas, refs, params, state, out):  # type: ignore[no-untyped-def]
    state[0] = state[0] + 1.0 if t < 0.02 else np.nan
    out[0] = params[0]


def test_checked_mode_refuses_a_non_finite_state() -> None:
    def params(context: object) -> list[float]:
        return [context.drives[0].equilibrium_command]  # type: ignore[attr-defined]

    result = webline.simulate(
        "hswl", 0.1, controller={"rewind": CompiledController(nan_state, params=params, state=1)}
    )
    assert result.failure is None  # unchecked: the NaN in its own memory goes unseen
    with pytest.raises(ControllerError, match="state became non-finite") as info:
        webline.simulate(
            "hswl",
            0.1,
            controller={
                "rewind": CompiledController(nan_state, params=params, state=1, checked=True)
            },
        )
    assert "tick 20" in str(info.value)


def test_an_unchecked_laws_failure_recommends_checked_mode() -> None:
    def raises(t, meas, refs, params, state, out):  # type: ignore[no-untyped-def]
        out[0] = params[0]
        if t > 0.01:
            raise ValueError("too fast")

    def params(context: object) -> list[float]:
        return [context.drives[0].equilibrium_command]  # type: ignore[attr-defined]

    with pytest.raises(ControllerError, match="checked mode"):
        webline.simulate(
            "hswl", 0.1, controller={"rewind": CompiledController(raises, params=params)}
        )
