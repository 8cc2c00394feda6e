"""mkdocs hooks of the webline site (mkdocs.yml ``hooks:``).

* **The gallery**: every script of ``examples/`` runs at build (a subprocess each, as a user
  runs it, several at once) and gets a page ``gallery/<name>.md`` with its description, its
  code, what it printed and the figures it drew (matplotlib pyplot figures left open when it
  ends, saved as PNG next to the page); ``gallery/index.md`` lists them with a thumbnail. An
  example that fails fails the build, naming the script and the end of its stderr.
* **Links in the tutorials**: the executed notebooks (mkdocs-jupyter) are rendered by
  nbconvert, which leaves a Markdown link such as ``../sweeps.md`` as written; here it becomes
  the page's URL, as mkdocs does for its own pages.
"""

from __future__ import annotations

import ast
import logging
import os
import re
import subprocess
import sys
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from mkdocs.exceptions import PluginError
from mkdocs.structure.files import File, Files

LOG = logging.getLogger("mkdocs.hooks.gallery")
ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples"
GALLERY = "gallery"
#: longest one example may run at build [s] (the slowest takes a few seconds once compiled)
TIMEOUT = 600
#: runs the example as ``python examples/x.py`` would (``__main__``, its folder on sys.path),
#: then saves the pyplot figures it left open; ``plt.show()`` does nothing under Agg
RUNNER = """
import runpy, sys, warnings
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
warnings.filterwarnings("ignore", message=".*non-interactive.*")
script, folder = sys.argv[1:3]
sys.argv = [script]
sys.path.insert(0, str(__import__("pathlib").Path(script).parent))
runpy.run_path(script, run_name="__main__")
for number in plt.get_fignums():
    plt.figure(number).savefig(f"{folder}/{number}.png", dpi=90, bbox_inches="tight")
"""


@dataclass(frozen=True)
class Example:
    """One script of examples/ after its run at build."""

    name: str  # file stem, e.g. "bode"
    summary: str  # the docstring's first paragraph
    description: str  # the rest of the docstring
    code: str  # the script without its docstring
    output: str  # what it printed
    figures: tuple[bytes, ...]  # PNG of each figure it drew
    seconds: float  # wall time of its run at build [s]


def _split_docstring(source: str) -> tuple[str, str, str]:
    """(first paragraph, rest, code after the docstring) of a script's source."""
    module = ast.parse(source)
    doc = ast.get_docstring(module) or ""
    body = module.body
    code = source
    if doc and body and isinstance(body[0], ast.Expr):
        lines = source.splitlines(keepends=True)
        code = "".join(lines[body[0].end_lineno or 0:]).lstrip("\n")
    # "Run: python examples/x.py" is said once on the page, not in the description
    doc = re.sub(r"^Run: .*$", "", doc, flags=re.M).strip()
    summary, _, rest = doc.partition("\n\n")
    return " ".join(summary.split()), rest.strip(), code


def run_example(path: Path) -> Example:
    """Run one example in a fresh interpreter; its figures go through a temporary folder."""
    env = {**os.environ, "MPLBACKEND": "Agg"}
    source = path.read_text(encoding="utf-8")
    summary, description, code = _split_docstring(source)
    with tempfile.TemporaryDirectory() as folder:
        started = time.perf_counter()
        try:
            done = subprocess.run([sys.executable, "-c", RUNNER, str(path), folder], env=env,
                                  cwd=folder, capture_output=True, text=True, timeout=TIMEOUT,
                                  check=False)
        except subprocess.TimeoutExpired as error:
            raise PluginError(f"gallery: examples/{path.name} ran past {TIMEOUT} s") from error
        seconds = time.perf_counter() - started
        if done.returncode != 0:
            tail = "\n".join(done.stderr.strip().splitlines()[-15:])
            raise PluginError(f"gallery: examples/{path.name} failed (exit "
                              f"{done.returncode}):\n{tail}")
        pngs = sorted(Path(folder).glob("*.png"), key=lambda p: int(p.stem))
        figures = tuple(p.read_bytes() for p in pngs)
    return Example(path.stem, summary, description, code, done.stdout, figures, seconds)


def example_page(example: Example) -> str:
    """The Markdown of an example's gallery page."""
    parts = [f"# {example.name}.py\n", f"{example.summary}\n"]
    if example.description:
        parts.append(f"{example.description}\n")
    parts.append(f"Run it from a clone: `python examples/{example.name}.py` (the output and "
                 "figures below are those of its run when this site was built).\n")
    parts.append(f"## Code\n\n```python\n{example.code.rstrip()}\n```\n")
    parts.append(f"## Output\n\n```text\n{example.output.rstrip() or '(nothing printed)'}\n```\n")
    if example.figures:
        parts.append("## Figures\n")
        for k in range(1, len(example.figures) + 1):
            parts.append(f"![Figure {k} of {example.name}.py]({example.name}-{k}.png)\n")
    return "\n".join(parts)


def index_page(examples: list[Example]) -> str:
    """The Markdown of the gallery's index: one entry per example, with its first figure."""
    parts = ["# Gallery of the examples\n",
             "Each script of `examples/` is run when this site is built: its page shows the "
             "code, what it printed and the figures it drew. The test suite runs the same "
             "scripts (`tests/integration/test_examples.py`).\n"]
    for example in examples:
        parts.append(f"## [{example.name}.py]({example.name}.md)\n")
        if example.figures:
            parts.append(f"[![{example.name}.py]({example.name}-1.png){{ width=\"360\" }}]"
                         f"({example.name}.md)\n")
        parts.append(f"{example.summary}\n")
    return "\n".join(parts)


def build_gallery(config: Any) -> list[File]:
    """Run every example (a few at once) and return the gallery's generated files."""
    scripts = sorted(EXAMPLES.glob("*.py"))
    workers = max(1, min(4, os.cpu_count() or 1))
    with ThreadPoolExecutor(workers) as pool:
        examples = list(pool.map(run_example, scripts))
    for example in examples:
        LOG.info("gallery: examples/%s.py ran in %.1f s, %d figure(s)", example.name,
                 example.seconds, len(example.figures))
    files = [File.generated(config, f"{GALLERY}/index.md", content=index_page(examples))]
    for example in examples:
        files.append(File.generated(config, f"{GALLERY}/{example.name}.md",
                                    content=example_page(example)))
        for k, png in enumerate(example.figures, 1):
            files.append(File.generated(config, f"{GALLERY}/{example.name}-{k}.png",
                                        content=png))
    return files


def on_files(files: Files, config: Any) -> Files:
    """Add the gallery's pages and figures to the site."""
    for file in build_gallery(config):
        files.append(file)
    return files


_LINK = re.compile(r'href="(?![a-z]+:|#|/)([^"#]+\.md)(#[^"]*)?"')


def on_page_content(html: str, page: Any, config: Any, files: Files) -> str:
    """Rewrite ``href="x.md"`` in a tutorial notebook's HTML to the target page's URL."""
    if not page.file.src_uri.startswith("tutorials/"):
        return html

    def url(match: re.Match[str]) -> str:
        target = os.path.normpath(os.path.join(os.path.dirname(page.file.src_uri),
                                               match.group(1))).replace(os.sep, "/")
        found = files.get_file_from_path(target)
        if found is None:
            raise PluginError(f"{page.file.src_uri}: link to {match.group(1)}, which is not a "
                              "page of the site")
        return f'href="{found.url_relative_to(page.file)}{match.group(2) or ""}"'

    return _LINK.sub(url, html)
