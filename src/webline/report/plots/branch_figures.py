"""Figures of a branched line's run (docs/branching.md): tensions per web."""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure

from webline.report.plots.frame import framed_figure
from webline.sim.branches.result import BranchResult


def tensions_figure(result: BranchResult) -> Figure:
    """One axes per web (raw web, laminate, lane): the tension [N] of each of its spans
    against time [s]; a laminate's axes also show its layers' tensions in its first span
    (dashed). The title of each axes gives its span tensions' range over the run."""
    ds = result.dataset
    webs = list(ds["web"].values)
    fig = framed_figure(8.0, 1.0 + 1.9 * len(webs), rows=len(webs))
    axes = np.atleast_1d(fig.subplots(len(webs), 1, sharex=True))
    t = ds["time"].values
    for ax, web in zip(axes, webs, strict=True):
        spans = ds["tension"].sel(span=ds["span_web"] == web)
        for name in spans["span"].values:
            ax.plot(t, spans.sel(span=name).values, label=str(name))
        for name in ds["layer_span"].values:
            if str(name).split("/")[0] == str(spans["span"].values[0]):
                ax.plot(t, ds["layer_tension"].sel(layer_span=name).values, "--",
                        label=f"layer {str(name).split('/')[1]}")
        low, high = float(spans.values.min()), float(spans.values.max())
        ax.set_title(f"{web}: span tensions {low:.4g} to {high:.4g} N", fontsize=9)
        ax.set_ylabel("tension [N]")
        ax.legend(fontsize=7, loc="best")
        ax.grid(alpha=0.3)
    axes[-1].set_xlabel("time [s]")
    return fig
