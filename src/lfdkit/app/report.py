"""Self-contained HTML reports of an lfdkit run.

:class:`Report` collects headings, paragraphs, figures, tables and key/value
lists, and renders them as ONE HTML file that needs nothing else: the CSS is
inline, there are no scripts or web fonts, and figures are embedded as base64
PNG ``data:`` URIs. The page can be mailed, attached to a ticket or archived
next to the run's outputs and will look the same anywhere, printed included.

Everything given to the builder is treated as plain text and HTML-escaped.

Examples
--------
>>> from lfdkit.app.report import Report
>>> report = Report("Reaching task", subtitle="5 demonstrations, 2-D")
>>> _ = report.heading("Settings").definition_list({"method": "GMR", "n_components": 5})
>>> _ = report.heading("Errors").table([{"method": "GMR", "rmse": 0.01234}])
>>> report.html().startswith("<!DOCTYPE html>")
True
"""

from __future__ import annotations

import base64
import io
import numbers
import re
import unicodedata
from collections.abc import Mapping, Sequence
from datetime import datetime, timezone
from html import escape
from pathlib import Path
from typing import TYPE_CHECKING
from urllib.parse import quote

import numpy as np

import lfdkit
from lfdkit.io import write_text
from lfdkit.model.demos import PathLike

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = ["PNG_SIGNATURE", "Report"]

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"
"""The eight bytes every PNG file starts with."""

_MISSING = "\u2013"  # en dash, shown for None / missing cells
_DEFAULT_FLOAT_FORMAT = ".4g"

_CSS = """\
:root { --fg: #1f2328; --muted: #656d76; --line: #d0d7de; --zebra: #f6f8fa; --accent: #0969da; }
* { box-sizing: border-box; }
body { margin: 0 auto; max-width: 1100px; padding: 1.5rem 1.25rem 3rem; color: var(--fg);
  font: 16px/1.5 system-ui, -apple-system, "Segoe UI", Roboto, "Helvetica Neue", Arial,
  sans-serif; }
header { border-bottom: 1px solid var(--line); margin-bottom: 1.25rem; }
h1 { font-size: 1.8rem; margin: 0 0 .25rem; }
h2 { font-size: 1.35rem; margin: 2rem 0 .75rem; padding-bottom: .2rem;
  border-bottom: 1px solid var(--line); }
.subtitle { font-size: 1.1rem; margin: 0 0 .25rem; }
.meta, .caption, figcaption, caption { color: var(--muted); font-size: .9rem; }
a { color: var(--accent); text-decoration: none; }
a:hover { text-decoration: underline; }
nav.toc { background: var(--zebra); border: 1px solid var(--line); border-radius: 6px;
  padding: .5rem 1rem; display: inline-block; min-width: 16rem; }
nav.toc ol { margin: .25rem 0; padding-left: 1.5rem; }
figure { margin: 1.25rem 0; break-inside: avoid; page-break-inside: avoid; }
figure img { display: block; max-width: 100%; height: auto; }
figcaption { margin-top: .4rem; }
.table-wrap { overflow-x: auto; margin: 1rem 0; break-inside: avoid; }
table { border-collapse: collapse; font-size: .95rem; }
caption { caption-side: top; text-align: left; padding-bottom: .3rem; }
th, td { border: 1px solid var(--line); padding: .3rem .65rem; text-align: left;
  vertical-align: top; }
thead th { background: #eaeef2; }
tbody tr:nth-child(even) { background: var(--zebra); }
.num { text-align: right; font-variant-numeric: tabular-nums;
  font-family: ui-monospace, SFMono-Regular, Menlo, Consolas, monospace; }
.empty { color: var(--muted); font-style: italic; }
.kv { margin: 1rem 0; break-inside: avoid; }
.kv dl { display: grid; grid-template-columns: max-content auto; gap: .2rem 1.25rem;
  margin: .3rem 0; }
.kv dt { font-weight: 600; }
.kv dd { margin: 0; }
@media print {
  body { max-width: none; padding: 0; font-size: 11pt; }
  h2 { break-after: avoid; page-break-after: avoid; }
  a { color: inherit; }
  .table-wrap { overflow: visible; }
}
"""


def _text(value: object) -> str:
    """``value`` as escaped HTML text (quotes escaped too, so it is safe in attributes)."""
    return escape(str(value), quote=True)


def _slug(text: str) -> str:
    """A URL-fragment-friendly id from heading text (ASCII letters, digits and dashes)."""
    ascii_text = unicodedata.normalize("NFKD", text).encode("ascii", "ignore").decode("ascii")
    slug = re.sub(r"[^a-z0-9]+", "-", ascii_text.lower()).strip("-")
    return slug or "section"


def _is_bool(value: object) -> bool:
    return isinstance(value, bool | np.bool_)


def _is_int(value: object) -> bool:
    return isinstance(value, numbers.Integral) and not _is_bool(value)


def _is_float(value: object) -> bool:
    return isinstance(value, numbers.Real) and not isinstance(value, numbers.Integral)


def _is_numeric(value: object) -> bool:
    return _is_int(value) or _is_float(value)


def _format_value(value: object, spec: str | None, column: str) -> str:
    """Plain-text rendering of one cell value (not yet escaped)."""
    if value is None:
        return _MISSING
    if _is_bool(value):
        return "yes" if value else "no"
    if _is_int(value):
        return str(int(value))  # type: ignore[call-overload]
    if _is_float(value):
        spec = _DEFAULT_FLOAT_FORMAT if spec is None else spec
        try:
            return format(float(value), spec)  # type: ignore[arg-type]
        except (ValueError, TypeError) as exc:
            raise ValueError(
                f"formats[{column!r}]: invalid float format spec {spec!r} ({exc})"
            ) from None
    return str(value)


def _png_size(png: bytes) -> tuple[int, int] | None:
    """``(width, height)`` from the PNG's IHDR chunk, or None if it is not there."""
    if len(png) >= 24 and png[12:16] == b"IHDR":
        return int.from_bytes(png[16:20], "big"), int.from_bytes(png[20:24], "big")
    return None


class Report:
    """Builder for one self-contained HTML page showing the results of a run.

    Add content in reading order with :meth:`heading`, :meth:`paragraph`,
    :meth:`figure`, :meth:`table` and :meth:`definition_list`, then get the page
    with :meth:`html` or save it with :meth:`write`. Each of the five adding
    methods returns the report itself, so calls chain.

    Parameters
    ----------
    title : str
        Page title, shown in the browser tab and as the top heading.
    subtitle : str
        Optional line under the title (e.g. the data set and the date of the run).

    Notes
    -----
    All text is plain text, never HTML: it is escaped when rendered. Figures are
    rendered to PNG when added, so a matplotlib figure may be changed or closed
    afterwards without affecting the report.
    """

    def __init__(self, title: str, *, subtitle: str = "") -> None:
        self.title = str(title)
        self.subtitle = str(subtitle)
        self._blocks: list[str] = []
        self._toc: list[tuple[str, str]] = []  # (id, text) per heading
        self._ids: set[str] = set()
        self._n_figures = 0

    # ------------------------------------------------------------------ #
    # Content
    # ------------------------------------------------------------------ #

    def heading(self, text: str) -> Report:
        """Start a section: an ``<h2>`` listed in the table of contents.

        Parameters
        ----------
        text : str
            Heading text. Its id is a slug of the text, made unique by a numeric
            suffix (``results``, ``results-2``, ...) when headings repeat.
        """
        text = str(text)
        base = _slug(text)
        anchor, n = base, 1
        while anchor in self._ids:
            n += 1
            anchor = f"{base}-{n}"
        self._ids.add(anchor)
        self._toc.append((anchor, text))
        self._blocks.append(f'<h2 id="{anchor}">{_text(text)}</h2>')
        return self

    def paragraph(self, text: str) -> Report:
        """Add plain text; blank lines separate paragraphs.

        Parameters
        ----------
        text : str
            The text. Runs of blank lines split it into ``<p>`` elements; single
            line breaks are kept as ordinary spaces by the browser.
        """
        for chunk in re.split(r"\n[ \t\r\f\v]*\n", str(text)):
            chunk = chunk.strip()
            if chunk:
                self._blocks.append(f"<p>{_text(chunk)}</p>")
        return self

    def figure(
        self,
        fig_or_png: Figure | bytes | bytearray | memoryview,
        caption: str = "",
        *,
        alt: str = "",
        dpi: int = 110,
    ) -> Report:
        """Embed a figure as a base64 PNG ``data:`` URI.

        Parameters
        ----------
        fig_or_png : matplotlib.figure.Figure or bytes
            A figure, rendered now with ``fig.savefig(buf, format="png", dpi=dpi)``,
            or the bytes of a PNG image.
        caption : str
            Text under the figure.
        alt : str
            Alternative text for the image; the caption (or ``"Figure N"``) if empty.
        dpi : int
            Resolution used to render a matplotlib figure (ignored for PNG bytes).

        Raises
        ------
        ValueError
            If ``fig_or_png`` is bytes that are not a PNG image, or ``dpi`` is not
            positive.
        TypeError
            If ``fig_or_png`` is neither a figure nor bytes.
        """
        if isinstance(fig_or_png, bytes | bytearray | memoryview):
            png = bytes(fig_or_png)
            if not png.startswith(PNG_SIGNATURE):
                raise ValueError(
                    "fig_or_png: bytes are not a PNG image (they do not start with the "
                    f"PNG signature {PNG_SIGNATURE!r}; got {png[:8]!r})"
                )
        elif hasattr(fig_or_png, "savefig"):
            if isinstance(dpi, bool) or not isinstance(dpi, numbers.Real) or not dpi > 0:
                raise ValueError(f"dpi: must be a positive number, got {dpi!r}")
            buf = io.BytesIO()
            fig_or_png.savefig(buf, format="png", dpi=dpi)
            png = buf.getvalue()
        else:
            raise TypeError(
                "fig_or_png: expected a matplotlib Figure or PNG bytes, "
                f"got {type(fig_or_png).__name__}"
            )
        self._n_figures += 1
        alt_text = str(alt) or str(caption) or f"Figure {self._n_figures}"
        size = _png_size(png)
        dims = f' width="{size[0]}" height="{size[1]}"' if size else ""
        data = base64.b64encode(png).decode("ascii")
        parts = [
            "<figure>",
            f'<img src="data:image/png;base64,{data}" alt="{_text(alt_text)}"{dims}>',
        ]
        if caption:
            parts.append(f"<figcaption>{_text(caption)}</figcaption>")
        parts.append("</figure>")
        self._blocks.append("\n".join(parts))
        return self

    def table(
        self,
        rows: Sequence[Mapping[str, object]],
        caption: str = "",
        *,
        columns: Sequence[str] | None = None,
        formats: Mapping[str, str] | None = None,
    ) -> Report:
        """Add a table, one row per mapping.

        Parameters
        ----------
        rows : sequence of mapping
            One mapping per row, column name to value.
        caption : str
            Text above the table.
        columns : sequence of str, optional
            Columns to show, in order. Default: every key of ``rows``, in the
            order first seen.
        formats : mapping of str to str, optional
            Format spec per column for floats (e.g. ``{"rmse": ".3g"}``); other
            floats use ``".4g"``. Keys that are not columns are ignored.

        Raises
        ------
        TypeError
            If a row is not a mapping.
        ValueError
            If a format spec is invalid for a float in its column.

        Notes
        -----
        Integers are shown as integers, booleans as ``yes``/``no`` and ``None``
        or missing values as an en dash. Numeric cells (and the header of a
        column whose values are all numeric) are right-aligned in tabular figures.
        """
        rows = list(rows)
        for i, row in enumerate(rows):
            if not isinstance(row, Mapping):
                raise TypeError(f"rows[{i}]: expected a mapping, got {type(row).__name__}")
        if columns is None:
            cols = list(dict.fromkeys(key for row in rows for key in row))
        else:
            cols = list(columns)
        formats = {} if formats is None else dict(formats)

        body: list[str] = []
        numeric_col = dict.fromkeys(cols, False)
        all_numeric = dict.fromkeys(cols, True)
        for row in rows:
            cells = []
            for col in cols:
                value = row.get(col)
                text = _format_value(value, formats.get(col), str(col))
                if _is_numeric(value):
                    numeric_col[col] = True
                    cells.append(f'<td class="num">{_text(text)}</td>')
                else:
                    if value is not None:
                        all_numeric[col] = False
                    cells.append(f"<td>{_text(text)}</td>")
            body.append("<tr>" + "".join(cells) + "</tr>")

        parts = ['<div class="table-wrap">']
        if not cols:
            if caption:
                parts.append(f'<p class="caption">{_text(caption)}</p>')
            parts.append('<p class="empty">No rows.</p>')
        else:
            parts.append("<table>")
            if caption:
                parts.append(f"<caption>{_text(caption)}</caption>")
            head = "".join(
                f'<th class="num">{_text(c)}</th>'
                if numeric_col[c] and all_numeric[c]
                else f"<th>{_text(c)}</th>"
                for c in cols
            )
            parts.append(f"<thead><tr>{head}</tr></thead>")
            if not body:
                body.append(f'<tr><td class="empty" colspan="{len(cols)}">No rows.</td></tr>')
            parts.append("<tbody>\n" + "\n".join(body) + "\n</tbody>")
            parts.append("</table>")
        parts.append("</div>")
        self._blocks.append("\n".join(parts))
        return self

    def definition_list(self, items: Mapping[str, object], caption: str = "") -> Report:
        """Add key/value pairs, e.g. the settings of a run.

        Parameters
        ----------
        items : mapping
            Names to values, shown in the mapping's order. Values are formatted
            as table cells are (floats with ``".4g"``, booleans as yes/no, ...).
        caption : str
            Text above the list.
        """
        parts = ['<div class="kv">']
        if caption:
            parts.append(f'<p class="caption">{_text(caption)}</p>')
        parts.append("<dl>")
        for key, value in items.items():
            text = _format_value(value, None, str(key))
            cls = ' class="num"' if _is_numeric(value) else ""
            parts.append(f"<dt>{_text(key)}</dt><dd{cls}>{_text(text)}</dd>")
        parts.append("</dl>")
        parts.append("</div>")
        self._blocks.append("\n".join(parts))
        return self

    def file_list(self, files: Mapping[str, str], caption: str = "") -> Report:
        """Add links to files next to the report, each with what it holds.

        Parameters
        ----------
        files : mapping of str to str
            Paths relative to the report's folder (``"skill.json"``,
            ``"figures/"``) to their descriptions. Each becomes a relative
            link, so the list works wherever the folder is copied; nothing
            outside it is linked.
        caption : str
            Text above the list.

        Raises
        ------
        ValueError
            For a path that is absolute, has a scheme (``http:``) or climbs
            out of the folder (``..``), naming it.
        """
        parts = ['<div class="files">']
        if caption:
            parts.append(f'<p class="caption">{_text(caption)}</p>')
        parts.append("<ul>")
        for path, description in files.items():
            name = str(path)
            pieces = name.replace("\\", "/").split("/")
            if not name or name.startswith("/") or ":" in name or ".." in pieces:
                raise ValueError(
                    f"files: {name!r} is not a path inside the report's folder; give a "
                    "relative path such as 'skill.json'"
                )
            href = escape(quote(name), quote=True)
            parts.append(
                f'<li><a href="{href}"><code>{_text(name)}</code></a> {_text(description)}</li>'
            )
        parts.append("</ul>")
        parts.append("</div>")
        self._blocks.append("\n".join(parts))
        return self

    # ------------------------------------------------------------------ #
    # Output
    # ------------------------------------------------------------------ #

    def html(self) -> str:
        """The complete HTML document.

        Returns
        -------
        str
            A self-contained HTML5 page (``\\n`` line endings). The generated-by
            line carries the current UTC time.
        """
        now = datetime.now(timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ")
        title = _text(self.title)
        out = [
            "<!DOCTYPE html>",
            '<html lang="en">',
            "<head>",
            '<meta charset="utf-8">',
            '<meta name="viewport" content="width=device-width, initial-scale=1">',
            '<meta name="generator" content="lfdkit">',
            f"<title>{title}</title>",
            f"<style>\n{_CSS}</style>",
            "</head>",
            "<body>",
            "<header>",
            f"<h1>{title}</h1>",
        ]
        if self.subtitle:
            out.append(f'<p class="subtitle">{_text(self.subtitle)}</p>')
        out.append(
            f'<p class="meta">Generated by lfdkit {_text(lfdkit.__version__)} on '
            f'<time datetime="{now}">{now}</time></p>'
        )
        out.append("</header>")
        if self._toc:
            out.append('<nav class="toc" aria-label="Contents">')
            out.append("<strong>Contents</strong>")
            out.append("<ol>")
            out.extend(
                f'<li><a href="#{anchor}">{_text(text)}</a></li>' for anchor, text in self._toc
            )
            out.append("</ol>")
            out.append("</nav>")
        out.append("<main>")
        out.extend(self._blocks)
        out.append("</main>")
        out.append("</body>")
        out.append("</html>")
        return "\n".join(out) + "\n"

    def write(self, path: PathLike, *, overwrite: bool = False) -> Path:
        """Save the page atomically, as UTF-8 (:func:`lfdkit.io.write_text`).

        Parameters
        ----------
        path : str or os.PathLike
            Destination file; its directory must exist.
        overwrite : bool
            Replace an existing file. When false an existing file is left
            intact and ``FileExistsError`` is raised.

        Returns
        -------
        pathlib.Path
            The page's file.

        Raises
        ------
        FileExistsError, IsADirectoryError, FileNotFoundError
            As :func:`lfdkit.io.write_text`: ``path`` exists and ``overwrite``
            is false, ``path`` is a directory, or its directory does not exist.
        """
        return write_text(path, self.html(), overwrite=overwrite)
