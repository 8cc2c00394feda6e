"""Users' compiled laws inside a branched line's compiled loop (docs/controllers.md, "Moving
a controller into the loop"; issue 33 item 3): the same contract as on a single-path line
(the same ``meas``/``refs``/``params``/``state``/``out`` per drive, the same error when a
law commands a non-finite torque or raises), called in the loop, not from Python."""

from __future__ import annotations

import importlib.util
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import webline
from webline import CompiledController
from webline.errors import ControllerError, LineFileError
from webline.sim.compiled_control import CHECKED_HINT

ONE_WEB = Path(__file__).parents[1] / "data" / "hswl_one_web.toml"


def _example(name: str) -> Any:
    path = Path(__file__).resolve().parents[2] / "examples" / f"{name}.py"
    spec = importlib.util.spec_from_file_location(name, path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


PI = _example("user_pi_numba")
PythonPI = _example("user_pi").CascadedPI  # type: ignore[attr-defined]


@pytest.fixture
def in_the_loop(monkeypatch: pytest.MonkeyPatch) -> None:
    """A compiled law called from Python fails the test: it must run inside the loop."""
    def called_from_python(self: CompiledController, *args: object) -> None:
        raise AssertionError(f"{self.name} was called from Python")
    monkeypatch.setattr(CompiledController, "__call__", called_from_python)


def hold(t: float, meas: np.ndarray, refs: np.ndarray, params: np.ndarray,
         state: np.ndarray, out: np.ndarray) -> None:
    """Holds each drive at ``params`` (its equilibrium command) and counts its calls in
    ``state[0]``; from ``t`` = ``params[-1]`` (if > 0) commands NaN."""
    state[0] += 1.0
    for k in range(out.shape[0]):
        out[k] = params[k]
    if params[params.shape[0] - 1] > 0.0 and t >= params[params.shape[0] - 1]:
        out[0] = np.nan


def _hold(nan_at: float = 0.0) -> CompiledController:
    return CompiledController(
        hold, params=lambda c: [d.equilibrium_command for d in c.drives] + [nan_at],
        state=1, name="hold")


def raises(t: float, meas: np.ndarray, refs: np.ndarray, params: np.ndarray,
           state: np.ndarray, out: np.ndarray) -> None:
    """Holds its drive at ``params[0]``; from t = 0.25 s it raises."""
    if t >= 0.25:
        raise ValueError("gain table empty")
    out[0] = params[0]


def test_laminator_compiled_pi_equals_the_same_pi_in_python(in_the_loop: None) -> None:
    """The layer-upset scenario (the film zone's reference steps 120 -> 150 N at 2 s): the
    cascaded PI as a compiled law (examples/user_pi_numba.py) in the loop and as a Python
    controller (examples/user_pi.py, called between ticks) read the same readings at every
    tick (both records every tick, the controller period) and do the same float operations
    in the same order, so the runs agree to round-off; 1e-9 N is far below the 30 N step."""
    line = webline.load_line("laminator").with_scenario("layer-upset")
    python = webline.simulate(line, 2.5, controller=PythonPI())
    law = PI.cascaded_pi()
    compiled = webline.simulate(line, 2.5, controller=law)
    assert python.failure is None and compiled.failure is None
    assert python.settings["record_every"] == compiled.settings["record_every"] == 1
    tension = compiled.dataset["tension"].values
    film = list(compiled.dataset["span"].values).index("film_zone")
    assert tension[:, film].max() - tension[0, film] > 20.0  # the step went through the run
    assert np.max(np.abs(tension - python.dataset["tension"].values)) <= 1e-9
    assert np.max(np.abs(compiled.states - python.states)) <= 1e-9 * np.max(
        np.abs(python.states))
    # the law's state is its memory where the run ended: two integrators per drive
    assert law.state.shape == (2 * len(line.drives),) and np.all(np.isfinite(law.state))
    # one drive alone: the others keep their compiled controllers, the same numbers
    one = webline.simulate(line, 2.5, controller={"rewind": PI.cascaded_pi()})
    assert np.max(np.abs(one.dataset["tension"].values - tension)) <= 1e-9


def test_hswl_one_web_compiled_law_equals_the_chain_with_the_same_law(
        in_the_loop: None) -> None:
    """hswl as a one-web ``[[webs]]`` file reproduces the chain's hswl (tests/
    test_one_web.py); with the compiled PI in both loops the two runs take the same readings
    and commands, so their tensions agree to round-off (1e-9 N of a 64 N tension), through
    the disturbance scenario's wound-in ripple and eccentric idler."""
    chain = webline.simulate("hswl", 3.0, scenario="disturbance", controller=PI.cascaded_pi())
    general = webline.simulate(ONE_WEB, 3.0, scenario="disturbance",
                               controller=PI.cascaded_pi())
    assert chain.failure is None and general.failure is None
    builtin = webline.simulate(ONE_WEB, 3.0, scenario="disturbance")
    gap = np.abs(general.dataset.tension.values - chain.tension)
    assert np.max(gap) < 1e-9
    # and the law is the built-in PI: the same run as the file's own controllers
    assert np.max(np.abs(general.dataset.tension.values
                         - builtin.dataset.tension.values)) < 1e-9


def test_a_nonfinite_command_stops_the_run_as_on_the_chain(in_the_loop: None) -> None:
    """A law commanding NaN from t = 0.25 s stops the run at tick 250 with the chain's
    error (the same words, the drive named, the checked-mode hint) and keeps ticks 0..249."""
    errors = []
    for line in ("hswl", ONE_WEB):
        with pytest.raises(ControllerError) as info:
            webline.simulate(line, 1.0, controller=_hold(nan_at=0.25))
        errors.append(info.value)
    chain, general = (str(e) for e in errors)
    assert chain == ("controller 'line' (compiled law hold) returned a non-finite torque "
                     "for unwind at tick 250 (t = 0.25 s)" + CHECKED_HINT)
    assert general == f"hswl_one_web: {chain}"  # (a branched line's errors name the line)
    partial = errors[1].partial
    assert partial.failure is not None
    assert float(partial.dataset.time.values[-1]) == pytest.approx(0.249)


def test_a_law_that_raises_is_named_with_its_message(in_the_loop: None) -> None:
    """A law that raises inside the loop (compiled code keeps no exception) stops the run
    with its own message, as on the chain; the other drives keep their built-in PI."""
    ctrl = CompiledController(raises, params=lambda c: [c.drives[0].equilibrium_command])
    with pytest.raises(ControllerError) as info:
        webline.simulate(ONE_WEB, 1.0, controller={"rewind": ctrl})
    assert str(info.value) == (
        "hswl_one_web: controller 'rewind' (compiled law raises) raised ValueError: gain "
        "table empty at tick 250 (t = 0.25 s)" + CHECKED_HINT)
    assert float(info.value.partial.dataset.time.values[-1]) == pytest.approx(0.249)


def test_a_line_files_law_runs_in_the_loop_with_consent_only(tmp_path: Path,
                                                              in_the_loop: None) -> None:
    """``controller = { type = "python", function = "laws.py:hold", params, states }`` on a
    branched file's rewind: refused without consent (one line naming the key), and with it
    the same law in the loop as the same law given through the API (1e-12 N: the same
    operations in the same order)."""
    (tmp_path / "laws.py").write_text(
        "def hold(t, meas, refs, params, state, out):\n"
        "    state[0] += 1.0\n"
        "    for k in range(out.shape[0]):\n"
        "        out[k] = params[k]\n"
        "    if params[params.shape[0] - 1] > 0.0 and t >= params[params.shape[0] - 1]:\n"
        "        out[0] = np.nan\n")
    api = _hold()
    direct = webline.simulate(ONE_WEB, 0.5, controller={"rewind": api})
    text = ONE_WEB.read_text()
    builtin = ('controller = { type = "cascaded_pi", speed_bandwidth = "40 rad/s", '
               'tension_bandwidth = "8 rad/s", damping = 1.0 }')
    rewind = text.index('name = "rewind"')
    at = text.index(builtin, rewind)
    path = tmp_path / "line.toml"
    path.write_text(text[:at] + f'controller = {{ type = "python", function = "laws.py:hold", '
                    f'params = [{float(api.params[0])!r}, 0.0], states = 1 }}'
                    + text[at + len(builtin):])
    (tmp_path / "laws.py").write_text("import numpy as np\n\n"
                                      + (tmp_path / "laws.py").read_text())
    with pytest.raises(LineFileError, match=r"rollers\[\d\]\.controller"):
        webline.simulate(path, 0.5, allow_code=False)
    from_file = webline.simulate(path, 0.5, allow_code=True)
    assert np.max(np.abs(from_file.dataset.tension.values
                         - direct.dataset.tension.values)) < 1e-12
