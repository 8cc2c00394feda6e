"""Hints for command-line mistakes that the parser alone reports obscurely (issue 37).

``webline run hswl --set web.ea=9 kN`` reaches the parser as ``--set web.ea=9`` and an extra
argument ``kN`` (the shell split the value at its space): ``WeblineGroup`` turns the parser's
"Got unexpected extra argument(s) (kN)" into one line that says to quote the value.
``distribution_hint`` says the same for a distribution given to a sweep without ``--samples``.
"""

from __future__ import annotations

import re
from typing import Any

import typer
from typer.core import TyperGroup

try:  # typer >= 0.25 carries its own copy of click
    from typer._click.exceptions import UsageError
except ImportError:  # pragma: no cover - typer on click
    from click.exceptions import UsageError  # type: ignore[assignment]

_EXTRA = re.compile(r"^Got unexpected extra arguments? ?\(?s?\)? \((.*)\)$")
#: a value written as a call: a distribution (``normal(9 kN, 5 %)``) or anything like it
_CALL = re.compile(r"^\s*[A-Za-z_]\w*\s*\(.*,.*\)\s*$")


def quote_hint(args: list[str], message: str) -> str | None:
    """The one-line error for ``message`` (the parser's) where its extra arguments are the
    rest of a ``--set`` value the shell split at a space, given the command's ``args``;
    None where they are not."""
    match = _EXTRA.match(message)
    if not match:
        return None
    extras = match.group(1).split(" ")
    for j in range(1, len(args)):
        if args[j] != extras[0]:
            continue
        before = args[j - 1]
        if before.startswith("--set="):
            value = before[len("--set=") :]
        elif j >= 2 and args[j - 2] == "--set" and "=" in before:
            value = before
        else:
            continue
        rest: list[str] = []
        for token in args[j:]:
            if token.startswith("-") or len(rest) == len(extras):
                break
            rest.append(token)
        whole = " ".join([value, *rest])
        return (
            f"error: --set {whole}: the shell split this value at its space(s) and "
            f'{" ".join(rest)!r} became an extra argument; quote it: --set "{whole}"'
        )
    return None


def distribution_hint(path: str, text: str) -> str | None:
    """The one-line error for a sweep's ``--set PATH=TEXT`` where ``TEXT`` is a call such as
    ``normal(9 kN, 5 %)`` (a distribution, whose comma would split it into two values) and
    ``--samples`` was not given; None otherwise."""
    if not _CALL.match(text):
        return None
    return (
        f"--set {path}={text}: a distribution needs --samples N (a Monte Carlo study of N "
        f"cases); without it --set takes a list of values and would split this one at "
        f"its comma"
    )


class WeblineGroup(TyperGroup):
    """The app's command group: as typer's, with ``quote_hint`` for an unquoted ``--set``."""

    def invoke(self, ctx: Any) -> Any:
        protected = getattr(ctx, "_protected_args", None) or getattr(ctx, "protected_args", [])
        args = [*protected, *ctx.args]  # the subcommand's name and what it will parse
        try:
            return super().invoke(ctx)
        except UsageError as exc:
            hint = quote_hint(args, exc.message)
            if hint is None:
                raise
            typer.echo(hint, err=True)
            raise typer.Exit(2) from None
