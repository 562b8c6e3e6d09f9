"""PNG images of matplotlib figures: one draw on an Agg canvas, encoded for plots.

``Figure.savefig`` on a figure with a layout engine ("constrained", "compressed") draws it
twice: once with rendering disabled, to place the axes, then once more to render. Drawing on
an Agg canvas runs the layout engine and renders in the same pass, as an interactive window
does, so every writer of figures here draws each figure once and encodes its pixels itself:

* a figure whose every pixel is opaque (a white figure) is stored as RGB, its alpha channel
  (all 255) left out; other figures keep RGBA;
* zlib's run-length strategy (``Z_RLE``), which suits the long runs of one colour of a plot
  about as well as the default strategy for a fraction of its time.

The decoded pixels are those ``savefig`` would write at the same ``dpi``.
"""

import io
import zlib
from pathlib import Path

import numpy as np

from tactilecal._atomic import atomic_path

__all__ = ["png_bytes", "write_png", "FIGURE_DPI"]

FIGURE_DPI = 120
"""Resolution of the figures written as PNG files (every ``save_figures``, ``tactilecal
plot`` and ``tactilecal compare``)."""

#: Pillow's PNG options: zlib's run-length strategy (``Z_RLE``).
PNG_OPTIONS = {"compress_type": zlib.Z_RLE}


def _pixels(figure, dpi):
    """Draw ``figure`` once at ``dpi`` on an Agg canvas; return its RGBA pixels.

    The figure's own canvas and dpi are restored afterwards, as ``savefig`` does.
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    old_canvas, old_dpi = figure.canvas, figure.dpi
    try:
        figure.dpi = dpi
        canvas = FigureCanvasAgg(figure)
        canvas.draw()
        return np.array(canvas.buffer_rgba())
    finally:
        figure.set_canvas(old_canvas)
        figure.dpi = old_dpi


def _image(figure, dpi):
    from PIL import Image

    rgba = _pixels(figure, dpi)
    opaque = bool((rgba[..., 3] == 255).all())
    return Image.fromarray(rgba[..., :3] if opaque else rgba)


def png_bytes(figure, dpi):
    """Return ``figure`` (a matplotlib Figure) as PNG bytes at ``dpi``, drawn once."""
    buf = io.BytesIO()
    _image(figure, dpi).save(buf, format="png", dpi=(dpi, dpi), **PNG_OPTIONS)
    return buf.getvalue()


def write_png(figure, path, dpi):
    """Write ``figure`` as a PNG file at ``path`` (``dpi``), drawn once, atomically.

    The bytes go to a temporary file next to ``path``, renamed onto it when written
    (:func:`~tactilecal._atomic.atomic_path`): a failed write leaves ``path`` as it was.
    """
    data = png_bytes(figure, dpi)
    with atomic_path(path) as tmp:
        Path(tmp).write_bytes(data)
