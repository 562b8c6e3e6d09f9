"""HTML building blocks of a report: escaped tables, notes and figures with a reading guide.

Figures are PNG drawn at twice the CSS size (192 dpi shown at 96 dpi) so that they stay
sharp on high-density screens and in print; the page scales them down to its width.
"""

import base64
import html

import numpy as np

__all__ = ["figure_html", "new_axes", "new_map_axes", "map_row_width", "note_html",
           "table_html", "details_html"]

#: CSS pixels per inch, and the drawing resolution (twice that).
CSS_DPI = 96
DRAW_DPI = 2 * CSS_DPI


def _esc(value):
    return html.escape(str(value))


def _fmt(value):
    """Return a cell for people (numbers through :func:`tactilecal._text.number`)."""
    from tactilecal._text import number

    if value is None:
        return "none"
    if isinstance(value, float | np.floating):
        return number(float(value)) if np.isfinite(value) else "n/a"
    return value


def note_html(text):
    """Return a highlighted note (where a figure or number is not available, and why)."""
    return f'<p class="note">{_esc(text)}</p>'


def table_html(rows, header=None, *, wide=False):
    """Return an HTML table built from an iterable of row tuples.

    ``wide=True`` marks a table with long cells (paths, hashes): they wrap anywhere, so
    the table never widens the page, on screen or on paper.
    """
    head = "" if header is None else "<tr>" + "".join(f"<th>{_esc(h)}</th>" for h in header) \
        + "</tr>"
    body = "".join("<tr>" + "".join(f"<td>{_esc(_fmt(v))}</td>" for v in row) + "</tr>"
                   for row in rows)
    return f'<div class="table{" wide" if wide else ""}"><table>{head}{body}</table></div>'


def new_axes(figsize=(6, 4), *, ncols=1):
    """Return fresh Axes on a Figure that is not registered with pyplot."""
    from matplotlib.figure import Figure

    return Figure(figsize=figsize, layout="constrained").subplots(1, ncols)


def map_row_width(recording, n, *, page_in=7.2):
    """Width [in] of a row of ``n`` maps of ``recording``: at most a printed page's width."""
    rows, cols = recording.sizes["row"], recording.sizes["col"]
    aspect = rows * float(recording.attrs["row_spacing_mm"]) / (
        cols * float(recording.attrs["col_spacing_mm"]))
    one = min(page_in / n, 5.0 / max(aspect, 1e-3) + 1.3)
    return round(n * one, 1)


def new_map_axes(recording, n, *, width):
    """Return ``n`` axes side by side for maps of ``recording`` (the "compressed" layout)."""
    from matplotlib.figure import Figure

    rows, cols = recording.sizes["row"], recording.sizes["col"]
    aspect = rows * float(recording.attrs["row_spacing_mm"]) / (
        cols * float(recording.attrs["col_spacing_mm"]))
    map_w = width / n - 1.3
    height = float(np.clip(map_w * aspect + 1.6, 2.5, 6.0))
    return Figure(figsize=(width, height), layout="compressed").subplots(1, n)


def details_html(summary, body):
    """Return a collapsible section: ``summary`` shown, ``body`` (HTML) on opening it."""
    return f"<details><summary>{_esc(summary)}</summary>{body}</details>"


def figure_html(figure, caption, how_to_read):
    """Embed a matplotlib Figure (or Axes) as a 2x PNG ``<figure>``.

    Parameters
    ----------
    figure : matplotlib.figure.Figure or matplotlib.axes.Axes or array of Axes
    caption : str
        What the figure shows.
    how_to_read : str
        One sentence that says how to read it.
    """
    from tactilecal._png import png_bytes

    fig = figure if hasattr(figure, "savefig") else np.ravel(figure)[0].figure
    width_px = round(fig.get_figwidth() * CSS_DPI)
    data = base64.b64encode(png_bytes(fig, DRAW_DPI)).decode("ascii")
    height_px = round(fig.get_figheight() * CSS_DPI)
    return (f'<figure><img alt="{_esc(caption)}" width="{width_px}" height="{height_px}" '
            f'src="data:image/png;base64,{data}">'
            f"<figcaption><b>{_esc(caption)}.</b> {_esc(how_to_read)}</figcaption></figure>")
