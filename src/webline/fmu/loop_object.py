"""The general loop (``sim.branches.loop.kernel.advance``) of one plan as a position-independent
object file with a C entry point and no Python inside (docs/fmu.md, "What is inside").

numba compiles a small ``step`` function around the plan's compiled loop
(``BranchPlan.loop``): it takes raw pointers and views them as arrays (``numba.carray``) of
the plan's shapes. Its final LLVM module (the loop and every helper, inlined) is compiled by
llvmlite for generic x86-64 (``reloc='pic'``). numba's C wrapper of the function (the
``cfunc`` entry that converts an error status into a Python exception) is cut from the module
before compiling: the object exports only ``webline_loop``, numba's own calling convention
(below), and needs only libm. An object is kept on disk per plan structure, kernel source
and numba version.
"""

from __future__ import annotations

import hashlib
import re
from pathlib import Path
from typing import Any

import numba
import numpy as np

from webline.errors import WeblineError
from webline.sim import _kernel_source_hash
from webline.sim.branches.loop.kernel import structure_key
from webline.sim.branches.plan import BranchPlan
from webline.sim.elements.signals import FAST
from webline.version import __version__

#: the float arrays the loop takes, in the order of ``webline_loop``'s pointer table (rec:
#: one record row; stages, work, held: scratch)
FLOAT_ARRAYS = ("x", "istate", "wound", "done", "rec", "stages", "cmd", "work", "held", "nodes",
                "sf", "rolls", "df", "clutch", "events", "dist", "prof_t", "prof_v", "lawf",
                "laws", "fb", "refs")

#: the C prototype of the object's entry point, numba's calling convention: it returns 0 (the
#: loop raises nothing: numpy's error model, no ``raise``; the exception slot is never
#: written) and puts the run's status (``layout`` STATUS_*) in the first argument; then the
#: step's arguments: the float arrays' pointers in ``FLOAT_ARRAYS`` order, the profile
#: offsets, the first tick, the ticks to run, ticks per record, 1 to record the state after
#: the last tick, and two outputs (records written, time of failure [s]).
C_PROTOTYPE = ("int32_t webline_loop(int64_t *status, void **excinfo, double **arrays, "
               "int64_t *prof_off, int64_t tick0, int64_t n_ticks, int64_t record_every, "
               "int64_t include_end, double *out);")

ENTRY = "webline_loop"

#: the functions the loop's object may take from the system: libm's (what numba's math and
#: LLVM's intrinsics lower to); anything else (Python's C API, numba's runtime) is refused
LIBM = frozenset({"sin", "cos", "tan", "asin", "acos", "atan", "atan2", "sinh", "cosh",
                  "tanh", "exp", "expm1", "log", "log1p", "log10", "log2", "pow", "sqrt",
                  "floor", "ceil", "fmod", "round", "trunc", "hypot", "cbrt", "erf", "erfc",
                  "memcpy", "memset", "memmove"})


class FmuBuildError(WeblineError):
    """The FMU could not be built (no C compiler, a compiler error, a loop that needs more
    than libm)."""
_TRIPLE = "x86_64-unknown-linux-gnu"


def loop_arrays(plan: BranchPlan, x: np.ndarray, istate: np.ndarray, wound: np.ndarray,
                done: np.ndarray, cmd: np.ndarray) -> dict[str, np.ndarray]:
    """Every float array ``webline_loop`` takes for ``plan`` from the start state (``x``,
    ``istate``, ``wound``, ``done``, ``cmd``: ``sim.branches.run.run_start``), by name."""
    n_d = plan.di.shape[0]
    return {"x": x, "istate": istate, "wound": wound, "done": done,
            "rec": np.zeros((1, 1 + plan.n_x + 2 * n_d)), "stages": np.zeros((5, plan.n_x)),
            "cmd": cmd, "work": plan.scratch(), "held": np.zeros_like(wound),
            "nodes": plan.nodes, "sf": plan.sf, "rolls": plan.rolls, "df": plan.df,
            "clutch": plan.clutch, "events": plan.events, "dist": plan.dist,
            "prof_t": plan.prof_t, "prof_v": plan.prof_v, "lawf": plan.lawf, "laws": plan.laws,
            "fb": plan.fb, "refs": plan.refs}


def loop_object(plan: BranchPlan, arrays: dict[str, np.ndarray], substeps: int,
                cache: Path | None = None) -> bytes:
    """The object file of ``plan``'s loop with ``substeps`` RK4 steps per tick for arrays of
    the shapes of ``arrays`` (``loop_arrays``); read from ``cache`` (a folder) when it was made
    before, else compiled (minutes on a first use: numba compiles the loop for raw arrays) and
    stored there."""
    shapes = tuple(tuple(int(n) for n in arrays[k].shape) for k in FLOAT_ARRAYS)
    key = repr((structure_key(plan.offsets, plan.si, plan.layers, plan.webs, plan.di,
                              plan.cells, plan.cores, plan.lawi, plan.kv),
                shapes, plan.prof_off.shape, float(plan.dt).hex(),
                float(plan.speed_max).hex(), int(substeps), numba.__version__, __version__,
                _kernel_source_hash()))  # (also where NUMBA_CACHE_DIR is the user's)
    name = hashlib.sha256(key.encode()).hexdigest()[:24] + ".o"
    if cache is not None and (cache / name).is_file():
        return (cache / name).read_bytes()
    obj = compile_object(loop_ir(plan, shapes, substeps))
    if cache is not None:
        cache.mkdir(parents=True, exist_ok=True)
        tmp = cache / f"{name}.{id(obj)}.tmp"
        tmp.write_bytes(obj)
        tmp.replace(cache / name)
    return obj


def loop_ir(plan: BranchPlan, shapes: tuple[tuple[int, ...], ...], substeps: int) -> str:
    """The LLVM IR of the step function of ``plan``'s loop for arrays of ``shapes`` (in
    ``FLOAT_ARRAYS`` order), its entry renamed ``ENTRY`` and numba's C wrapper cut out."""
    from numba import carray, types

    lines = ["def step(p, poff, tick0, n_ticks, record_every, include_end, out):"]
    lines += [f"    {k} = carray(p[{i}], S[{i}])" for i, k in enumerate(FLOAT_ARRAYS)]
    lines += ["    prof_off = carray(poff, (N_OFF,))",
              "    n, status, t_fail = loop(x, istate, wound, done, rec, stages, cmd, work, "
              "held, tick0, n_ticks, DT, SUBSTEPS, record_every, include_end != 0, SPEED_MAX, "
              "nodes, sf, rolls, df, clutch, events, dist, prof_t, prof_v, prof_off, lawf, "
              "laws, fb, refs)",
              "    out[0] = n", "    out[1] = t_fail", "    return status"]
    space: dict[str, Any] = {"carray": carray, "S": shapes, "N_OFF": plan.prof_off.shape[0],
                             "loop": plan.loop(), "DT": float(plan.dt), "SUBSTEPS": substeps,
                             "SPEED_MAX": float(plan.speed_max)}
    # generated source: the shapes are constants of the step, so the arrays it makes have
    # known extents, as the loop's frozen integer tables do
    exec(compile("\n".join(lines), "<webline.fmu step>", "exec"), space)
    f64p = types.CPointer(types.float64)
    signature = types.int64(types.CPointer(f64p), types.CPointer(types.int64), types.int64,
                            types.int64, types.int64, types.int64, f64p)
    compiled = numba.cfunc(signature, error_model="numpy", fastmath=FAST)(space["step"])
    ir = _cut(compiled.inspect_llvm(), r"@cfunc\.")
    inner = re.search(r"^define [^@]*@(_Z\w*4step\w+)\(", ir, re.M)
    if inner is None:
        raise RuntimeError("webline.fmu: the step function is missing from numba's module")
    return ir.replace(f"@{inner.group(1)}(", f"@{ENTRY}(")


def compile_object(ir: str) -> bytes:
    """``ir`` compiled for generic x86-64 Linux as position-independent code, every symbol but
    ``ENTRY`` internal and what nothing uses dropped (numba's ``NRT_decref``, the
    environments of its functions); ``FmuBuildError`` if it still needs more than
    ``LIBM``."""
    import llvmlite.binding as llvm

    llvm.initialize_native_target()
    llvm.initialize_native_asmprinter()
    module = llvm.parse_assembly(ir)
    module.triple = _TRIPLE
    for fn in module.functions:
        if not fn.is_declaration and fn.name != ENTRY:
            fn.linkage = llvm.Linkage.internal
    for gv in module.global_variables:
        if not gv.is_declaration:
            gv.linkage = llvm.Linkage.internal
    machine = llvm.Target.from_triple(_TRIPLE).create_target_machine(
        cpu="x86-64", features="", opt=3, reloc="pic", codemodel="default")
    passes = llvm.create_new_module_pass_manager()
    passes.add_global_dead_code_eliminate_pass()
    passes.add_strip_dead_prototype_pass()
    passes.run(module, llvm.create_pass_builder(machine, llvm.create_pipeline_tuning_options()))
    module.verify()
    needed = {fn.name for fn in module.functions
              if fn.is_declaration and not fn.name.startswith("llvm.")}
    if not needed <= LIBM:
        raise FmuBuildError(f"the compiled loop needs {', '.join(sorted(needed - LIBM))} "
                            "beyond libm: it cannot run without Python (webline.fmu)")
    return bytes(machine.emit_object(module))


def _cut(ir: str, name: str) -> str:
    """``ir`` without the definitions of the functions whose name matches ``name``."""
    out, skipping = [], False
    for line in ir.splitlines(keepends=True):
        if not skipping and line.startswith("define") and re.search(name, line):
            skipping = True
        elif skipping:
            skipping = not line.startswith("}")
        else:
            out.append(line)
    return "".join(out)
