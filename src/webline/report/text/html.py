"""One self-contained HTML page: inline CSS, figures as base64 PNG, no script, no external URL.

A page is a list of sections; a section holds tables, figures, paragraphs and preformatted
text. ``render`` escapes every piece of text it is given.
"""

from __future__ import annotations

import base64
from collections.abc import Sequence
from dataclasses import dataclass, field
from html import escape

from webline.report.text.tables import Table

CSS = """
body { font-family: system-ui, -apple-system, "Segoe UI", Roboto, sans-serif; margin: 0;
       color: #1d1d1f; background: #fafafa; line-height: 1.45; }
main { max-width: 1100px; margin: 0 auto; padding: 1.5rem 2rem 3rem; background: white; }
h1 { font-size: 1.6rem; margin-bottom: .2rem; } h2 { font-size: 1.25rem; margin-top: 2rem;
  border-bottom: 1px solid #ddd; padding-bottom: .2rem; } h3 { font-size: 1rem; }
.subtitle { color: #555; margin-top: 0; }
.status { padding: .6rem 1rem; border-radius: 6px; margin: 1rem 0; }
.status.ok { background: #e8f5e9; border: 1px solid #a5d6a7; }
.status.failed { background: #fdecea; border: 1px solid #f5a9a3; }
.status.warning { background: #fff4e0; border: 1px solid #f0c36d; }
.status.interrupted { background: #eeeeee; border: 1px solid #bbbbbb; }
.status .headline { font-weight: 600; display: block; }
table { border-collapse: collapse; margin: .5rem 0 1rem; font-size: .88rem; }
th, td { border: 1px solid #ddd; padding: .25rem .6rem; text-align: right; }
th { background: #f2f4f7; } td:first-child, th:first-child { text-align: left; }
summary { cursor: pointer; color: #1f4e8c; }
td.text, th.text { text-align: left; }
figure { margin: 1rem 0 1.5rem; } figure img { max-width: 100%; height: auto; }
figcaption { color: #555; font-size: .9rem; }
pre { background: #f6f8fa; padding: .8rem; overflow-x: auto; font-size: .8rem; }
footer { color: #777; font-size: .8rem; margin-top: 2rem; }
"""


@dataclass(frozen=True)
class Image:
    """A PNG figure to inline, with the caption shown under it."""

    key: str
    caption: str
    png: bytes


@dataclass(frozen=True)
class Text:
    """A paragraph, or a preformatted block (``pre=True``) folded under ``fold`` if given."""

    text: str
    pre: bool = False
    fold: str = ""


@dataclass(frozen=True)
class Section:
    """A titled part of the page."""

    title: str
    parts: Sequence[Table | Image | Text] = field(default_factory=tuple)


def table_html(table: Table) -> str:
    """A ``Table`` as an HTML table with its title as a heading."""
    numeric = [all(_numeric(row[j]) for row in table.rows) for j in range(len(table.columns))]
    head = "".join(f"<th>{escape(c)}</th>" if numeric[j] else f'<th class="text">{escape(c)}</th>'
                   for j, c in enumerate(table.columns))
    rows = []
    for row in table.rows:
        cells = "".join(f"<td>{escape(c)}</td>" if numeric[j] else
                        f'<td class="text">{escape(c)}</td>' for j, c in enumerate(row))
        rows.append(f"<tr>{cells}</tr>")
    return (f'<h3>{escape(table.title)}</h3>\n<table id="{escape(table.key)}">'
            f"<thead><tr>{head}</tr></thead><tbody>{''.join(rows)}</tbody></table>")


def _numeric(cell: str) -> bool:
    try:
        float(cell.split(" ")[0])
    except ValueError:
        return cell == "–"
    return True


def _part_html(part: Table | Image | Text) -> str:
    if isinstance(part, Table):
        return table_html(part)
    if isinstance(part, Image):
        data = base64.b64encode(part.png).decode("ascii")
        return (f'<figure id="fig-{escape(part.key)}"><img alt="{escape(part.caption)}" '
                f'src="data:image/png;base64,{data}"><figcaption>{escape(part.caption)}'
                "</figcaption></figure>")
    if part.pre and part.fold:
        return (f"<details><summary>{escape(part.fold)}</summary>"
                f"<pre>{escape(part.text)}</pre></details>")
    if part.pre:
        return f"<pre>{escape(part.text)}</pre>"
    return f"<p>{escape(part.text)}</p>"


def render(title: str, subtitle: str, status: str, status_class: str,
           sections: Sequence[Section], footer: str, headline: str = "") -> str:
    """The whole page as one HTML string (UTF-8, no external resources). The status box shows
    ``headline`` (bold) and ``status`` and is coloured by ``status_class`` (ok, warning,
    failed, interrupted)."""
    box = (f'<span class="headline">{escape(headline)}</span>' if headline else "") + escape(
        status)
    body = []
    for section in sections:
        anchor = section.title.lower().replace(" ", "-")
        body.append(f'<section id="{escape(anchor)}"><h2>{escape(section.title)}</h2>')
        body.extend(_part_html(part) for part in section.parts)
        body.append("</section>")
    return f"""<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<title>{escape(title)}</title>
<link rel="icon" href="data:,">
<style>{CSS}</style>
</head>
<body>
<main>
<h1>{escape(title)}</h1>
<p class="subtitle">{escape(subtitle)}</p>
<div class="status {escape(status_class)}" id="verdict">{box}</div>
{chr(10).join(body)}
<footer>{escape(footer)}</footer>
</main>
</body>
</html>
"""
