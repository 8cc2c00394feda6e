"""User-supplied names made literal for matplotlib text.

Matplotlib reads a string with an even number of unescaped ``$`` as mathtext, so a roller
named ``$\\frac{$`` breaks the figure (a ValueError while drawing). Escaping each ``$`` as
``\\$`` keeps the name literal while the figures' own math (tick labels such as
``$\\mathdefault{10^{1}}$`` of log axes, offset texts) still renders; switching
``text.parse_math`` off instead would print those tick labels raw. Other TeX characters
(``_ ^ % \\ { }``) are plain text outside mathtext; webline never enables ``text.usetex``.
"""

from __future__ import annotations


def literal(text: str) -> str:
    """``text`` as matplotlib shows it verbatim: every ``$`` escaped."""
    return text.replace("$", r"\$")


def legend_label(text: str) -> str:
    """``literal(text)`` for a legend entry; a leading ``_`` (which matplotlib takes as "leave
    out of the legend") gets a space before it."""
    text = literal(text)
    return " " + text if text.startswith("_") else text
