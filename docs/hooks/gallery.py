"""mkdocs hooks of the webline site (mkdocs.yml ``hooks:``).

* **The gallery**: every script of ``examples/`` runs at build, in a few worker processes that
  start with the build and run while the tutorials execute, and gets a page
  ``gallery/<name>.md`` with its description, its code, what it printed and the figures it
  drew (matplotlib pyplot figures left open when it ends, saved as PNG next to the page);
  ``gallery/index.md`` lists them with a thumbnail. An example that fails fails the build,
  naming the script and the end of its traceback.
* **Links in the tutorials**: the executed notebooks (mkdocs-jupyter) are rendered by
  nbconvert, which leaves a Markdown link such as ``../sweeps.md`` as written; here it becomes
  the page's URL, as mkdocs does for its own pages.
"""

from __future__ import annotations

import ast
import json
import logging
import os
import re
import subprocess
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from mkdocs.exceptions import PluginError
from mkdocs.structure.files import File, Files

LOG = logging.getLogger("mkdocs.hooks.gallery")
ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples"
GALLERY = "gallery"
#: longest the examples may run at build, all together [s] (a few seconds each, compiled)
TIMEOUT = 900
#: a worker: runs each script it is given as ``python examples/x.py`` would (``__main__``, its
#: folder on sys.path), one after the other in one interpreter (the imports of webline and its
#: compiled loops are paid once per worker, not once per example); writes what each printed,
#: its error if any and its time to ``<name>.json`` and the pyplot figures it left open to
#: ``<name>-<k>.png``, then closes them (``plt.show()`` does nothing under Agg)
WORKER = """
import contextlib, io, json, runpy, sys, time, traceback, warnings
from pathlib import Path
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
warnings.filterwarnings("ignore", message=".*non-interactive.*")
folder = Path(sys.argv[1])
for script in sys.argv[2:]:
    path, printed, error = Path(script), io.StringIO(), ""
    sys.argv, started = [script], time.perf_counter()
    sys.path.insert(0, str(path.parent))
    try:
        with contextlib.redirect_stdout(printed):
            runpy.run_path(script, run_name="__main__")
    except SystemExit as exit_:
        if exit_.code not in (0, None):
            error = f"exit {exit_.code}"
    except Exception:
        error = traceback.format_exc()
    finally:
        sys.path.remove(str(path.parent))
    for k, number in enumerate(plt.get_fignums(), 1):
        plt.figure(number).savefig(folder / f"{path.stem}-{k}.png", dpi=90, bbox_inches="tight")
    plt.close("all")
    (folder / f"{path.stem}.json").write_text(json.dumps(
        {"output": printed.getvalue(), "error": error, "seconds": time.perf_counter() - started}))
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


class Runs:
    """The examples running in the background while the rest of the site (the tutorials'
    notebooks first) is built: a few worker processes, each given every n-th script."""

    def __init__(self, scripts: list[Path]) -> None:
        self.scripts = scripts
        self.folder = tempfile.TemporaryDirectory(prefix="webline-gallery-")
        workers = max(1, min(4, os.cpu_count() or 1, len(scripts)))
        env = {**os.environ, "MPLBACKEND": "Agg"}
        self.processes = []
        for k in range(workers):  # stderr to a file: a full pipe would stall a worker
            with open(Path(self.folder.name) / f"worker-{k}.err", "w") as stderr:
                self.processes.append(subprocess.Popen(
                    [sys.executable, "-c", WORKER, self.folder.name,
                     *map(str, scripts[k::workers])],
                    cwd=self.folder.name, env=env, stdout=subprocess.DEVNULL, stderr=stderr))
        self.examples: list[Example] | None = None

    def wait(self) -> list[Example]:
        """Every example after its run (waits for the workers the first time)."""
        if self.examples is None:
            try:
                for k, process in enumerate(self.processes):
                    if process.wait(timeout=TIMEOUT) != 0:
                        err = Path(self.folder.name) / f"worker-{k}.err"
                        tail = "\n".join(err.read_text().strip().splitlines()[-15:])
                        raise PluginError(f"gallery: a worker running examples/ stopped (exit "
                                          f"{process.returncode}):\n{tail}")
                self.examples = [self._example(path) for path in self.scripts]
            except subprocess.TimeoutExpired as error:
                raise PluginError(f"gallery: the examples ran past {TIMEOUT} s") from error
            finally:
                self.stop()
        return self.examples

    def _example(self, path: Path) -> Example:
        folder = Path(self.folder.name)
        run = json.loads((folder / f"{path.stem}.json").read_text(encoding="utf-8"))
        if run["error"]:
            tail = "\n".join(run["error"].strip().splitlines()[-15:])
            raise PluginError(f"gallery: examples/{path.name} failed:\n{tail}")
        pngs = sorted(folder.glob(f"{path.stem}-*.png"),
                      key=lambda p: int(p.stem.rpartition("-")[2]))
        summary, description, code = _split_docstring(path.read_text(encoding="utf-8"))
        LOG.info("gallery: examples/%s ran in %.1f s, %d figure(s)", path.name,
                 run["seconds"], len(pngs))
        return Example(path.stem, summary, description, code, run["output"],
                       tuple(p.read_bytes() for p in pngs), run["seconds"])

    def stop(self) -> None:
        """End the workers still running (a failed build) and remove their folder."""
        for process in self.processes:
            if process.poll() is None:
                process.kill()
                process.wait()
        self.folder.cleanup()


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


#: the runs of the build in progress (a module global: mkdocs calls hooks as functions)
_RUNS: dict[str, Runs] = {}


def on_files(files: Files, config: Any) -> Files:
    """Start the examples and add the gallery's pages (their Markdown comes when they ran)."""
    scripts = sorted(EXAMPLES.glob("*.py"))
    if "build" in _RUNS:
        _RUNS.pop("build").stop()
    _RUNS["build"] = Runs(scripts)
    files.append(File.generated(config, f"{GALLERY}/index.md", content="# Gallery\n"))
    for path in scripts:
        files.append(File.generated(config, f"{GALLERY}/{path.stem}.md",
                                    content=f"# {path.name}\n"))
    return files


def on_page_markdown(markdown: str, page: Any, config: Any, files: Files) -> str:
    """A gallery page's Markdown, after the examples ran; the first such page also adds their
    figures to the site's files."""
    uri = page.file.src_uri
    if not uri.startswith(f"{GALLERY}/"):
        return markdown
    runs = _RUNS["build"]
    if runs.examples is None:
        for example in runs.wait():
            for k, png in enumerate(example.figures, 1):
                files.append(File.generated(config, f"{GALLERY}/{example.name}-{k}.png",
                                            content=png))
    examples = {example.name: example for example in runs.wait()}
    if uri == f"{GALLERY}/index.md":
        return index_page(list(examples.values()))
    return example_page(examples[Path(uri).stem])


def on_build_error(error: Exception) -> None:
    """A failed build leaves no example running."""
    if "build" in _RUNS:
        _RUNS.pop("build").stop()


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
