"""Profile of ``simulate(line, 1.0)`` on a long line (issue 12): where a newly loaded line's
call spends its time once its loop structure is compiled.

Run:  python benchmarks/long_line.py [--pairs 31] [--repeat 3]
      python benchmarks/long_line.py --run-spans 20 50 100 500   # the whole `webline run -d 1`

The line is built from the pieces of the built-in ``hswl``: its unwind and master roller, then
``pairs`` times (its idle roller, its process roller) — each process roller a tension-controlled
drive regulating the zone through the idler before it — and its rewind: 2 + 2·pairs + 1 nodes,
2·pairs + 2 spans (64 for the default 31 pairs). Each repeat loads the line anew (a new
``Line``, as every case of a sweep is), so every per-line cost is paid; the structure's loop is
compiled once before timing. Reported: the whole call, the operating point, the fastest mode
(``webline.sim.linear.linearize.fastest_mode``, building the plan's open- and closed-loop models
included, and of it the bound on their eigenvalues alone) and the compiled loop
(``kernel.run``), each the best of ``repeat`` runs [ms] (the least disturbed by other work).
"""

from __future__ import annotations

import argparse
import copy
import time
from collections.abc import Callable
from typing import Any

from webline import load_line, simulate
from webline.line import Line
from webline.model import operating_point as op_module
from webline.sim.core import kernel
from webline.sim.linear import linearize as lin_module


def long_line(pairs: int = 31) -> Line:
    """The hswl stretched to ``pairs`` (idler, process roller) pairs between master and rewind:
    2·pairs + 2 spans, each zone's loadcell on the span entering its process roller."""
    base = load_line("hswl").spec.model_dump(exclude_none=True)
    rollers = {r["name"]: r for r in base["rollers"]}
    span = {k: v for k, v in base["spans"][0].items() if k != "name"}
    data = copy.deepcopy(base)
    data["name"] = f"hswl-{2 * pairs + 2}-spans"
    data["scenarios"] = {}
    data["rollers"] = [rollers["unwind"], rollers["master"]]
    data["spans"] = [{**span, "name": "span1"}]
    for p in range(pairs):
        data["rollers"] += [{**rollers["idler"], "name": f"idler{p + 1}"},
                            {**rollers["process"], "name": f"process{p + 1}"}]
        data["spans"] += [{"length": span["length"], "name": f"span{2 * p + 2}"},
                          {**span, "name": f"span{2 * p + 3}"}]
    data["rollers"].append(rollers["rewind"])
    data["spans"].append({**span, "name": f"span{2 * pairs + 2}"})
    return load_line(data)


def profile(pairs: int, repeat: int) -> dict[str, float]:
    """Best times [s] of one ``simulate(line, 1.0)`` of a newly loaded long line, and of its
    parts (operating point, fastest mode, compiled loop), plus how often each part ran."""
    simulate(long_line(pairs), 0.01)  # compile the structure's loop (or load it from disk)
    parts: dict[str, list[float]] = {"operating point": [], "fastest mode": [],
                                     "  of which the bound": [], "loop": []}
    calls: dict[str, int] = {k: 0 for k in parts}

    def timing(name: str, fn: Callable[..., Any]) -> Callable[..., Any]:
        def wrapped(*args: Any, **kwargs: Any) -> Any:
            t = time.perf_counter()
            try:
                return fn(*args, **kwargs)
            finally:
                parts[name][-1] += time.perf_counter() - t
                calls[name] += 1
        return wrapped

    originals = (op_module.operating_point, lin_module.fastest_mode,
                 lin_module.spectral_radius_bound, kernel.run)
    whole = []
    try:
        for target, attr, name, fn in _patches(originals):
            setattr(target, attr, timing(name, fn))
        for _ in range(repeat):
            for v in parts.values():
                v.append(0.0)
            line = long_line(pairs)
            t = time.perf_counter()
            simulate(line, 1.0)
            whole.append(time.perf_counter() - t)
    finally:
        for target, attr, _, fn in _patches(originals):
            setattr(target, attr, fn)
    out = {"simulate": min(whole)}
    out |= {k: min(v) for k, v in parts.items()}
    out |= {f"{k} calls per run": calls[k] / repeat for k in calls}
    return out


def _patches(originals: tuple[Callable[..., Any], ...]) -> list[tuple[Any, str, str, Any]]:
    """Where each timed function is looked up: its home module and the modules that imported
    it by name."""
    from webline.sim import simulate as sim_module
    from webline.sim.core import plan as plan_module

    op, fastest, bound, run = originals
    return [(op_module, "operating_point", "operating point", op),
            (plan_module, "operating_point", "operating point", op),
            (lin_module, "fastest_mode", "fastest mode", fastest),
            (sim_module, "fastest_mode", "fastest mode", fastest),
            (lin_module, "spectral_radius_bound", "  of which the bound", bound),
            (kernel, "run", "loop", run)]


def whole_run(spans: int, seconds: float = 1.0, limit: float = 600.0) -> dict[str, float]:
    """``webline run LINE -d seconds`` of a long line of about ``spans`` spans, in its own
    process as a user runs it (simulation, results file, figures and report): its wall time
    [s], exit status (-9: stopped after ``limit`` s), and the CPU time [s] and largest
    resident memory [MB] of the runs so far (``RUSAGE_CHILDREN``: call it smallest line
    first)."""
    import resource
    import subprocess
    import sys
    import tempfile
    from pathlib import Path

    from webline.spec.load import dump_spec

    with tempfile.TemporaryDirectory(prefix="webline-long-") as folder:
        path = Path(folder) / "line.toml"
        path.write_text(dump_spec(long_line(max(1, (spans - 2) // 2)).spec))
        command = [sys.executable, "-c", "from webline.cli import main; main()", "run",
                   str(path), "-d", str(seconds), "-q", "-o", str(Path(folder) / "out")]
        started = time.perf_counter()
        proc = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
        try:
            proc.wait(limit)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()
        wall = time.perf_counter() - started
        children = resource.getrusage(resource.RUSAGE_CHILDREN)  # largest child so far
        return {"wall [s]": wall, "exit": float(proc.returncode if proc.returncode is not None
                                                else -9),
                "peak memory [MB]": children.ru_maxrss / 1024,
                "cpu of all runs so far [s]": children.ru_utime + children.ru_stime}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--pairs", type=int, default=31)
    parser.add_argument("--repeat", type=int, default=7)
    parser.add_argument("--run-spans", type=int, nargs="*", default=None, help=(
        "time `webline run -d 1` (report included) of lines of these many spans instead"))
    args = parser.parse_args()
    if args.run_spans is not None:
        for spans in args.run_spans:
            print(f"{spans} spans: " + ", ".join(f"{k} {v:.1f}" for k, v in
                                                 whole_run(spans).items()), flush=True)
        return
    line = long_line(args.pairs)
    print(f"{line.name}: {line.n_spans} spans, {line.n_nodes} nodes, {len(line.drives)} drives")
    for name, value in profile(args.pairs, args.repeat).items():
        print(f"  {name:32s} {value:8.0f}" if "calls" in name else
              f"  {name:32s} {1e3 * value:8.1f} ms")


if __name__ == "__main__":
    main()
