"""User Python controllers on branched lines (docs/controllers.md, "On a branched line"):
called every tick with the drive's readings, their torques through the same drives; the
other drives keep their compiled controllers."""

from __future__ import annotations

import numpy as np
import pytest

import webline
from webline.errors import ArgumentError, ControllerError


class UserPI:
    """The cascaded PI (thesis Fig. 4.3) written here, with the gains the file's cascaded PI
    runs (``DriveInfo.builtin_pi``); it records what it read at every tick."""

    def reset(self, context):
        self.dt, self.drives = context.sample_period, context.drives
        self.names = context.measurement_names
        self.speed_i = [d.equilibrium_command for d in context.drives]  # [N·m]
        self.tension_i = [d.tension_sign * d.equilibrium_trim for d in context.drives]
        self.out = np.zeros(len(context.drives))
        self.seen = []  # (t, measurements, references) per tick

    def __call__(self, t, meas, refs):
        self.seen.append((t, meas.copy(), refs.copy()))
        for k, d in enumerate(self.drives):
            speed, tension, radius, inertia = meas[4 * k:4 * k + 4]
            g = d.builtin_pi
            scale = inertia / (d.ratio * radius) / d.gain_norm if d.roll else 1.0
            e_t = trim = 0.0
            if d.role == "tension":
                e_t = refs[2 * k + 1] - tension
                trim = d.tension_sign * (g.tension_kp * e_t + self.tension_i[k])
            e_v = refs[2 * k] + trim - speed
            raw = g.speed_kp * scale * e_v + self.speed_i[k]
            u = min(max(raw, -d.torque_limit), d.torque_limit)
            if not (raw != u and e_v * raw > 0.0):  # conditional integration, as built in
                self.speed_i[k] += g.speed_ki * scale * e_v * self.dt
            if not (raw != u and d.tension_sign * e_t * raw > 0.0):
                self.tension_i[k] += g.tension_ki * e_t * self.dt
            self.out[k] = u
        return self.out


def _tensions(result):
    return result.dataset["tension"].values


def test_a_user_pi_reproduces_the_built_in_laminator_through_a_tension_step():
    # The layer-upset scenario: 150 m/min, the film zone's reference steps 120 -> 150 N at
    # 2 s. The user PI reads what the compiled PI reads at the same tick (sampled on a copy
    # of the state before the tick), its command is held over the same period and does the
    # same float operations in the same order: the runs are equal to round-off. One
    # loadcell per zone makes even the order of the sums the same, so 1e-9 N (far below the
    # 30 N step and its transient) is a margin, not a fit (the runs agree to the bit here).
    line = webline.load_line("laminator").with_scenario("layer-upset")
    built_in = webline.simulate(line, 2.5)
    pi = UserPI()
    user = webline.simulate(line, 2.5, controller=pi)
    assert built_in.failure is None and user.failure is None
    film = list(built_in.dataset["span"].values).index("film_zone")
    step = _tensions(built_in)[:, film]
    assert step.max() - step[0] > 20.0  # the step went through the run compared
    assert np.max(np.abs(_tensions(user) - _tensions(built_in))) <= 1e-9
    assert np.max(np.abs(user.states - built_in.states)) <= 1e-9 * np.max(np.abs(
        built_in.states))
    # called at every tick t = k dt from 0 to the end (the last command only recorded)
    times = [t for t, *_ in pi.seen]
    assert len(times) == round(2.5 / line.spec.control.sample_rate ** -1) + 1
    assert times[0] == 0.0 and times[-1] == pytest.approx(2.5)
    # and one drive alone: the others keep their compiled controllers, same numbers
    one = webline.simulate(line, 2.5, controller={"rewind": UserPI()})
    assert np.max(np.abs(_tensions(one) - _tensions(built_in))) <= 1e-9


def test_a_shaft_of_lanes_reads_the_sum_of_its_lanes_loadcells():
    # The slitter's rewind_shaft winds two lanes (100 N each): its drive's tension reading is
    # the sum of the lanes' loadcells and its reference their sum (200 N), the error the
    # built-in PI integrates. The user PI then reproduces the built-in run; the sum's order
    # differs from the built-in's sum of errors, so round-off (1e-9 of 300 N) is allowed.
    line = webline.load_line("slitter")
    built_in = webline.simulate(line, 1.0)
    pi = UserPI()
    user = webline.simulate(line, 1.0, controller=pi)
    assert np.max(np.abs(_tensions(user) - _tensions(built_in))) <= 1e-9 * 300.0
    spans = list(user.dataset["span"].values)
    lanes = [spans.index("lane_1_span"), spans.index("lane_2_span")]
    k = [d.name for d in pi.drives].index("rewind_shaft")
    for row in (0, 500, 1000):  # the reading of tick j is of the state recorded at tick j
        t, meas, refs = pi.seen[row]
        assert user.time[row] == pytest.approx(t)
        assert meas[4 * k + 1] == pytest.approx(_tensions(user)[row, lanes].sum(), abs=1e-9)
        assert refs[2 * k + 1] == pytest.approx(200.0)
    master = [d.role for d in pi.drives].index("master")
    assert np.isnan(pi.seen[0][1][4 * master + 1])  # the master has no zone: NaN


class Raises:
    def reset(self, context):
        self.n = len(context.drives)

    def __call__(self, t, meas, refs):
        if t > 0.01:
            raise RuntimeError("gain table empty")
        return np.zeros(self.n)


class ReturnsNaN(Raises):
    def __call__(self, t, meas, refs):
        return np.full(self.n, np.nan if t > 0.02 else 0.0)


class WrongShape(Raises):
    def __call__(self, t, meas, refs):
        return np.zeros(self.n + 1)


@pytest.mark.parametrize(("controller", "message", "t_last"), [
    (Raises(), r"^laminator: controller 'line' \(Raises\) raised RuntimeError: gain table "
               r"empty at tick 11 \(t = 0\.011 s\)$", 0.01),
    (ReturnsNaN(), r"^laminator: controller 'line' \(ReturnsNaN\) returned a non-finite "
                   r"torque nan for unwind_film at tick 21 \(t = 0\.021 s\)$", 0.02),
    (WrongShape(), r"returned shape \(5,\) where 4 torque\(s\) \[N·m\] were due at tick 0",
     None),
])
def test_a_failing_controller_stops_the_run_in_one_line_naming_it_and_the_tick(
        controller, message, t_last):
    with pytest.raises(ControllerError, match=message) as caught:
        webline.simulate("laminator", 0.1, controller=controller)
    assert "\n" not in str(caught.value)
    partial = caught.value.partial
    if t_last is None:  # failed at tick 0: the start alone is kept (the CLI writes it)
        assert len(partial.time) == 1 and partial.time[0] == 0.0
    else:  # the run up to the tick before the failing one
        assert partial.time[-1] == pytest.approx(t_last)
    returned = webline.simulate("laminator", 0.1, controller=controller,
                                raise_on_failure=False)
    assert returned.failure is not None and "controller 'line'" in returned.failure


def test_bad_controller_arguments_are_one_line_naming_the_problem():
    with pytest.raises(ArgumentError, match="controller: no drive 'nope'; the drives are "
                                            "unwind_film, unwind_foil, nip, rewind"):
        webline.simulate("laminator", 0.1, controller={"nope": UserPI()})
    with pytest.raises(ArgumentError, match=r"controller\['nip'\]: object is not a controller"):
        webline.simulate("laminator", 0.1, controller={"nip": object()})


def test_a_session_steps_as_simulate_runs_and_a_restore_repeats_the_same_numbers():
    # Stepping 200 + 0 + 300 ticks runs the same compiled loop on the same arrays as one
    # simulate(0.5 s): the same records to the bit, the last row the state at t = 0.5 s.
    line = webline.load_line("laminator").with_scenario("layer-upset")
    session = webline.Session(line)
    assert type(session).__name__ == "BranchSession"
    session.step(200)
    session.step(0)
    session.step(300)
    assert session.t == pytest.approx(0.5)
    stepped, run = session.result(), webline.simulate(line, 0.5)
    assert type(stepped).__name__ == "BranchResult" and stepped.failure is None
    assert np.array_equal(stepped.rec, run.rec)
    snap = session.snapshot()
    session.apply({"film_zone.stretch": 30.0})  # a 30 N kick, then back to the snapshot
    session.set_reference("film_zone.tension", 150.0)
    session.step(100)
    kicked = session.result().rec.copy()
    session.restore(snap)
    session.step(100)
    again = session.result().rec.copy()
    session.restore(snap)
    session.apply({"film_zone.stretch": 30.0})
    session.set_reference("film_zone.tension", 150.0)
    session.step(100)
    assert np.array_equal(session.result().rec, kicked)  # the same numbers again
    assert np.array_equal(again, webline.simulate(line, 0.6).rec)  # restore undid the kick
    with pytest.raises(ArgumentError, match="set_reference: no reference 'x'; there are "
                                            "speed, film_zone\\.tension"):
        session.set_reference("x", 1.0)
    with pytest.raises(ArgumentError, match="apply: no state 'x'"):
        session.apply({"x": 1.0})
    with pytest.raises(ArgumentError, match="step: n must be a whole number >= 0"):
        session.step(-1)


def test_a_session_with_a_user_controller_equals_its_simulate_run():
    # The user PI on every drive: the same readings, commands and ticks as simulate's user
    # run, so the states are equal to the bit; the last record's user commands are the
    # held ones (the session does not call the controller for a tick it has not run).
    line = webline.load_line("laminator").with_scenario("layer-upset")
    run = webline.simulate(line, 0.3, controller=UserPI())
    session = webline.Session(line, controller=UserPI())
    session.step(300)
    assert np.array_equal(session.result().states, run.states)
    assert session.measurements["measured.rewind.tension"] == pytest.approx(180.0, abs=1.0)


def _laminator_with(tmp_path, controller: str) -> str:
    """The laminator's file in ``tmp_path`` with its rewind's controller table replaced by
    ``controller``, beside a module ``user_pi_module.py`` holding ``UserPI``."""
    import inspect
    from importlib import resources

    text = resources.files("webline.data.lines").joinpath("laminator.toml").read_text("utf-8")
    head, rewind = text.split('name = "rewind"', 1)
    old = next(line for line in rewind.splitlines() if line.startswith("controller ="))
    (tmp_path / "user_pi_module.py").write_text(
        "import numpy as np\n\n\n" + inspect.getsource(UserPI), encoding="utf-8")
    path = tmp_path / "laminator_user.toml"
    path.write_text(head + 'name = "rewind"' + rewind.replace(old, controller, 1),
                    encoding="utf-8")
    return str(path)


def test_run_takes_the_files_python_controller_and_the_controller_option(tmp_path):
    import xarray as xr
    from typer.testing import CliRunner

    from webline.cli import app
    from webline.control.select import with_branched_controller

    path = _laminator_with(tmp_path, 'controller = { type = "python", object = '
                                     '"user_pi_module.py:UserPI" }')
    out = tmp_path / "out"
    ran = CliRunner().invoke(app, ["run", path, "-d", "0.3", "-o", str(out), "-q", "--allow-code"])
    assert ran.exit_code == 0, ran.output
    written = xr.open_dataset(out / "results.nc")["tension"].values
    # the file's python PI on the rewind, the compiled PI on the others: the built-in run
    built_in = webline.simulate("laminator", 0.3)
    assert np.max(np.abs(written - _tensions(built_in))) <= 1e-9
    ran = CliRunner().invoke(app, ["run", "laminator", "-d", "0.3", "--controller",
                                   "state-feedback", "-o", str(tmp_path / "sf"), "-q"])
    assert ran.exit_code == 0, ran.output
    expected = webline.simulate(with_branched_controller(webline.load_line("laminator"),
                                                         "state_feedback"), 0.3)
    written = xr.open_dataset(tmp_path / "sf" / "results.nc")["tension"].values
    assert np.array_equal(written, _tensions(expected))
    assert not np.array_equal(written, _tensions(built_in))  # another family ran


@pytest.mark.parametrize(("controller", "key", "problem"), [
    ('controller = { type = "python", object = "user_pi_module.py:Nope" }',
     "rollers[6].controller.object", "'user_pi_module.py' has no 'Nope'"),
    ('controller = { type = "python", object = "missing.py:UserPI" }',
     "rollers[6].controller.object", "cannot import 'missing.py'"),
])
def test_a_bad_python_controller_in_a_branched_file_is_one_line_exit_2(
        tmp_path, controller, key, problem):
    from typer.testing import CliRunner

    from webline.cli import app

    path = _laminator_with(tmp_path, controller)
    ran = CliRunner().invoke(app, ["run", path, "-d", "0.1", "-o", str(tmp_path / "o"),
                                   "--allow-code"])
    assert ran.exit_code == 2
    lines = [line for line in ran.output.splitlines() if line.strip()]
    assert len(lines) == 1 and key in lines[0] and problem in lines[0], ran.output


def test_analyze_refuses_a_branched_line_with_a_python_controller_in_one_line(tmp_path):
    from typer.testing import CliRunner

    from webline.cli import app

    path = _laminator_with(tmp_path, 'controller = { type = "python", object = '
                                     '"user_pi_module.py:UserPI" }')
    ran = CliRunner().invoke(app, ["analyze", path])
    assert ran.exit_code == 2
    lines = [line for line in ran.output.splitlines() if line.strip()]
    assert len(lines) == 1 and "rewind run a user's python controller, which has no linear " \
        "model" in lines[0], ran.output


class StopsWithCtrlC(Raises):
    def __call__(self, t, meas, refs):
        if t > 0.05:
            raise KeyboardInterrupt
        return self.torques

    def reset(self, context):
        self.torques = np.array([d.equilibrium_command for d in context.drives])


def test_ctrl_c_in_a_user_run_keeps_what_was_computed():
    # Ctrl-C between two ticks: the run returns with its records so far, as a built-in run
    # interrupted between chunks (the user path's chunk is still 20 000 ticks)
    result = webline.simulate("laminator", 1.0, controller=StopsWithCtrlC(),
                              raise_on_failure=False)
    assert result.failure is not None and "interrupted" in result.failure
    assert result.time[-1] == pytest.approx(0.05)
