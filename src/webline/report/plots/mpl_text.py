"""User-supplied names made literal for matplotlib text.

Matplotlib reads a string with an even number of unescaped ``$`` as mathtext, so a roller
named ``$\\frac{$`` breaks the figure (a ValueError while drawing). Escaping each ``$`` as
``\\$`` keeps the name literal while the figures' own math (tick labels such as
``$\\mathdefault{10^{1}}$`` of log axes, offset texts) still renders; switching
``text.parse_math`` off instead would print those tick labels raw. Other TeX characters
(``_ ^ % \\ { }``) are plain text outside mathtext; webline never enables ``text.usetex``.
"""

from __future__ import annotations

import math


def literal(text: str) -> str:
    """``text`` as matplotlib shows it verbatim: every ``$`` escaped."""
    return text.replace("$", r"\$")


def legend_label(text: str) -> str:
    """``literal(text)`` for a legend entry; a leading ``_`` (which matplotlib takes as "leave
    out of the legend") gets a space before it."""
    text = literal(text)
    return " " + text if text.startswith("_") else text


#: digits and minus sign as superscripts (DejaVu Sans, matplotlib's default font, has them)
_SUPERSCRIPT = str.maketrans("-0123456789", "⁻⁰¹²³⁴⁵⁶⁷⁸⁹")


def power_label(value: float, _position: object = None) -> str:
    """A tick of a symmetric-log axis as plain text: ``−10²``, ``0``, ``10¹`` (a value that is
    no power of ten as ``%g``). Matplotlib's own labels for these ticks are mathtext, whose
    parser costs about 0.2 s of CPU to build in each process that draws them (a report's
    poles figure; issue 37: the main job's CPU)."""
    if value == 0.0:
        return "0"
    exponent = math.log10(abs(value))
    if abs(exponent - round(exponent)) > 1e-9:
        return f"{value:g}".replace("-", "−")
    return ("−" if value < 0.0 else "") + "10" + str(round(exponent)).translate(_SUPERSCRIPT)
