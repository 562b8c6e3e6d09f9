"""HTML building blocks of a report: escaped tables, notes and figures with a reading guide.

Figures are PNG drawn at twice the CSS size (192 dpi shown at 96 dpi) so that they stay
sharp on high-density screens and in print; the page scales them down to its width.
"""

import base64
import html
import io

import numpy as np

__all__ = ["figure_html", "new_axes", "note_html", "table_html"]

#: CSS pixels per inch, and the drawing resolution (twice that).
CSS_DPI = 96
DRAW_DPI = 2 * CSS_DPI


def _esc(value):
    return html.escape(str(value))


def _fmt(value):
    if value is None:
        return "none"
    if isinstance(value, float | np.floating):
        return "n/a" if not np.isfinite(value) else f"{value:.6g}"
    return value


def note_html(text):
    """Return a highlighted note (where a figure or number is not available, and why)."""
    return f'<p class="note">{_esc(text)}</p>'


def table_html(rows, header=None, *, wide=False):
    """Return an HTML table built from an iterable of row tuples.

    ``wide=True`` marks a table with long cells (paths, hashes): it wraps them and
    scrolls inside its own box rather than widening the page.
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
    fig = figure if hasattr(figure, "savefig") else np.ravel(figure)[0].figure
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=DRAW_DPI)
    width_px = round(fig.get_figwidth() * CSS_DPI)
    data = base64.b64encode(buf.getvalue()).decode("ascii")
    return (f'<figure><img alt="{_esc(caption)}" width="{width_px}" '
            f'src="data:image/png;base64,{data}">'
            f"<figcaption><b>{_esc(caption)}.</b> {_esc(how_to_read)}</figcaption></figure>")
