"""A recording as a movie: the pressure map frame by frame, its centre of force, saturation.

matplotlib's animation writers: MP4 through ffmpeg when it is installed, else an animated
GIF through Pillow (which matplotlib depends on).
"""

from pathlib import Path

import numpy as np

from tactilecal._atomic import atomic_path, check_target
from tactilecal._errors import TactilecalError
from tactilecal.analysis._plots import SATURATED_STYLE, _centre_path, draw_map, map_figsize
from tactilecal.analysis._units import display_unit, pressure_map_kPa, saturation_mask

__all__ = ["write_movie", "MAX_MOVIE_FRAMES", "movie_frames"]

MAX_MOVIE_FRAMES = 600
"""Longer recordings are shown every k-th frame so that a movie has at most this many."""


def movie_frames(n_frames, max_frames=MAX_MOVIE_FRAMES):
    """Return the frame positions a movie (or the report's player) shows: every k-th.

    Examples
    --------
    >>> movie_frames(10, 4).tolist()
    [0, 3, 6, 9]
    """
    if max_frames < 1:
        raise TactilecalError(f"max_frames is {max_frames!r}; expected a whole number >= 1")
    step = max(1, int(np.ceil(n_frames / max_frames)))
    return np.arange(0, n_frames, step)


def write_movie(recording, path, *, calibration=None, units=None, fps=None,
                max_frames=MAX_MOVIE_FRAMES, dpi=100, progress=None, overwrite=False):
    """Write the recording as a movie: MP4 when ffmpeg is present, else an animated GIF.

    Parameters
    ----------
    recording : xarray.DataArray
        Recording in the data model (a raw one without ``calibration`` in raw readings).
    path : str or os.PathLike
        Output ``.mp4`` or ``.gif``. Without ffmpeg an ``.mp4`` is written as a GIF next to
        it (same name, ``.gif``), which is returned.
    calibration : CalibrationResult or path, optional
        Applied to a raw recording.
    units : str, optional
        Pressure unit shown (default the recording's own pressure unit, else kPa).
    fps : float, optional
        Frames per second of the movie (default: real time for the frames shown).
    max_frames : int, default :data:`MAX_MOVIE_FRAMES`
        Longer recordings show every k-th frame.
    dpi : int, default 100
        Resolution.
    progress : callable, optional
        The progress protocol of :mod:`tactilecal._progress`, over the frames written.
    overwrite : bool, default False
        Replace an existing movie at the path written (never another kind of file).

    Returns
    -------
    pathlib.Path
        The file written (atomically).

    Notes
    -----
    Every frame shows the pressure map on one colour scale (0 to the recording's largest
    pressure), the centre of force (a white cross, in frames with at least 5 % of the peak
    force) and the saturated sensels (red crosses).

    Examples
    --------
    >>> import tempfile, pathlib, numpy as np, xarray as xr
    >>> rec = xr.DataArray(np.arange(18.0).reshape(2, 3, 3), dims=("frame", "row", "col"),
    ...                    coords={"time": ("frame", [0.0, 0.1])},
    ...                    attrs={"units": "kPa", "row_spacing_mm": 1.0, "col_spacing_mm": 1.0,
    ...                           "sensel_area_mm2": 1.0})
    >>> write_movie(rec, pathlib.Path(tempfile.mkdtemp()) / "m.gif", dpi=30).suffix
    '.gif'
    """
    from matplotlib import animation

    from tactilecal._progress import resolve

    path = Path(path)
    suffix = path.suffix.lower()
    if suffix not in (".mp4", ".gif"):
        raise TactilecalError(f"movie {path} ends in {suffix!r}; expected .mp4 or .gif")
    if suffix == ".mp4" and not animation.writers.is_available("ffmpeg"):
        path, suffix = path.with_suffix(".gif"), ".gif"
    check_target(path, overwrite=overwrite, kind="movie")
    positions = movie_frames(recording.sizes["frame"], max_frames)
    t = np.asarray(recording["time"].values, float) if "time" in recording.coords else \
        np.arange(recording.sizes["frame"], dtype=float)
    if fps is None:
        step_s = float(np.median(np.diff(t[positions]))) if positions.size > 1 else 1.0
        fps = float(np.clip(1.0 / step_s if step_s > 0 else 10.0, 1.0, 60.0))
    fig, update = _animator(recording, positions, t, calibration, units, dpi)
    frames = resolve(progress)(range(positions.size), total=positions.size, desc=path.name)
    with atomic_path(path, suffix=suffix) as tmp:
        rendered = _blitted(fig, update, frames)
        if suffix == ".gif":
            _write_gif(rendered, tmp, fps)
        else:
            _write_mp4(rendered, tmp, fps, animation.FFMpegWriter.bin_path())
    return path


def _blitted(fig, update, frames):
    """Yield ``(width, height, RGBA bytes)`` of each frame, drawing only what changes.

    The axes, colour bar and labels are drawn once; per frame only the map, the marks and
    the title (the artists marked animated) are drawn again onto the saved background
    (matplotlib's blitting), many times faster than drawing the whole figure.
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    canvas = FigureCanvasAgg(fig)
    canvas.draw()
    fig.set_layout_engine("none")  # laid out once: every frame has the same axes
    moving = [a for ax in fig.axes for a in ax.get_children() if a.get_animated()]
    background = canvas.copy_from_bbox(fig.bbox)
    for k in frames:
        update(k)
        canvas.restore_region(background)
        for artist in moving:
            artist.axes.draw_artist(artist)
        yield (*canvas.get_width_height(), bytes(canvas.buffer_rgba()))


def _write_gif(rendered, path, fps):
    """Write the frames as an animated GIF with Pillow, on the first frame's palette."""
    from PIL import Image

    images = []
    for width, height, rgba in rendered:
        rgb = Image.frombuffer("RGBA", (width, height), rgba, "raw", "RGBA", 0, 1).convert("RGB")
        images.append(rgb.quantize(colors=256) if not images
                      else rgb.quantize(palette=images[0]))
    images[0].save(path, format="GIF", save_all=True, append_images=images[1:],
                   duration=round(1000.0 / fps), loop=0)


def _write_mp4(rendered, path, fps, ffmpeg):
    """Pipe the frames to ffmpeg as raw RGBA; H.264 in an MP4 (even sizes, yuv420p)."""
    import subprocess

    process = None
    try:
        for width, height, rgba in rendered:
            if process is None:
                process = subprocess.Popen(
                    [ffmpeg, "-y", "-loglevel", "error", "-f", "rawvideo", "-pix_fmt", "rgba",
                     "-s", f"{width}x{height}", "-r", f"{fps:g}", "-i", "pipe:",
                     "-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2", "-vcodec", "libx264",
                     "-pix_fmt", "yuv420p", "-f", "mp4", str(path)],
                    stdin=subprocess.PIPE, stderr=subprocess.PIPE)
            try:
                process.stdin.write(rgba)
            except BrokenPipeError:  # ffmpeg stopped: its message is read below
                break
    finally:
        if process is not None:
            try:
                process.stdin.close()  # flushes what is buffered: ffmpeg may have stopped
            except BrokenPipeError:
                pass
            with process.stderr:
                error = process.stderr.read().decode(errors="replace").strip()
            if process.wait() != 0:
                raise TactilecalError(f"ffmpeg could not write {path}: {error[-300:]}; "
                                      "expected an MP4 (write a .gif instead)")


def _animator(recording, positions, t, calibration, units, dpi):
    """Return the figure and ``update(k)`` drawing the k-th shown frame."""
    from matplotlib.figure import Figure

    raw = recording.attrs.get("units") == "raw" and calibration is None
    if raw:
        values, label = np.asarray(recording.values, float)[positions], "raw reading"
    else:
        unit, factor = display_unit(recording, units)
        values = np.asarray(pressure_map_kPa(recording, calibration=calibration)
                            .values, float)[positions] / factor
        label = f"pressure [{unit}]"
    mask, _ = saturation_mask(recording)
    saturated = None if mask is None else np.asarray(mask.values)[positions]
    x, y = (a[positions] for a in _centre_path(recording, calibration))
    fig = Figure(figsize=map_figsize(recording), layout="compressed", dpi=dpi)
    ax = fig.subplots()
    image = draw_map(ax, recording, values[0], label=label, vmax=float(np.nanmax(values)) or 1)
    row_mm, col_mm = (float(recording.attrs[k]) for k in ("row_spacing_mm", "col_spacing_mm"))
    marks = ax.scatter([], [], **SATURATED_STYLE)
    centre, = ax.plot([], [], "P", color="white", mec="black", ms=9)
    ax.set_title(" ")
    for artist in (image, marks, centre, ax.title):
        artist.set_animated(True)  # redrawn per frame (_write_gif blits them)
    frame_numbers = recording["frame"].values if "frame" in recording.coords else positions + 1

    def update(k):
        image.set_data(values[k])
        if saturated is not None:
            r, c = np.nonzero(saturated[k])
            marks.set_offsets(np.column_stack([c * col_mm, r * row_mm]))
        centre.set_data([x[k]] if np.isfinite(x[k]) else [], [y[k]] if np.isfinite(y[k])
                        else [])
        ax.set_title(f"frame {frame_numbers[positions[k]]}, t = {t[positions[k]]:.3f} s")

    return fig, update
