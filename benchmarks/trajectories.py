"""Save the state trajectories of every built-in line and scenario, or compare two saves: the
check that a refactor leaves the physics bit for bit as it was.

    python benchmarks/trajectories.py save before.npz      # on the old commit
    python benchmarks/trajectories.py save after.npz       # on the new one
    python benchmarks/trajectories.py compare before.npz after.npz

Each run is 6 s of a built-in line, branched ones included (its default run and every
scenario), and of ``hswl`` under
the state-feedback, adaptive and MRAC controllers. ``compare`` prints the largest absolute
difference per run and exits 1 if any differs or is missing.
"""

from __future__ import annotations

import argparse
import sys

import numpy as np

import webline
from webline.control.select import with_controller

SECONDS = 6.0
LINES = ("hswl", "rockwell", "converter", "laminator", "slitter")
CONTROLLERS = ("state_feedback", "adaptive", "mrac")


def save(path: str) -> None:
    runs = {}
    for name in LINES:
        line = webline.load_line(name)
        runs[name] = webline.simulate(line, SECONDS).states
        for scenario in line.spec.scenarios:
            runs[f"{name}-{scenario}"] = webline.simulate(line, SECONDS, scenario=scenario).states
    for family in CONTROLLERS:
        line = with_controller(webline.load_line("hswl"), family)  # type: ignore[arg-type]
        runs[f"hswl-{family}"] = webline.simulate(line, SECONDS).states
    np.savez(path, **runs)
    print(f"{len(runs)} runs saved to {path}")


def compare(before: str, after: str) -> int:
    old, new = np.load(before), np.load(after)
    worst = 0.0
    for key in old.files:
        if key not in new.files or old[key].shape != new[key].shape:
            print(f"{key:32s} missing or of another shape")
            worst = np.inf
            continue
        diff = float(np.max(np.abs(old[key] - new[key]))) if old[key].size else 0.0
        print(f"{key:32s} largest difference {diff:.3g}")
        worst = max(worst, diff)
    print(f"largest difference over {len(old.files)} runs: {worst:.3g}")
    return 0 if worst == 0.0 else 1


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    commands = parser.add_subparsers(dest="command", required=True)
    commands.add_parser("save").add_argument("path")
    both = commands.add_parser("compare")
    both.add_argument("before")
    both.add_argument("after")
    args = parser.parse_args()
    if args.command == "save":
        save(args.path)
    else:
        sys.exit(compare(args.before, args.after))


if __name__ == "__main__":
    main()
