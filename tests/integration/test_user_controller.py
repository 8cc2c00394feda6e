"""User controllers in the loop (issue 25, item 1): the protocol, the line file's
``type = "python"``, what a controller sees and how its failures are reported."""

from __future__ import annotations

import importlib.util
import math
import sys
from pathlib import Path

import numpy as np
import pytest

import webline
from webline.errors import ArgumentError, ControllerError, LineFileError

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def _example(name: str) -> object:
    spec = importlib.util.spec_from_file_location(f"example_{name}", EXAMPLES / f"{name}.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module
    spec.loader.exec_module(module)
    return module


CascadedPI = _example("user_pi").CascadedPI  # type: ignore[attr-defined]


class Hold:
    """Holds every drive at its equilibrium command; records what it was given."""

    def reset(self, context: object) -> None:
        self.context = context
        self.torques = np.array([d.equilibrium_command for d in context.drives])  # type: ignore[attr-defined]
        self.calls = 0

    def __call__(self, t: float, measurements: np.ndarray, references: np.ndarray) -> object:
        self.calls += 1
        return self.torques


class FailsAt:
    """Holds its drive, then at ``tick`` returns ``bad`` (or raises if ``bad`` is None)."""

    def __init__(self, tick: int, bad: object) -> None:
        self.tick, self.bad = tick, bad

    def reset(self, context: object) -> None:
        self.dt = context.sample_period  # type: ignore[attr-defined]
        self.torque = context.drives[0].equilibrium_command  # type: ignore[attr-defined]

    def __call__(self, t: float, measurements: np.ndarray, references: np.ndarray) -> object:
        if round(t / self.dt) == self.tick:
            if self.bad is None:
                raise RuntimeError("gain table empty")
            return self.bad
        return self.torque


@pytest.mark.parametrize("name", ["hswl", "converter"])
def test_python_pi_reproduces_builtin(name: str) -> None:
    """Must show: the cascaded PI in Python gives the built-in trajectories to 1e-9 of each
    state's range over 6 s. Both compute the same IEEE operations on the same measurements;
    only the compiled loop's fused multiply-adds round differently (~1e-16 per tick, grown by
    the closed loop to ~1e-11 at most), so 1e-9 leaves margin yet fails on any real
    difference (a wrong initial integrator is 1e-4)."""
    line = webline.load_line(name)
    builtin = webline.simulate(line, 6.0)
    user = webline.simulate(line, 6.0, controller=CascadedPI())
    assert user.states.shape == builtin.states.shape
    scale = np.max(np.abs(builtin.states), axis=0)
    assert np.max(np.abs(user.states - builtin.states) / scale) < 1e-9


def test_mixed_line_one_user_drive() -> None:
    """A dict per drive name: only that drive runs the user's PI, the others their
    built-in controllers; with the same PI the run is the built-in one (1e-9, as above)."""
    line = webline.load_line("hswl")
    builtin = webline.simulate(line, 2.0)
    user = webline.simulate(line, 2.0, controller={"rewind": CascadedPI()})
    scale = np.max(np.abs(builtin.states), axis=0)
    assert np.max(np.abs(user.states - builtin.states) / scale) < 1e-9


def test_context_and_measurement_names() -> None:
    """reset gets the sample period, the drives in order and named measurements; a whole-line
    controller is called once per tick, the final tick included (2 s at 1 kHz: 2001)."""
    line = webline.load_line("hswl")
    hold = Hold()
    webline.simulate(line, 2.0, controller=hold, raise_on_failure=False)
    ctx = hold.context
    assert ctx.sample_period == pytest.approx(1e-3)
    assert [d.name for d in ctx.drives] == [line.node_name(i) for i in line.drives]
    assert ctx.measurement_names[:4] == tuple(f"{ctx.drives[0].name}.{m}" for m in
                                              ("speed", "tension", "radius", "inertia"))
    assert ctx.index(f"{ctx.drives[1].name}.tension_reference") == 3
    assert hold.calls == 2001


def test_sees_the_noisy_sampled_measurements() -> None:
    """With measurement noise the user's speed and tension measurements are the built-in
    drive's: the recorded torque of a user PI equals the built-in one, which a noiseless
    measurement would not give (the noise moves the command by far more than 1e-9)."""
    line = webline.load_line("hswl").replace(disturbances=[
        {"type": "measurement_noise", "tension": "2 N", "speed": "0.001 m/s", "seed": 3}])
    builtin = webline.simulate(line, 1.0)
    user = webline.simulate(line, 1.0, controller=CascadedPI())
    scale = np.max(np.abs(builtin.torque_cmd), axis=0)
    assert np.max(np.abs(user.torque_cmd - builtin.torque_cmd) / scale) < 1e-9


def test_torque_is_limited() -> None:
    """The user's command passes the drive's torque limit: a huge command is clipped there."""
    line = webline.load_line("hswl")

    class Huge(Hold):
        def __call__(self, t: float, m: np.ndarray, r: np.ndarray) -> object:
            return np.full(len(self.torques), 1e9)

    result = webline.simulate(line, 0.01, controller=Huge(), raise_on_failure=False)
    limits = result.plan.drives[:, 9]  # layout.D_LIMIT
    assert np.allclose(result.torque_cmd[1:], limits)


@pytest.mark.parametrize(("bad", "says"), [
    (None, "raised RuntimeError: gain table empty"),
    (math.nan, "non-finite torque nan"),
    ([1.0, 2.0], "returned shape (2,) where 1 torque(s)"),
    ("fast", "returned a str where 1 torque(s)"),
])
def test_failing_controller_named_with_tick_and_partial_kept(bad: object, says: str) -> None:
    """Must show: a controller that raises, returns NaN or the wrong shape stops the run with
    one error naming it and the tick; the records up to that tick are kept."""
    line = webline.load_line("hswl")
    with pytest.raises(ControllerError) as info:
        webline.simulate(line, 1.0, controller={"rewind": FailsAt(250, bad)})
    message = str(info.value)
    assert "controller 'rewind'" in message and "tick 250" in message and says in message
    assert "\n" not in message
    partial = info.value.partial
    assert partial.failure.kind == "controller"
    assert partial.time[-1] == pytest.approx(0.249)  # ticks 0..249 ran
    assert partial.status == "failed"


def test_line_file_python_controller(tmp_path: Path) -> None:
    """``controller = { type = "python", object = "file.py:Class", parameters = {...} }``
    runs that object on its drive (here the PI: the built-in run again)."""
    (tmp_path / "mine.py").write_text((EXAMPLES / "user_pi.py").read_text())
    source = webline.load_line("hswl")
    rollers = [r.model_dump(exclude_none=True) for r in source.spec.rollers]
    rollers[-1]["controller"] = {"type": "python", "object": "mine.py:CascadedPI"}
    data = source.spec.model_dump(exclude_none=True) | {"rollers": rollers}
    import tomli_w

    path = tmp_path / "line.toml"
    path.write_bytes(tomli_w.dumps(data).encode())
    user = webline.simulate(webline.load_line(path), 1.0, allow_code=True)
    builtin = webline.simulate(source, 1.0)
    scale = np.max(np.abs(builtin.states), axis=0)
    assert np.max(np.abs(user.states - builtin.states) / scale) < 1e-9


@pytest.mark.parametrize(("obj", "says"), [
    ("nowhere_module_xyz:Ctrl", "cannot import 'nowhere_module_xyz'"),
    ("missing.py:Ctrl", "cannot import 'missing.py'"),
    ("math:nothing", "'math' has no 'nothing'"),
    ("math:pi", "neither a controller nor a controller class"),
])
def test_line_file_bad_object_is_one_clear_error(obj: str, says: str) -> None:
    """A bad object path is a LineFileError (exit 2) naming the key and the problem (the
    installed modules trusted, docs/security.md, so that the names are looked at)."""
    from webline.spec.code_consent import trusted_file

    trusted_file().parent.mkdir(parents=True, exist_ok=True)
    trusted_file().write_text('modules = ["math", "nowhere_module_xyz"]\n')
    source = webline.load_line("hswl")
    rollers = [r.model_dump(exclude_none=True) for r in source.spec.rollers]
    rollers[-1]["controller"] = {"type": "python", "object": obj}
    line = source.replace(rollers=rollers)
    with pytest.raises(LineFileError) as info:
        webline.simulate(line, 0.1, allow_code=True)
    assert info.value.key == f"rollers[{len(rollers) - 1}].controller.object"
    assert says in str(info.value) and "\n" not in str(info.value)
    assert info.value.exit_code == 2


def test_unknown_drive_and_non_controller_are_argument_errors() -> None:
    line = webline.load_line("hswl")
    with pytest.raises(ArgumentError, match="no drive 'nope'"):
        webline.simulate(line, 0.1, controller={"nope": Hold()})
    with pytest.raises(ArgumentError, match="is not a controller"):
        webline.simulate(line, 0.1, controller=42)


def test_ctrl_c_keeps_the_run_so_far() -> None:
    """Ctrl-C (KeyboardInterrupt) between ticks of a user run stops it as the built-in run
    stops: SimulationInterrupted whose partial holds the ticks done (here 0..299)."""
    from webline.errors import SimulationInterrupted

    class Interrupts(FailsAt):
        def __call__(self, t: float, m: np.ndarray, r: np.ndarray) -> object:
            if round(t / self.dt) == 300:
                raise KeyboardInterrupt
            return self.torque

    with pytest.raises(SimulationInterrupted) as info:
        webline.simulate(webline.load_line("hswl"), 1.0,
                         controller={"rewind": Interrupts(0, None)})
    partial = info.value.partial
    assert partial.status == "interrupted"
    assert partial.time[-1] == pytest.approx(0.299)


def test_study_refuses_a_python_controller() -> None:
    """A sweep runs its cases in the compiled batch loop, which has no user path: a line with
    a python controller is one clear error (exit 2), never a run of garbage commands."""
    source = webline.load_line("hswl")
    rollers = [r.model_dump(exclude_none=True) for r in source.spec.rollers]
    rollers[-1]["controller"] = {"type": "python", "object": "math:pi"}
    line = source.replace(rollers=rollers)
    with pytest.raises(LineFileError) as info:
        webline.sweep(line, {"web.ea": [8000.0, 9000.0]}, duration=0.1)
    assert "controller" in info.value.key and info.value.exit_code == 2


def _line_file(tmp_path: Path, obj: str) -> Path:
    source = webline.load_line("hswl")
    rollers = [r.model_dump(exclude_none=True) for r in source.spec.rollers]
    rollers[-1]["controller"] = {"type": "python", "object": obj}
    import tomli_w

    path = tmp_path / "line.toml"
    path.write_bytes(tomli_w.dumps(source.spec.model_dump(exclude_none=True)
                                   | {"rollers": rollers}).encode())
    return path


def test_cli_bad_object_exit_2_and_failing_controller_exit_1(tmp_path: Path) -> None:
    """``webline run``: a line file naming an object that is not there is one line on
    stderr and exit 2; a controller that raises fails the run (exit 1) with its name and
    tick in the verdict, and the results up to it are written."""
    import subprocess

    (tmp_path / "bad.py").write_text(
        "class Raises:\n"
        "    def reset(self, context):\n        pass\n"
        "    def __call__(self, t, m, r):\n"
        "        if t > 0.05:\n            raise RuntimeError('boom')\n        return 0.0\n")
    command = [str(Path(sys.executable).parent / "webline"), "run", "--allow-code"]
    done = subprocess.run([*command, str(_line_file(tmp_path, "bad.py:Nope")), "--duration",
                           "0.1", "-o", str(tmp_path / "a")], capture_output=True, text=True,
                          timeout=600)
    assert done.returncode == 2, done.stderr
    errors = [s for s in done.stderr.splitlines() if s.startswith("error")]
    assert len(errors) == 1 and "rollers[4].controller.object" in errors[0]
    done = subprocess.run([*command, str(_line_file(tmp_path, "bad.py:Raises")), "--duration",
                           "0.1", "-o", str(tmp_path / "b")], capture_output=True, text=True,
                          timeout=600)
    assert done.returncode == 1, done.stderr
    assert "controller 'rewind' (Raises) raised RuntimeError: boom at tick 51" in (
        done.stdout + done.stderr)
    assert (tmp_path / "b" / "summary.json").exists()
