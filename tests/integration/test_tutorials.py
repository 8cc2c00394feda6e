"""The tutorial notebooks of docs/tutorials run (issue 23, item 4), so they cannot rot: each is
a jupytext Markdown notebook, executed cell by cell in a fresh kernel by nbclient. Needs the
``notebook`` extra (in ``dev``); skipped without it locally, a failure in CI."""

from __future__ import annotations

import os
import time
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
TUTORIALS = sorted((ROOT / "docs" / "tutorials").glob("*.md"))
#: longest a tutorial may take [s]: each is kept to a few seconds of simulation; the kernel's
#: start and first imports (numba, the compiled loop from its cache) add a few more
TIMEOUT = 120


def _tools():
    try:
        import jupytext
        import nbclient
    except ImportError:
        if os.environ.get("CI"):
            raise
        pytest.skip("the notebook extra (jupytext, nbclient) is not installed")
    return jupytext, nbclient


def test_every_tutorial_is_in_the_site() -> None:
    """Each notebook of docs/tutorials is in mkdocs.yml's navigation, and there are five."""
    nav = (ROOT / "mkdocs.yml").read_text(encoding="utf-8")
    assert len(TUTORIALS) == 5
    for path in TUTORIALS:
        assert f"tutorials/{path.name}" in nav, path.name


@pytest.mark.parametrize("path", TUTORIALS, ids=[p.stem for p in TUTORIALS])
def test_tutorial_runs(path: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Every cell of the notebook runs without error in a fresh kernel (working directory a
    temporary folder, webline from this tree)."""
    jupytext, nbclient = _tools()
    notebook = jupytext.read(path)
    assert sum(cell.cell_type == "code" for cell in notebook.cells) >= 2
    monkeypatch.setenv("PYTHONPATH", os.pathsep.join(  # the kernel imports this tree
        [str(ROOT / "src"), *filter(None, [os.environ.get("PYTHONPATH")])]))
    monkeypatch.setenv("MPLBACKEND", "Agg")
    started = time.perf_counter()
    nbclient.NotebookClient(notebook, timeout=TIMEOUT, kernel_name="python3",
                            resources={"metadata": {"path": str(tmp_path)}}).execute()
    assert time.perf_counter() - started < TIMEOUT
