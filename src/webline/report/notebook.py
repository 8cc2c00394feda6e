"""What a notebook shows of a line: its schematic (SVG) and key tables.

``Line._repr_html_`` (in the ``line`` layer, below the report) calls ``line_html`` through the
named display hook ``webline.line.HTML_VIEW``, resolved when a notebook first displays a line,
as pandas resolves its plotting backend by name: the line layer imports nothing of the report.
"""

from __future__ import annotations

import io

from webline.line import Line
from webline.report.text.describe import line_tables
from webline.report.text.display import Display, System
from webline.report.text.html import table_html

#: the tables a notebook shows (``describe.line_tables``' keys); ``webline show`` has them all
KEY_TABLES = ("line", "rollers", "spans", "drives", "zones")


def schematic_svg(line: Line, display: Display | None = None) -> str:
    """The report's schematic of ``line`` as an inline SVG element (no XML header, no date,
    element ids from a fixed salt: the same line gives the same text)."""
    import matplotlib

    from webline.report.plots.schematic import schematic

    buffer = io.StringIO()
    with matplotlib.rc_context({"svg.hashsalt": "webline", "svg.fonttype": "none"}):
        schematic(line, display).savefig(buffer, format="svg", metadata={"Date": None})
    text = buffer.getvalue()
    return text[text.index("<svg"):]


def line_html(line: Line, units: System = "si") -> str:
    """``line`` for a notebook: its schematic (SVG) and its key tables (``KEY_TABLES``) in
    ``units`` ("si", "imperial", "si-per-width", "imperial-per-width")."""
    display = Display(units, line.spec.web.width)
    tables = [t for t in line_tables(line, display) if t.key in KEY_TABLES and t.rows]
    return ("<div class='webline-line'>"
            f"<div style='max-width:100%;overflow-x:auto'>{schematic_svg(line, display)}</div>"
            + "".join(table_html(t) for t in tables) + "</div>")
