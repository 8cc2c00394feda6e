"""``export_fmu``: a line with its built-in controllers as an FMI 2.0 or 3.0 co-simulation FMU
(docs/fmu.md): the general loop's object (``loop_object``), the C wrapper (``fmi_wrapper.c``)
with the line's tables (``c_model``), linked by the system's C compiler into a shared library
and zipped with its ``modelDescription.xml``."""

from __future__ import annotations

import dataclasses
import math
import os
import shutil
import subprocess
import tempfile
import uuid
import zipfile
from importlib import resources
from pathlib import Path

import numba

from webline.errors import ArgumentError
from webline.fmu.c_model import model_header
from webline.fmu.loop_object import FmuBuildError, loop_arrays, loop_object
from webline.fmu.model_description import _identifier, model_description
from webline.fmu.variables import fmu_variables
from webline.line import Line
from webline.model.one_web import load_general
from webline.model.web_graph import BranchedLine
from webline.sim.branches.loop import layout as B
from webline.sim.branches.plan import BranchPlan
from webline.sim.branches.run import plan_and_step, run_start
from webline.sim.user_objects import named_code
from webline.spec.ranges import argument

#: the FMI platform folder of the binary each version's FMU holds
PLATFORM = {2: "linux64", 3: "x86_64-linux"}


def export_fmu(line: BranchedLine | Line | str | Path, path: str | Path, fmi: int = 3,
               step: float | str | None = None, scenario: str | None = None,
               plant_only: bool = False) -> Path:
    """Write the FMU of ``line`` (a line object, a line file or a built-in name) with its
    built-in controllers to ``path``: FMI ``fmi`` (2 or 3) co-simulation, a shared library
    for Linux x86-64 inside, no Python. ``step``: the communication step of its default
    experiment [s] (or with units), a whole number of controller periods (default: one);
    ``scenario``: a named scenario of the line file whose references and events the FMU
    runs. ``plant_only``: the drives' torque commands are inputs and the controllers are left
    out (each drive's readings are outputs, as a user controller gets them). The start
    state (the operating point at t = 0) is computed here, from the file's values:
    parameters changed at instantiation start from it. The first export of a line
    structure compiles the loop (minutes); later ones read it from numba's cache folder.
    A single-path line (``hswl``, ``converter``: a ``Line``, its file or name) is exported
    as its line of one web (``model.one_web``), its variables named as its own result names
    them (``radius[unwind]``, not ``radius[unwind/web]``). Returns the path."""
    if fmi not in PLATFORM:
        raise ArgumentError(f"fmi: expected 2 or 3, got {fmi!r}")
    out = Path(path)
    out.parent.mkdir(parents=True, exist_ok=True)  # (before minutes of compiling, not after)
    branched, single_path = load_general(line)
    if scenario is not None:
        branched = branched.with_scenario(scenario)
    code = named_code(branched)  # (read from the file, nothing imported)
    if code and not plant_only:
        key, text = code[0]
        raise ArgumentError(f"{branched.name}: {key} = {text!r}: a Python controller cannot go "
                            "into an FMU; export with --plant-only and close the loop around "
                            "it (docs/fmu.md)")
    plan, point, substeps = plan_and_step(branched, None, None)
    dt = plan.dt
    comm = dt if step is None else argument(step, "time", "step")
    k = round(comm / dt)
    if k < 1 or not math.isclose(k * dt, comm, rel_tol=1e-9):
        raise ArgumentError(f"step: must be a whole number of the line's controller period "
                            f"{dt:g} s, got {comm:g} s")
    start = run_start(plan, point)
    if plant_only:  # every drive a user drive: its command from its memory row (loop.user)
        plan = plant_plan(plan)
        start[1][:, B.I_UCMD] = point.torque  # held at the operating point until set
    arrays = loop_arrays(plan, *start)
    variables = fmu_variables(plan, arrays, plant_only, single_path=single_path)
    name = branched.name + (f"_{scenario}" if scenario else "") + (
        "_plant" if plant_only else "")
    guid = "{" + str(uuid.uuid4()) + "}"
    obj = loop_object(plan, arrays, substeps,
                      cache=Path(numba.config.CACHE_DIR) / "fmu")  # type: ignore[attr-defined]
    ident = _identifier(name)
    with tempfile.TemporaryDirectory(prefix="webline-fmu-") as tmp:
        folder = Path(tmp)
        (folder / "loop.o").write_bytes(obj)
        (folder / "model.h").write_text(model_header(name, guid, dt, arrays, plan.prof_off,
                                                     variables))
        wrapper = folder / "fmi_wrapper.c"
        wrapper.write_text(resources.files("webline.fmu").joinpath("fmi_wrapper.c").read_text())
        library = folder / f"{ident}.so"
        _compile(folder, wrapper, library, fmi)
        xml = model_description(fmi, name, guid, k * dt, variables,
                                f"webline line {branched.name} with its controllers")
        tmp_out = out.with_name(f".{out.name}.{os.getpid()}.tmp")
        with zipfile.ZipFile(tmp_out, "w", zipfile.ZIP_DEFLATED) as fmu:
            fmu.writestr("modelDescription.xml", xml)
            fmu.write(library, f"binaries/{PLATFORM[fmi]}/{ident}.so")
        tmp_out.replace(out)
    return out


def plant_plan(plan: BranchPlan) -> BranchPlan:
    """``plan`` with every drive a user drive (``FAMILY_USER``, ``loop.user``): the loop
    issues the command held in the drive's memory row; a new structure, compiled once (the
    run starts from the state and memory of ``plan``'s own controllers, as a user run)."""
    di = plan.di.copy()
    di[:, B.DI_FAMILY] = B.FAMILY_USER
    return dataclasses.replace(plan, di=di)


def _compile(folder: Path, wrapper: Path, library: Path, fmi: int) -> None:
    """Link the wrapper and the loop's object into ``library`` with the system's C compiler
    (``CC``, else cc or gcc)."""
    cc = os.environ.get("CC") or shutil.which("cc") or shutil.which("gcc")
    if cc is None:
        raise FmuBuildError("export --fmu needs a C compiler (cc or gcc, or set CC) to link "
                            "the FMU's shared library")
    command = [cc, "-shared", "-fPIC", "-O2", "-fvisibility=hidden", f"-DFMI_VERSION={fmi}",
               "-I", str(folder), "-o", str(library), str(wrapper), str(folder / "loop.o"),
               "-lm"]
    done = subprocess.run(command, capture_output=True, text=True)
    if done.returncode != 0:
        raise FmuBuildError(f"the C compiler failed to build the FMU: {done.stderr.strip()}")
