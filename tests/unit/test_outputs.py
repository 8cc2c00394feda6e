"""Output files and folders: safe default names, atomic writes, links refused, the manifest
that removes stale files, and names that matplotlib must show literally (issue 11, item 4)."""

from __future__ import annotations

import json
import os
from pathlib import Path

import pytest
from matplotlib.figure import Figure

from webline.files import OutputError, atomic_write, atomic_write_text
from webline.report.outputs import MANIFEST, NAME_LIMIT, OutputFolder, default_folder, safe_name
from webline.report.plots.mpl_text import legend_label, literal

NASTY = ["/tmp/x", "../../x", "a/b", "..", ".", "", "a\\b", "C:\\x", "x\x00y\n\tz", "~", "-rf",
         "$HOME", "`id`", "\u202eevil", "." * 300, "ä" * 500, "name with spaces", "a" + "/" * 50]


@pytest.mark.parametrize("name", NASTY)
def test_default_folder_is_a_direct_child_of_out(name):
    """Whatever the line or scenario name, the folder is one plain component under ``out``:
    no separator, no ``..``, no hidden or empty name, no control character, bounded length."""
    for folder in (default_folder(name), default_folder("line", name), default_folder(name, name)):
        assert folder.parent == Path("out")
        part = folder.name
        assert part and part not in (".", "..") and not part.startswith((".", "-"))
        assert "/" not in part and "\\" not in part and "$" not in part
        assert all(c.isprintable() and c not in "\u202e" for c in part), repr(part)
        assert len(part) <= NAME_LIMIT


def test_safe_name_keeps_ordinary_and_unicode_names():
    assert safe_name("hswl") == "hswl"
    assert safe_name("Folie_Línea-3 ü") == "Folie_Línea-3_ü"
    assert safe_name("薄膜ライン") == "薄膜ライン"
    assert default_folder("hswl", "speed-change") == Path("out/hswl-speed-change")
    assert safe_name("../../x") == "x" and safe_name("/tmp/x") == "tmp_x"


def test_atomic_write_interrupted_leaves_old_file_and_no_temp(tmp_path):
    """A KeyboardInterrupt half-way through writing (a second Ctrl-C) leaves the previous file
    untouched and no temporary file."""
    target = tmp_path / "results.nc"
    target.write_bytes(b"previous run")

    def half_then_interrupt(tmp: Path) -> None:
        tmp.write_bytes(b"half of the new fi")
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        atomic_write(target, half_then_interrupt)
    assert target.read_bytes() == b"previous run"
    assert os.listdir(tmp_path) == ["results.nc"]


def test_atomic_write_keeps_umask_permissions(tmp_path):
    """A file written atomically gets the permissions of an ordinary new file (not mkstemp's
    0600)."""
    mask = os.umask(0o022)
    os.umask(mask)
    path = atomic_write_text(tmp_path / "a.txt", "x")
    assert path.stat().st_mode & 0o777 == 0o666 & ~mask


def test_symlinked_target_is_refused_and_its_target_untouched(tmp_path):
    victim = tmp_path / "victim.txt"
    victim.write_text("keep me")
    link = tmp_path / "report.html"
    link.symlink_to(victim)
    with pytest.raises(OutputError, match="symbolic link"):
        atomic_write_text(link, "new")
    assert victim.read_text() == "keep me" and link.is_symlink()


def test_symlinked_folder_and_subfolder_are_refused(tmp_path):
    real = tmp_path / "real"
    real.mkdir()
    (tmp_path / "link").symlink_to(real)
    with pytest.raises(OutputError, match="symbolic link"):
        OutputFolder.open(tmp_path / "link")
    out = OutputFolder.open(tmp_path / "run")
    (tmp_path / "run" / "figures").symlink_to(real)
    with pytest.raises(OutputError, match="symbolic link"):
        out.claim("figures/tension.png")
    assert list(real.iterdir()) == []


def test_rerun_removes_stale_files_of_the_previous_manifest(tmp_path):
    first = OutputFolder.open(tmp_path / "run")
    for name in ("results.nc", "figures/slip.png", "report.html"):
        atomic_write_text(first.claim(name), name)
    first.finish()
    (tmp_path / "run" / "notes.txt").write_text("the user's own file")

    second = OutputFolder.open(tmp_path / "run")
    for name in ("results.csv", "report.html"):
        atomic_write_text(second.claim(name), "new " + name)
    removed = second.finish()
    assert sorted(p.name for p in removed) == ["results.nc", "slip.png"]
    files = sorted(str(p.relative_to(tmp_path / "run")) for p in (tmp_path / "run").rglob("*")
                   if p.is_file())
    assert files == [MANIFEST, "notes.txt", "report.html", "results.csv"]
    manifest = json.loads((tmp_path / "run" / MANIFEST).read_text())
    assert manifest["files"] == ["report.html", "results.csv"]


def test_interrupted_run_lists_what_it_created(tmp_path):
    """Each file joins the manifest before it is written, so an interrupted run (no
    ``finish``) still leaves every file it created listed for the next run to clean."""
    first = OutputFolder.open(tmp_path / "run")
    atomic_write_text(first.claim("results.nc"), "x")
    first.finish()
    second = OutputFolder.open(tmp_path / "run")
    atomic_write_text(second.claim("results.csv"), "y")  # interrupted here
    listed = json.loads((tmp_path / "run" / MANIFEST).read_text())["files"]
    assert listed == ["results.csv", "results.nc"]


def test_foreign_non_empty_folder_needs_force(tmp_path):
    (tmp_path / "thesis.tex").write_text("mine")
    with pytest.raises(OutputError, match="did not write it"):
        OutputFolder.open(tmp_path)
    OutputFolder.open(tmp_path, force=True)
    OutputFolder.open(tmp_path / "empty")  # a new or empty folder needs no --force


def test_tampered_manifest_cannot_delete_outside_the_folder(tmp_path):
    outside = tmp_path / "precious.txt"
    outside.write_text("keep")
    run = tmp_path / "run"
    run.mkdir()
    (run / MANIFEST).write_text(json.dumps({"files": ["../precious.txt", "/etc/hostname"]}))
    OutputFolder.open(run).finish()
    assert outside.read_text() == "keep"


@pytest.mark.parametrize("name", [r"$\frac{$", "$x_1^2$", "100% _nip ^", r"a\$b$", "$"])
def test_literal_names_render_verbatim(name):
    """A name with TeX characters draws without error and shows exactly as written, in a title
    and a legend (a leading underscore included)."""
    fig = Figure()
    ax = fig.subplots()
    ax.plot([0, 1], label=legend_label(name))
    ax.plot([0, 1], label=legend_label("_" + name))
    ax.set_title(literal(name))
    legend = ax.legend()
    fig.canvas.draw()  # raises ValueError on bad mathtext
    shown = [t.get_text() for t in legend.get_texts()]
    assert len(shown) == 2
    for text in (ax.title, *legend.get_texts()):
        assert not text._preprocess_math(text.get_text())[1]  # not read as math
    assert ax.title._preprocess_math(ax.title.get_text())[0] == name


def test_a_study_figure_that_fails_half_written_leaves_the_previous_file(tmp_path):
    """Studies write atomically too (``studies.output``): a figure whose drawing fails after
    writing part of its file leaves the previous file whole and no temporary file behind;
    the tables and summary go the same way."""
    from webline.studies import output

    path = tmp_path / "tension.png"
    path.write_bytes(b"the previous run's figure")
    fig = Figure()

    def half_then_fail(target, **kwargs):
        Path(target).write_bytes(b"\x89PNG half")
        raise RuntimeError("drawing failed")

    fig.savefig = half_then_fail  # type: ignore[method-assign]
    with pytest.raises(RuntimeError):
        output.write_figure(fig, path)
    assert path.read_bytes() == b"the previous run's figure"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["tension.png"]
    rows = [{"a": 1, "b": 2.5}, {"a": 2, "c": "x"}]
    output.finish("demo", tmp_path, [path], rows, "two rows")
    assert (tmp_path / "table.csv").read_text().splitlines() == ["a,b,c", "1,2.5,", "2,,x"]
    assert (tmp_path / "summary.txt").read_text() == "two rows\n"
