"""A line file is data (issue 34, docs/security.md): the Python code it names runs only with
the user's consent (``--allow-code``, ``allow_code=True``, the per-user allow-list), only
from the line file's own folder or the allow-list, and only objects with the controller
protocol are ever called. The hostile files here must leave no trace under any command."""

from __future__ import annotations

import os
import shutil
from pathlib import Path

import numpy as np
import pytest
import tomli_w
from typer.testing import CliRunner

import webline
from webline.cli import app
from webline.errors import LineFileError
from webline.spec.code_consent import allowing_code, trusted_file

EXAMPLES = Path(__file__).parents[2] / "examples"

SIDE_EFFECT = (
    "from pathlib import Path\n"
    "Path({mark!r}).write_text('ran')\n"
    "class Ctrl:\n"
    "    def reset(self, context):\n"
    "        self.torque = context.drives[0].equilibrium_command\n"
    "    def __call__(self, t, m, r):\n"
    "        return self.torque\n"
)


def line_file(path: Path, controller: dict[str, object]) -> Path:
    """hswl with ``controller`` on its rewind, written to ``path``."""
    source = webline.load_line("hswl")
    rollers = [r.model_dump(exclude_none=True) for r in source.spec.rollers]
    rollers[-1]["controller"] = {"type": "python", **controller}
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_bytes(
        tomli_w.dumps(source.spec.model_dump(exclude_none=True) | {"rollers": rollers}).encode()
    )
    return path


@pytest.fixture
def hostile(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> dict[str, tuple[Path, Path]]:
    """Three hostile line files, each with the file its code would leave if it ran:
    ``os:system`` touching PWNED, a side-effect module beside the file, and one reached by
    ``../``. The working folder is ``tmp_path`` (where ``touch PWNED`` would write)."""
    monkeypatch.chdir(tmp_path)
    beside, above = tmp_path / "beside", tmp_path / "above"
    (tmp_path / "side.py").write_text(SIDE_EFFECT.format(mark=str(beside)))
    (tmp_path / "evil.py").write_text(SIDE_EFFECT.format(mark=str(above)))
    return {
        "os-system": (
            line_file(
                tmp_path / "system.toml",
                {"object": "os:system", "parameters": {"command": f"touch {tmp_path}/PWNED"}},
            ),
            tmp_path / "PWNED",
        ),
        "beside": (line_file(tmp_path / "side.toml", {"object": "side.py:Ctrl"}), beside),
        "dotdot": (line_file(tmp_path / "sub" / "line.toml", {"object": "../evil.py:Ctrl"}), above),
    }


def invoke(*args: str) -> tuple[int, list[str]]:
    ran = CliRunner().invoke(app, list(args))
    return ran.exit_code, [s for s in ran.output.splitlines() if s.strip()]


@pytest.mark.parametrize("case", ["os-system", "beside", "dotdot"])
def test_no_command_runs_a_hostile_files_code_without_consent(
    hostile: dict[str, tuple[Path, Path]], tmp_path: Path, case: str
) -> None:
    """run (exit 2, one line naming the object and how to consent), sweep, validate, show and
    analyze: nothing imported, nothing called, no trace."""
    path, mark = hostile[case]
    code, lines = invoke("run", str(path), "-d", "0.05", "-o", str(tmp_path / "out"))
    assert code == 2 and len(lines) == 1, lines
    named = {"os-system": "'os:system'", "beside": "'side.py:Ctrl'", "dotdot": "'../evil.py:Ctrl'"}[
        case
    ]
    assert "rollers[4].controller.object" in lines[0] and named in lines[0]
    assert "--allow-code" in lines[0] and str(trusted_file()) in lines[0]
    assert not (tmp_path / "out").exists()  # refused before anything was written
    for command in (
        ["validate", str(path)],
        ["show", str(path)],
        ["analyze", str(path)],
        [
            "sweep",
            str(path),
            "--set",
            "web.ea=8000,9000",
            "-d",
            "0.05",
            "-o",
            str(tmp_path / "sweep"),
        ],
    ):
        code, lines = invoke(*command)
        if command[0] in ("validate", "show"):  # they say that the file names code
            assert code == 0 and any(
                "names Python code" in s and "--allow-code" in s for s in lines
            ), lines
    assert not mark.exists()


def test_consent_covers_only_the_files_folder_and_only_controllers(
    hostile: dict[str, tuple[Path, Path]], tmp_path: Path
) -> None:
    """With --allow-code: the module beside the file runs (consent given); ``os:system`` and
    ``../evil.py`` are still refused in one line (an installed module and a file outside the
    folder need the allow-list), and nothing of theirs runs."""
    path, mark = hostile["beside"]
    code, lines = invoke(
        "run", str(path), "-d", "0.05", "-o", str(tmp_path / "a"), "-q", "--allow-code"
    )
    assert code == 0 and mark.exists(), lines
    for case, says in (
        ("os-system", "installed module os"),
        ("dotdot", "outside the line file's folder"),
    ):
        path, mark = hostile[case]
        code, lines = invoke(
            "run", str(path), "-d", "0.05", "-o", str(tmp_path / case), "--allow-code"
        )
        assert code == 2 and len(lines) == 1 and says in lines[0], lines
        assert "trusted.toml" in lines[0] and not mark.exists()


def test_the_allow_list_trusts_folders_and_modules_but_never_calls_a_non_controller(
    hostile: dict[str, tuple[Path, Path]], tmp_path: Path
) -> None:
    """trusted.toml: a trusted folder's files run without the flag (``../evil.py`` here); a
    trusted module is imported, but ``os:system`` is no controller class or factory of its
    own module, so it is refused before any call: no PWNED."""
    trusted_file().parent.mkdir(parents=True, exist_ok=True)
    trusted_file().write_text(tomli_w.dumps({"folders": [str(tmp_path)], "modules": ["os"]}))
    path, mark = hostile["dotdot"]
    code, lines = invoke("run", str(path), "-d", "0.05", "-o", str(tmp_path / "a"), "-q")
    assert code == 0 and mark.exists(), lines
    path, mark = hostile["os-system"]
    code, lines = invoke("run", str(path), "-d", "0.05", "-o", str(tmp_path / "b"))
    errors = [s for s in lines if s.startswith("error")]
    assert code == 2 and len(errors) == 1 and "neither a controller" in errors[0], lines
    assert not mark.exists()


def test_a_malformed_allow_list_is_one_line(
    tmp_path: Path, hostile: dict[str, tuple[Path, Path]]
) -> None:
    trusted_file().parent.mkdir(parents=True, exist_ok=True)
    trusted_file().write_text('folders = "not a list"\n')
    code, lines = invoke("run", str(hostile["beside"][0]), "-d", "0.05")
    assert code == 2 and len(lines) == 1 and "trusted.toml: folders: expected a list" in lines[0], (
        lines
    )


def test_api_consent(hostile: dict[str, tuple[Path, Path]]) -> None:
    """simulate and Session refuse without consent (LineFileError saying allow_code=True);
    ``allow_code=True`` or ``with allowing_code():`` consents."""
    path, mark = hostile["beside"]
    for call in (lambda: webline.simulate(path, 0.05), lambda: webline.Session(path)):
        with pytest.raises(LineFileError, match=r"allow_code=True") as info:
            call()
        assert "\n" not in str(info.value) and info.value.exit_code == 2
    assert not mark.exists()
    webline.Session(path, allow_code=True).step(3)
    assert mark.exists()
    with allowing_code():
        assert webline.simulate(path, 0.05).failure is None


def _worst(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.max(np.abs(a - b) / np.maximum(np.max(np.abs(b), axis=0), 1e-300)))


@pytest.mark.parametrize(
    ("example", "obj", "make"),
    [
        ("user_pi.py", "CascadedPI", "CascadedPI"),
        ("user_pi_numba.py", "cascaded_pi", "cascaded_pi"),
        ("user_lqr.py", "IntegralLQR", "IntegralLQR"),
    ],
)
def test_the_examples_controllers_run_from_a_line_file_with_consent(
    tmp_path: Path, example: str, obj: str, make: str
) -> None:
    """The legitimate user controllers of examples/ named by a line file (copied beside it)
    run as the same objects passed in Python (1e-9: the same operations, another import)."""
    for name in ("user_pi.py", example):
        shutil.copy(EXAMPLES / name, tmp_path / name)
    path = line_file(tmp_path / "line.toml", {"object": f"{example}:{obj}"})
    from_file = webline.simulate(path, 0.5, allow_code=True)
    import importlib.util

    spec = importlib.util.spec_from_file_location(f"example_{example[:-3]}", EXAMPLES / example)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    direct = webline.simulate("hswl", 0.5, controller={"rewind": getattr(module, make)()})
    assert _worst(from_file.states, direct.states) < 1e-9
    assert os.path.exists(path)
