"""What a line of one web's result gives beside a single-path line's (issue 33, item 4).

Runs hswl through the single-path loop and ``tests/data/hswl_one_web.toml`` through the
general one, for the default run and every hswl scenario, and prints side by side: the
variables (dimensions, units, long names) each has and the other lacks, the largest
difference of each shared one (relative to its largest value), the metrics, summary keys,
verdict lines, ``to_dataframe()`` columns and global attributes, and, with ``--report``, the
sections of each report (``webline run ... --out``).

    python benchmarks/result_inventory.py [--seconds 3] [--report]

``tests/integration/test_one_result.py`` asserts what this prints.
"""

from __future__ import annotations

import argparse
import re
import tempfile
from pathlib import Path

import numpy as np

import webline
from webline.model.web_graph import load_branched

ONE_WEB = Path(__file__).parents[1] / "tests" / "data" / "hswl_one_web.toml"


def _gap(a: np.ndarray, b: np.ndarray) -> str:
    """Largest |a - b| relative to the largest |a| (NaN patterns must match)."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    if a.shape != b.shape:
        return f"shape {a.shape} vs {b.shape}"
    if not np.array_equal(np.isnan(a), np.isnan(b)):
        return "NaN where the other is not"
    finite = np.isfinite(a)
    scale = float(np.max(np.abs(a[finite]), initial=0.0))
    gap = float(np.max(np.abs(a[finite] - b[finite]), initial=0.0))
    return f"{gap / scale:.1e}" if scale else f"{gap:.1e} (abs)"


def variables(chain, general) -> None:
    a, b = chain.signals, general.signals
    print("| variable | single-path dims, units | general dims, units | rel. gap |")
    print("|---|---|---|---|")
    for name in sorted(set(a.data_vars) | set(b.data_vars)):
        def text(ds, name=name):
            if name not in ds:
                return "-"
            v = ds[name]
            return f"{v.dims[1:] or '()'} {v.attrs.get('units', '')}"
        gap = (_gap(a[name].values, b[name].values)
               if name in a and name in b and a[name].dims == b[name].dims else "")
        same = (name in a and name in b
                and a[name].attrs.get("long_name") == b[name].attrs.get("long_name"))
        mark = "" if same or name not in a or name not in b else " (long_name differs)"
        print(f"| {name} | {text(a)} | {text(b)} | {gap}{mark} |")


def the_rest(chain, general) -> None:
    ours, theirs = chain.metric_arrays(), general.metric_arrays()
    print("metrics:", {k: _gap(ours[k], theirs[k]) for k in ours if k != "status"},
          "status", ours["status"], theirs["status"])
    a, b = chain.summary(), general.summary()
    for group in a:
        for element, row in a[group].items():
            other = b[group].get(element, {})
            print(f"summary {group}.{element}:",
                  {k: _gap(np.array(v), np.array(other.get(k, np.nan))) for k, v in row.items()})
    lines = [{(f.level, f.kind, f.where, f.message) for f in r.verdict.findings}
             for r in (chain, general)]
    print("verdict lines only single-path:", lines[0] - lines[1])
    print("verdict lines only general:", lines[1] - lines[0])
    c, g = set(chain.to_dataframe().columns), set(general.to_dataframe().columns)
    print("columns only single-path:", sorted(c - g))
    print("columns only general:", sorted(g - c))
    print("global attributes only single-path:", sorted(set(chain.signals.attrs)
                                                        - set(general.signals.attrs)))
    print("global attributes only general:", sorted(set(general.signals.attrs)
                                                    - set(chain.signals.attrs)))


def sections(chain, general) -> None:
    from webline.report.writer import write_report

    with tempfile.TemporaryDirectory() as tmp:
        for name, result in (("single-path", chain), ("general", general)):
            write_report(result, Path(tmp) / name)
            html = next((Path(tmp) / name).rglob("*.html")).read_text()
            print(f"report sections, {name}:", re.findall(r"<h2[^>]*>(.*?)</h2>", html))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--seconds", type=float, default=3.0)
    parser.add_argument("--report", action="store_true", help="also the reports' sections")
    args = parser.parse_args()
    one_web = load_branched(ONE_WEB)
    for scenario in (None, *webline.load_line("hswl").spec.scenarios):
        chain = webline.simulate("hswl", args.seconds, scenario=scenario)
        general = webline.simulate(one_web, args.seconds, scenario=scenario)
        print(f"\n## scenario {scenario or '(default)'}, {args.seconds:g} s\n")
        if scenario is None:
            variables(chain, general)
        the_rest(chain, general)
        if scenario is None and args.report:
            sections(chain, general)


if __name__ == "__main__":
    main()
