"""Calibration manifests (CSV, one row per point) and plateau detection for blank frames."""

from pathlib import Path

import numpy as np
import pandas as pd

from tactilecal._errors import TactilecalError
from tactilecal._progress import resolve
from tactilecal._provenance import sensor_of
from tactilecal._validate import check_number, csv_rows, parse_number, read_text
from tactilecal.calibration._points import _points_from_histograms, frame_histograms
from tactilecal.calibration._tekscan_cal import cal_points, is_tekscan_cal, refuse_recording

__all__ = ["load_points", "load_frames", "find_plateau"]

_BAR_MIN_ROWS = 50
"""Manifests shorter than this are read without calling ``progress`` (they take moments)."""


def find_plateau(total, *, window=3, rel_tol=0.02, min_level=0.5):
    """Find the steady plateau of a loading record from its per-frame total raw signal.

    Among frames whose total is at least ``min_level`` x the maximum, the centre of the
    ``window``-frame span with the smallest coefficient of variation seeds the plateau; the
    plateau is the run of consecutive frames around it whose total stays within ``rel_tol``
    of the seed span's median, and its middle frame is returned.

    Parameters
    ----------
    total : array_like, shape (n,)
        Per-frame total raw reading.
    window : int
        Frames in the rolling span.
    rel_tol : float
        Relative band around the plateau level.
    min_level : float
        Only frames above this fraction of the maximum are candidates.

    Returns
    -------
    index : int
        0-based index of the chosen frame.
    first, last : int
        0-based indices of the plateau's ends.
    cv : float
        Coefficient of variation of the total over the plateau.

    Raises
    ------
    ValueError
        If every frame is empty.

    Examples
    --------
    >>> find_plateau([0, 10, 50, 99, 100, 101, 100, 99, 60])[:3]
    (5, 3, 7)
    """
    total = pd.Series(np.asarray(total, dtype=float))
    if not (total > 0).any():
        raise TactilecalError("every frame has a total raw reading of 0; expected a loaded plateau")
    if len(total) < window:
        i = int(total.to_numpy().argmax())
        return i, i, i, 0.0
    roll = total.rolling(window, center=True)
    cv = (roll.std() / roll.mean()).where(total >= min_level * total.max())
    seed = int(np.nanargmin(cv.to_numpy()))
    half = window // 2
    level = float(total.iloc[max(seed - half, 0):seed + half + 1].median())
    inside = ((total - level).abs() <= rel_tol * level).to_numpy()
    first, last = seed, seed
    while first > 0 and inside[first - 1]:
        first -= 1
    while last < len(total) - 1 and inside[last + 1]:
        last += 1
    span = total.iloc[first:last + 1]
    return (first + last) // 2, first, last, float(span.std(ddof=0) / span.mean())


def _manifest_table(path):
    """Return the manifest's rows as dicts of text (``csv`` module, any encoding Excel writes).

    Every row must have as many values as the header: an extra comma shifts the columns.
    """
    lines = list(csv_rows(read_text(path, expected="a manifest CSV"), path))
    if not lines:
        raise TactilecalError(f"{path} is empty; expected a CSV header with file, frame and "
                              "load_N or mass_kg")
    columns = lines[0][1]
    missing = [c for c in ("file", "frame") if c not in columns]
    if missing or not ({"load_N", "mass_kg"} & set(columns)):
        raise TactilecalError(f"{path} has columns {columns}; expected file, frame and "
                              "load_N or mass_kg (optional pad_mass_g, label)")
    if len(lines) == 1:
        raise TactilecalError(f"{path} has no rows; expected one row per calibration point")
    return [(number, dict(zip(columns, cells, strict=True))) for number, cells in lines[1:]]


_MAX_LOAD_N = 1e9
"""No dead weight on a tactile sensor comes near 1e9 N (100,000 t): a larger load is a typo."""


def _number(text, column, where, **limits):
    return parse_number(text, f"{where}: {column}", **limits)


def _row_load_N(row, where):
    """Load of one manifest row: ``load_N``, else the weights of mass_kg and pad_mass_g [N]."""
    from tactilecal._units import mass_to_N

    positive = {"minimum": 0.0, "min_inclusive": False, "maximum": _MAX_LOAD_N}
    if row.get("load_N", ""):
        return _number(row["load_N"], "load_N", where, **positive)
    if row.get("mass_kg", ""):
        pad = (_number(row["pad_mass_g"], "pad_mass_g", where, minimum=0.0,
                       maximum=_MAX_LOAD_N) if row.get("pad_mass_g") else 0.0)
        mass = _number(row["mass_kg"], "mass_kg", where, minimum=0.0, maximum=_MAX_LOAD_N)
        return check_number(mass_to_N(mass, "kg") + mass_to_N(pad, "g"), f"{where}: the load in N",
                            **positive)
    raise TactilecalError(f"{where}: load_N and mass_kg are both blank; expected a load")


def _read_recording(path, where, cache):
    from tactilecal.io import open_recording

    if path not in cache:
        if not path.exists():
            raise TactilecalError(f"{where}: file {path} does not exist")
        try:
            rec = open_recording(path)
        except ValueError as exc:  # name the manifest line that points at the file
            raise TactilecalError(f"{where}: {exc}") from None
        units = rec.attrs.get("units", "raw")
        if units != "raw":
            raise TactilecalError(f"{where}: {path.name} has units {units!r}; expected raw "
                                  "readings (units raw) to calibrate")
        cache[path] = rec
    return cache[path]


def _pick_frame(rec, text, where, name):
    """Return (0-based index, note) of the manifest's frame or of the detected plateau."""
    frames = rec["frame"].values
    if text:
        number = _number(text, "frame", where, integer=True)
        hits = np.flatnonzero(frames == number)
        if not len(hits):
            raise TactilecalError(f"{where}: frame {text} is not in {name} (frames "
                                  f"{frames[0]}..{frames[-1]}); expected one of its frame numbers")
        return int(hits[0]), ""
    total = np.nansum(rec.values.reshape(len(frames), -1), axis=1)
    try:
        i, first, last, cv = find_plateau(total)
    except ValueError as exc:  # an empty recording: name the manifest line and its file
        raise TactilecalError(f"{where}: {name}: {exc}") from None
    note = (f"frame blank: chose frame {frames[i]}, middle of the plateau frames "
            f"{frames[first]}..{frames[last]} (raw sum {total[i]:.0f}, variation {cv:.2%})")
    return i, note


def _manifest_frames(manifest_path, equilibration, progress):
    """Yield (row, frame (1, rows, cols), frame number, note, attrs, load_N) per manifest row.

    ``attrs`` are the recording's attributes (sensel area, sensor type and serial).

    ``progress`` (the protocol of :mod:`tactilecal._progress`) wraps the rows of manifests of
    50 rows or more.
    """
    path = Path(manifest_path)
    rows = _manifest_table(path)
    cache = {}
    if len(rows) >= _BAR_MIN_ROWS:
        rows = progress(rows, total=len(rows), desc=f"reading {path.name}")
    for line, row in rows:
        where = f"{path.name} line {line}"
        load = _row_load_N(row, where)
        rec = _read_recording(path.parent / row["file"], where, cache)
        i, note = _pick_frame(rec, row["frame"], where, row["file"])
        frame = rec.values[i:i + 1]
        if equilibration is not None:
            frame = equilibration.apply(frame)
        yield row, frame, int(rec["frame"].values[i]), note, rec.attrs, load


def load_frames(manifest_path, *, equilibration=None, progress=None):
    """Return the manifest's chosen frames stacked (n, rows, cols), e.g. to find dead sensels.

    ``equilibration`` and ``progress`` are as in :func:`load_points`.

    Raises
    ------
    ValueError
        As :func:`load_points`, and if the files' frame shapes differ.
    """
    if is_tekscan_cal(manifest_path):
        raise TactilecalError(f"{manifest_path} is a Tekscan .cal file: it keeps histograms, "
                              "not frames; expected a manifest CSV to read frames from")
    progress = resolve(progress)
    frames = [f[1][0] for f in _manifest_frames(manifest_path, equilibration, progress)]
    shapes = sorted({f.shape for f in frames})
    if len(shapes) > 1:
        raise TactilecalError(f"{manifest_path}: files have frame shapes {shapes}; expected one "
                              "sensor model")
    return np.stack(frames)


def load_points(manifest_path, *, mask=None, equilibration=None, progress=None):
    """Read a calibration manifest and return its calibration points.

    The manifest is a CSV with one row per point: ``file`` (path relative to the manifest),
    ``frame`` (the file's frame number; blank = the steady plateau, found by
    :func:`find_plateau` and reported in the point's ``note``), ``load_N`` or ``mass_kg``
    with optional ``pad_mass_g`` (g = 9.80665 m/s2), optional ``label``.

    A Tekscan calibration file (``.cal``) is read instead by its own reader
    (:mod:`tactilecal.calibration._tekscan_cal`): one point per ``CAL_*_n`` group, its
    histogram as the file stores it.

    Parameters
    ----------
    manifest_path : str or os.PathLike
        The manifest CSV, or a Tekscan ``.cal`` file.
    mask : array_like of bool, optional
        Non-working sensels to leave out (see :func:`find_dead_sensels`).
    equilibration : Equilibration, optional
        Per-sensel gains applied to every frame first (see :func:`equilibrate`).
    progress : callable, optional
        ``progress(iterable, total=, desc=)`` wrapping the rows of manifests of 50 rows or
        more, e.g. a progress bar (see :mod:`tactilecal._progress`); None: no bar.

    Returns
    -------
    list of CalibrationPoint

    Raises
    ------
    ValueError
        Missing columns, a blank or non-numeric load, a missing file, a frame not in its
        file, a file that is not raw; messages name the manifest line.

    Examples
    --------
    >>> import tempfile
    >>> from tactilecal.simulate import deadweight_session, make_sensor
    >>> session = deadweight_session(make_sensor("5051"), n_patches=6, seed=3)
    >>> points = load_points(session.write(tempfile.mkdtemp()))  # its manifest.csv
    >>> len(points), bool(np.allclose([p.load_N for p in points], session.load_N))
    (6, True)
    >>> points[0].source, points[0].frame  # the manifest left this frame blank
    ('2kg-1cm-001.csv', 8)
    >>> print(points[0].note)  # doctest: +ELLIPSIS
    frame blank: chose frame 8, middle of the plateau frames 5..12 ...
    """
    if is_tekscan_cal(manifest_path):
        return cal_points(manifest_path, mask=mask, equilibration=equilibration)
    refuse_recording(manifest_path)
    progress = resolve(progress)
    points = []
    for row, frame, number, note, attrs, load in _manifest_frames(manifest_path, equilibration,
                                                                   progress):
        total = int(np.isfinite(frame).sum())
        if mask is not None:
            frame = np.where(_frame_mask(mask, frame.shape[1:], row["file"])[None], np.nan,
                             frame)
        points.extend(_points_from_histograms(
            frame_histograms(frame), [load], source=row["file"], labels=[row.get("label", "")],
            frames=[number], sensel_area_mm2=float(attrs.get("sensel_area_mm2", np.nan)),
            total_cells=total, notes=[note], sensor=sensor_of(attrs),
            manifest=manifest_path, readings=frame.astype(float)))
    return points


def _frame_mask(mask, shape, name):
    """Return ``mask`` as a boolean (rows, cols) array of the frames' shape."""
    mask = np.asarray(mask, dtype=bool)
    if mask.shape != tuple(shape):
        raise TactilecalError(f"mask has shape {mask.shape}; expected {tuple(shape)}, the frames "
                              f"of {name}")
    return mask
