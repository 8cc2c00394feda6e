"""webline as a package in someone else's environment (issue 23, item 1): the core runs without
the optional parts, and a missing optional part is one line naming the extra to install."""

from __future__ import annotations

import os
import subprocess
import sys
import tomllib
from pathlib import Path

import webline
from webline.errors import MissingExtra
from webline.extras import OPTIONAL, require

ROOT = Path(__file__).resolve().parents[2]

#: run first in each child process: Dask (distributed and dask) cannot be imported, as in an
#: environment that installed webline without its [dask] extra
WITHOUT_DASK = """
import sys
sys.modules.update(distributed=None, dask=None)  # None: 'import dask' fails, find_spec is None
"""


def _python(code: str, *args: str) -> subprocess.CompletedProcess[str]:
    env = {**os.environ, "PYTHONPATH": str(ROOT / "src")}
    return subprocess.run([sys.executable, "-c", code, *args], capture_output=True, text=True,
                          env=env, timeout=300, cwd=ROOT)


def test_a_run_needs_no_dask() -> None:
    """The README's first line runs with Dask absent (load, simulate, verdict, results as
    xarray and pandas)."""
    done = _python(WITHOUT_DASK + """
import webline
result = webline.simulate('hswl', '0.2 s')
result.to_xarray(); result.to_dataframe()
print(result.verdict.status)
""")
    assert done.returncode == 0, done.stderr
    assert done.stdout.split() == ["ok"]


def test_the_core_path_never_imports_distributed() -> None:
    """With Dask installed, the core path of a run never imports ``distributed`` (its
    import is what made it a core dependency): only cluster sweeps do."""
    done = _python("""
import sys, webline
result = webline.simulate('hswl', '0.2 s')
result.to_xarray(); result.to_dataframe(); result.metrics()
print(result.verdict.status, 'distributed' in sys.modules)
""")
    assert done.returncode == 0, done.stderr
    assert done.stdout.split() == ["ok", "False"]


def test_a_cluster_sweep_without_dask_names_the_extra(tmp_path: Path) -> None:
    """``webline sweep --scheduler local`` without Dask: one line on stderr naming
    ``webline[dask]``, exit 2, no traceback; the Python API raises ``MissingExtra``."""
    done = _python(WITHOUT_DASK + "from webline.cli import main; sys.argv[0] = 'webline'; main()",
                   "sweep", "hswl", "--set", "web.ea=8 kN,9 kN", "--duration", "0.05",
                   "--scheduler", "local", "--out", str(tmp_path / "sweep"),
                   "--force", "--quiet")
    assert done.returncode == 2, done.stderr
    lines = done.stderr.strip().splitlines()
    assert len(lines) == 1 and "pip install 'webline[dask]'" in lines[0], done.stderr
    assert "Traceback" not in done.stderr


def test_require_names_the_extra(monkeypatch) -> None:
    """``require`` of an optional module that is not there raises ``MissingExtra`` (an
    ``ImportError`` too) with the install line; one that is there is returned."""
    monkeypatch.setitem(sys.modules, "jupytext", None)  # None in sys.modules: import fails
    try:
        require("jupytext")
    except MissingExtra as exc:
        assert isinstance(exc, ImportError) and exc.exit_code == 2
        assert "pip install 'webline[notebook]'" in str(exc)
    else:
        raise AssertionError("require did not raise")
    assert require("json").dumps([1]) == "[1]"  # not optional: imported as usual


def test_each_optional_module_is_in_its_extra() -> None:
    """Every extra that ``webline.extras.OPTIONAL`` names exists in ``pyproject.toml``, the
    core dependencies hold none of the optional packages, and ``dev`` pulls every extra (the
    tests use them all)."""
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    extras = project["optional-dependencies"]
    core = {d.split(">")[0].split("[")[0].strip() for d in project["dependencies"]}
    assert {extra for extra, _ in OPTIONAL.values()} <= set(extras)
    assert not core & {"distributed", "dask", "mkdocs", "jupytext", "nbclient"}
    assert any(d.startswith("distributed") for d in extras["dask"])
    dev_self = [d for d in extras["dev"] if d.startswith("webline[")]
    assert dev_self and set(dev_self[0][8:-1].split(",")) == set(extras) - {"dev"}


def test_version_is_pep440_and_single_sourced() -> None:
    """The version the package reports is the one the build reads (pyproject's dynamic
    version from ``webline.version``) and is a valid PEP 440 version."""
    from packaging.version import Version

    pyproject = tomllib.loads((ROOT / "pyproject.toml").read_text())
    assert pyproject["project"]["dynamic"] == ["version"]
    assert pyproject["tool"]["setuptools"]["dynamic"]["version"] == {
        "attr": "webline.version.__version__"}
    assert str(Version(webline.__version__)) == webline.__version__
    assert (ROOT / "LICENSE").read_text().startswith("MIT License")
    assert pyproject["project"]["license"] == "MIT"
