"""The documentation site shows what the code gives (issue 37, item 5): `mkdocs build --strict`
(what `make docs` runs) executes the tutorials and the examples, and the built HTML holds each
tutorial's figures and printed output and a gallery page per example with its figure.

One build (a minute or two: five notebooks and eleven examples run) is shared by the tests of
this file; with ``WEBLINE_DOCS_SITE`` naming a folder that ``make docs`` just built (``site``),
the tests check that build instead of making their own. Needs the ``docs`` and ``notebook``
extras (in ``dev``); skipped without them locally, a failure in CI."""

from __future__ import annotations

import html
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = sorted(p.stem for p in (ROOT / "examples").glob("*.py"))
#: a string of each tutorial's printed output (not of its code): the build ran the cell
TUTORIAL_OUTPUT = {
    "first-simulation": "2 s simulated, 2001 records",  # print(repr(result))
    "linear-analysis": "final value 1.000",  # the closed loop's step settles at its reference
    "sweeps": "Name: count",  # print(mc.status.to_pandas().value_counts())
    "winder": "largest diameter error",  # the diameter calculator against the true roll
    "your-own-line": "speed: must be >= 0",  # the LineFileError names the key
}
PNG = b"\x89PNG\r\n\x1a\n"
#: one inline figure of a notebook output: a PNG (pyplot) or an SVG drawn by matplotlib
NOTEBOOK_FIGURE = re.compile(r'<img[^>]+src="data:image/png;base64,|<svg[^>]*>\s*<metadata>',
                             re.S)

pytestmark = pytest.mark.slow


@pytest.fixture(scope="module")
def site(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The site built once into a temporary folder with this tree's webline."""
    built = os.environ.get("WEBLINE_DOCS_SITE")
    if built:
        assert (Path(built) / "index.html").is_file(), f"WEBLINE_DOCS_SITE={built}: no site"
        return Path(built)
    for module in ("mkdocs", "mkdocs_jupyter", "material", "mkdocstrings"):
        try:
            __import__(module)
        except ImportError:
            if os.environ.get("CI"):
                raise
            pytest.skip(f"the docs extra ({module}) is not installed")
    out = tmp_path_factory.mktemp("site")
    env = {**os.environ, "NO_MKDOCS_2_WARNING": "1", "PYTHONPATH": os.pathsep.join(
        [str(ROOT / "src"), *filter(None, [os.environ.get("PYTHONPATH")])])}
    done = subprocess.run([sys.executable, "-m", "mkdocs", "build", "--strict", "--site-dir",
                           str(out)], cwd=ROOT, env=env, capture_output=True, text=True,
                          timeout=1200, check=False)
    assert done.returncode == 0, done.stderr[-4000:]
    return out


def _page(site: Path, uri: str) -> str:
    path = site / uri / "index.html"
    assert path.is_file(), f"{uri} is not in the built site"
    return path.read_text(encoding="utf-8")


@pytest.mark.parametrize("name", sorted(TUTORIAL_OUTPUT))
def test_tutorial_page_shows_its_outputs(site: Path, name: str) -> None:
    """The tutorial's page holds a figure of its own outputs and a known printed string."""
    page = _page(site, f"tutorials/{name}")
    outputs = page[page.find('class="jp-Cell'):]  # the notebook's cells, after the theme's
    assert NOTEBOOK_FIGURE.search(outputs), f"{name}: no figure among the outputs"
    assert TUTORIAL_OUTPUT[name] in html.unescape(outputs), f"{name}: output not shown"
    # nbconvert leaves Markdown links as written; the hook turns them into the pages' URLs
    assert not re.findall(r'href="[^"]*\.md[#"]', outputs), f"{name}: a link to a .md file"


def test_every_tutorial_is_checked() -> None:
    assert {p.stem for p in (ROOT / "docs" / "tutorials").glob("*.md")} == set(TUTORIAL_OUTPUT)


def test_every_example_is_in_the_gallery_nav() -> None:
    """Each script of examples/ has its page in mkdocs.yml's navigation, and no other."""
    nav = (ROOT / "mkdocs.yml").read_text(encoding="utf-8")
    listed = re.findall(r"^\s+- [\w.]+: gallery/(\w+)\.md$", nav, re.M)
    assert sorted(listed) == EXAMPLES


@pytest.mark.parametrize("name", EXAMPLES)
def test_gallery_page_per_example(site: Path, name: str) -> None:
    """The example's page shows how to run it, a non-empty printed output and its figure, a
    real PNG (more than 5 kB: drawn axes, not an empty canvas) saved next to the page."""
    page = _page(site, f"gallery/{name}")
    assert f"python examples/{name}.py" in page
    output = re.search(r'id="output".*?<code>(.*?)</code>', page, re.S)
    assert output and html.unescape(re.sub(r"<[^>]+>", "", output.group(1))).strip(), name
    figures = re.findall(r'<img[^>]+src="([^"]+\.png)"', page)
    assert figures, f"{name}: no figure"
    png = (site / "gallery" / name / figures[0]).resolve()
    assert png.read_bytes()[:8] == PNG and png.stat().st_size > 5_000, png


def test_gallery_index_links_every_example(site: Path) -> None:
    index = _page(site, "gallery")
    for name in EXAMPLES:
        assert f'href="{name}/"' in index, name


def _gallery_hook(monkeypatch: pytest.MonkeyPatch) -> object:
    """docs/hooks/gallery.py as a module (mkdocs loads it by path and registers it, as here)."""
    pytest.importorskip("mkdocs")
    import importlib.util

    spec = importlib.util.spec_from_file_location("gallery_hook",
                                                  ROOT / "docs" / "hooks" / "gallery.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    monkeypatch.setitem(sys.modules, "gallery_hook", module)
    spec.loader.exec_module(module)
    return module


def test_gallery_run_keeps_output_and_figures_and_refuses_a_failing_example(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """An example's printed lines and pyplot figures are kept (``plt.show()`` is harmless, a
    ``sys.exit(0)`` is a success); an example that raises fails the build with its name and
    the exception, even when its worker's other example ran fine."""
    hook = _gallery_hook(monkeypatch)
    good = tmp_path / "good.py"
    good.write_text('"""Draws a line.\n\nRun: python good.py\n"""\nimport sys\n'
                    "import matplotlib.pyplot as plt\nprint('drawn')\nplt.plot([0, 1])\n"
                    "plt.figure()\nplt.show()\nsys.exit(0)\n", encoding="utf-8")
    bad = tmp_path / "bad.py"
    bad.write_text("print('before')\nraise ValueError('broken on purpose')\n", encoding="utf-8")
    (example,) = hook.Runs([good]).wait()  # type: ignore[attr-defined]
    assert example.output == "drawn\n" and example.summary == "Draws a line."
    assert len(example.figures) == 2 and all(f[:8] == PNG for f in example.figures)
    assert example.code.startswith("import sys")  # the docstring is the page's text, not code
    from mkdocs.exceptions import PluginError

    with pytest.raises(PluginError, match=r"(?s)bad\.py failed.*broken on purpose"):
        hook.Runs([good, bad]).wait()  # type: ignore[attr-defined]


def test_how_to_cite_names_webline_and_the_thesis(site: Path) -> None:
    """The site's How to cite page holds CITATION.cff itself: webline's entry and the thesis's
    (its type and institution), so the page cannot drift from the file."""
    page = html.unescape(re.sub(r"<[^>]+>", "", _page(site, "cite")))  # text of the highlighting
    assert "cff-version: 1.2.0" in page and 'title: "webline:' in page
    assert "type: thesis" in page and "Oklahoma State University" in page
