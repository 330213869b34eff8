"""Tables kept as data and rendered as Markdown, HTML or CSV.

The run folder keeps the CSV; the report reads it back.
"""

from __future__ import annotations

import csv
import html
import io
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from .._files import write_text
from .._readers import read_text
from ..errors import FileError

__all__ = ["Table", "read_csv"]


def _text(value: Any) -> str:
    if isinstance(value, bool):
        return "yes" if value else "NO"
    return str(value)


@dataclass(frozen=True)
class Table:
    """Rows of values under named columns.

    Args:
        columns: the column names.
        rows: one sequence of values per row; values show as ``str`` gives them (round
            numbers before), bools as yes/NO in Markdown and HTML.
    """

    columns: Sequence[str]
    rows: Sequence[Sequence[Any]]

    def _cells(self) -> list[list[str]]:
        return [[_text(v) for v in row] for row in self.rows]

    def to_markdown(self) -> str:
        """A Markdown pipe table."""
        def line(cells):
            return "| " + " | ".join(str(c).replace("|", "\\|") for c in cells) + " |"

        body = [line(r) for r in self._cells()]
        return "\n".join([line(self.columns), "|" + "---|" * len(self.columns), *body]) + "\n"

    def to_html(self) -> str:
        """An HTML table; the texts "yes" and "NO" get the classes ``yes`` and ``no``."""
        def cell(tag, text):
            cls = {"yes": ' class="yes"', "NO": ' class="no"'}.get(text, "")
            return f"<{tag}{cls}>{html.escape(text)}</{tag}>"

        head = "".join(cell("th", c) for c in self.columns)
        body = "".join("<tr>" + "".join(cell("td", c) for c in r) + "</tr>"
                       for r in self._cells())
        return f"<table><thead><tr>{head}</tr></thead><tbody>{body}</tbody></table>"

    def to_csv(self) -> str:
        """CSV text with a header row (values in full)."""
        buffer = io.StringIO()
        writer = csv.writer(buffer, lineterminator="\n")
        writer.writerow(self.columns)
        writer.writerows(self.rows)
        return buffer.getvalue()

    def write(self, stem: Path) -> list[Path]:
        """Write ``<stem>.csv`` and ``<stem>.md`` (atomically); returns their paths."""
        stem = Path(stem)
        return [write_text(stem.with_suffix(".csv"), self.to_csv()),
                write_text(stem.with_suffix(".md"), self.to_markdown())]


def read_csv(path: Path) -> Table:
    """A table written by :meth:`Table.write` (values come back as text, bools as bools)."""
    try:
        rows = list(csv.reader(io.StringIO(read_text(path, "a CSV table", 2**28), newline="")))
    except csv.Error as err:
        raise FileError(f"{path}: not a CSV table ({err}); expected a CSV table") from None
    if not rows:
        return Table((), ())
    flags = {"True": True, "False": False}
    return Table(rows[0], [[flags.get(v, v) for v in r] for r in rows[1:]])
