"""Calibration points: one loaded frame reduced to its 256-bin histogram of raw values.

A calibration point keeps everything a static calibration needs from a frame: the counts
of every raw value 0..255 over the frame's working sensels, so that any per-sensel law
``f(raw)`` gives the frame's total force as ``histogram @ f(arange(256))`` (Zvyagin 2022,
eq. 2), at a cost independent of the number of sensels.
"""

from dataclasses import dataclass, field

import numpy as np

from tactilecal._errors import TactilecalError
from tactilecal._provenance import sensor_of
from tactilecal._result import ShortRepr

__all__ = [
    "CalibrationPoint",
    "frame_histograms",
    "points_from_frames",
    "points_to_arrays",
    "take_rows",
]

N_LEVELS = 256
SATURATION_RAW = 255


@dataclass(repr=False)
class CalibrationPoint(ShortRepr):
    """One calibration frame: the histogram of its raw values and the applied load.

    Attributes
    ----------
    histogram : numpy.ndarray
        int64[256], counts of raw values 0..255 over the frame's working, non-NaN sensels.
    load_N : float
        Applied load in newtons.
    raw_sum : float
        Sum of the raw values (``R_T`` of Zvyagin 2022, eq. 4).
    loaded_cells : int
        Number of sensels with raw > 0 (``C_T``).
    saturated_cells : int
        Number of sensels with raw == 255.
    source : str
        File (or description) the frame came from.
    frame : int
        The file's frame number.
    label : str
        Free label from the manifest.
    sensel_area_mm2 : float
        Area of one sensel (NaN when unknown).
    working_cells : int
        Number of working sensels of the frame (histogram total).
    total_cells : int
        Number of sensels of the sensor shape (working + masked non-working).
    note : str
        How the frame was chosen (e.g. the plateau detection's report).
    sensor : dict
        ``sensor_type`` and ``sensor_serial`` of the recording (empty when not read from
        a file); they go into the calibration's provenance.
    manifest : str
        The manifest the point was read from (``source`` is relative to its folder), or
        ``""``; with ``source`` it goes into the calibration's provenance.
    readings : numpy.ndarray or None
        The frame itself, ``(rows, cols)`` (NaN outside the sensor and at masked sensels):
        where each reading lies, which a gain map learned with the law needs
        (``calibrate(..., gains="learn")``); None for points known only by their histogram.

    Examples
    --------
    >>> from tactilecal.calibration import points_from_frames
    >>> raw = np.zeros((1, 3, 3)); raw[0, 1] = [10, 30, 255]
    >>> point = points_from_frames(raw, [12.5], source="a.csv")[0]
    >>> point.load_N, point.raw_sum, point.loaded_cells, point.saturated_cells
    (12.5, 295.0, 3, 1)
    >>> int(point.histogram.sum()), int(point.histogram[255]), round(point.mean_raw, 2)
    (9, 1, 98.33)
    """

    histogram: np.ndarray
    load_N: float
    raw_sum: float
    loaded_cells: int
    saturated_cells: int
    source: str = ""
    frame: int = 0
    label: str = ""
    sensel_area_mm2: float = float("nan")
    working_cells: int = 0
    total_cells: int = 0
    note: str = field(default="")
    sensor: dict = field(default_factory=dict)
    manifest: str = ""
    readings: np.ndarray | None = field(default=None, repr=False)

    def _repr_fields(self):
        return [("load_N", self.load_N), ("raw_sum", self.raw_sum),
                ("loaded_cells", self.loaded_cells), ("saturated_cells", self.saturated_cells),
                ("source", self.source), ("frame", self.frame), ("label", self.label)]

    @property
    def mean_raw(self):
        """Mean raw reading of the loaded sensels (I-Scan's x), NaN for an empty frame."""
        return self.raw_sum / self.loaded_cells if self.loaded_cells else float("nan")


def frame_histograms(raw, *, chunk_frames=64, out=None, prepare=None, mask=None):
    """Count raw values 0..255 per frame, ignoring NaN sensels.

    Large inputs are counted in one pass by a compiled kernel, small ones with NumPy
    (:mod:`tactilecal.calibration._histogram`, which says where the line is and why;
    ``benchmarks/bench_movie.py`` measures both against one pass over the same array).

    Parameters
    ----------
    raw : array_like, shape (n_frames, rows, cols)
        Raw readings of any real dtype (floats are rounded to the nearest integer, half to
        even as :func:`numpy.rint`; NaN are skipped). uint8 is counted fastest.
    chunk_frames : int
        Frames passed to ``prepare`` at a time (and copied at a time when ``raw`` is not
        C-contiguous), so that the work stays in cache.
    out : numpy.ndarray, optional
        (n_frames, 256) array to fill (e.g. float64 for fitting); default a new int64 array.
    prepare : callable, optional
        Applied to each chunk of frames (m, rows, cols) before counting (equilibration
        gains), so a long movie is never copied whole.
    mask : array_like of bool, shape (rows, cols), optional
        True for sensels not to count (non-working); their readings are not checked.

    Returns
    -------
    numpy.ndarray
        ``out``, by default int64 (n_frames, 256).

    Raises
    ------
    ValueError
        If a counted value (rounded) lies outside 0..255, or the mask does not have the
        frames' shape.
    TypeError
        If the readings are not real numbers.

    Examples
    --------
    >>> frame_histograms(np.array([[[0, 3], [3, 255]]]))[0, [0, 3, 255]]
    array([1, 2, 1])
    """
    return _frame_histograms(raw, chunk_frames=chunk_frames, out=out, prepare=prepare,
                             mask=mask)


def _frame_histograms(raw, *, chunk_frames=64, out=None, prepare=None, mask=None,
                      compiled=None):
    """:func:`frame_histograms`; ``compiled`` (default: by size) chooses the counting path.

    A caller counting a long movie chunk by chunk passes ``compiled`` for the whole movie.
    """
    from tactilecal.calibration._histogram import COMPILED_MIN_VALUES, count_into

    raw = np.asarray(raw)
    if raw.ndim == 2:
        raw = raw[None]
    if raw.ndim != 3:
        raise TactilecalError(f"raw frames have {raw.ndim} dimensions; expected 3 (frame, row, "
                              f"col)")
    compiled = raw.size >= COMPILED_MIN_VALUES if compiled is None else compiled
    n = raw.shape[0]
    skip = (np.zeros(raw.shape[1:], bool) if mask is None
            else _checked_mask(mask, raw.shape[1:])).ravel()
    out = np.empty((n, N_LEVELS), dtype=np.int64) if out is None else out
    whole = prepare is None and raw.flags.c_contiguous
    step = max(n, 1) if whole else max(int(chunk_frames), 1)
    for start in range(0, n, step):
        block = raw[start:start + step]
        m = len(block)
        if prepare is not None:
            block = np.asarray(prepare(block), dtype=float)
        count_into(block.reshape(m, -1), skip, out[start:start + m], compiled=compiled)
    return out


def points_from_frames(raw, load_N, *, source="", labels=None, frames=None, mask=None,
                       sensel_area_mm2=None):
    """Make calibration points from raw frames and their applied loads.

    Parameters
    ----------
    raw : xarray.DataArray or array_like, shape (n, rows, cols)
        Raw frames (data model of ``docs/data-model.md``); NaN sensels are not counted.
    load_N : array_like, shape (n,)
        Applied load of each frame in newtons.
    source : str
        Source file recorded in each point.
    labels : sequence of str, optional
        One label per frame.
    frames : sequence of int, optional
        Frame numbers (default: the DataArray's ``frame`` coordinate, else 1..n).
    mask : array_like of bool, shape (rows, cols), optional
        True for non-working sensels to leave out (see :func:`find_dead_sensels`).
    sensel_area_mm2 : float, optional
        Sensel area (default: the DataArray's ``sensel_area_mm2`` attribute, else NaN).

    Returns
    -------
    list of CalibrationPoint

    Raises
    ------
    ValueError
        If the number of loads or labels differs from the number of frames, or the mask
        shape differs from the frame shape.

    Examples
    --------
    >>> raw = np.zeros((1, 4, 4)); raw[0, 1:3, 1:3] = 10
    >>> p = points_from_frames(raw, [5.0])[0]
    >>> p.raw_sum, p.loaded_cells, p.saturated_cells, int(p.histogram[10])
    (40.0, 4, 0, 4)
    """
    attrs = getattr(raw, "attrs", {})
    if frames is None and hasattr(raw, "coords") and "frame" in raw.coords:
        frames = np.asarray(raw["frame"].values)
    if sensel_area_mm2 is None:
        sensel_area_mm2 = float(attrs.get("sensel_area_mm2", float("nan")))
    source = source or str(attrs.get("source", ""))
    values = np.asarray(getattr(raw, "values", raw))  # any real dtype: not copied
    if values.ndim == 2:
        values = values[None]
    n = values.shape[0]
    load_N = np.atleast_1d(np.asarray(load_N, dtype=float))
    _check_length("load_N", len(load_N), n)
    labels = [""] * n if labels is None else list(labels)
    _check_length("labels", len(labels), n)
    frames = np.arange(1, n + 1) if frames is None else np.asarray(frames)
    _check_length("frames", len(frames), n)
    total_cells = int(np.isfinite(values[0]).sum())
    hist = frame_histograms(values, mask=mask)
    readings = values.astype(float) if mask is None else \
        np.where(_checked_mask(mask, values.shape[1:]), np.nan, values.astype(float))
    return _points_from_histograms(hist, load_N, source=source, labels=labels, frames=frames,
                                   sensel_area_mm2=sensel_area_mm2, total_cells=total_cells,
                                   sensor=sensor_of(attrs) if attrs else None,
                                   readings=readings)


def _check_length(name, found, expected):
    if found != expected:
        raise TactilecalError(f"{name} has {found} entries; expected {expected} (one per frame)")


def _checked_mask(mask, shape):
    mask = np.asarray(mask, dtype=bool)
    if mask.shape != tuple(shape):
        raise TactilecalError(f"mask has shape {mask.shape}; expected {tuple(shape)} "
                              "(rows, cols of the frames)")
    return mask


def _points_from_histograms(hist, load_N, *, source, labels, frames, sensel_area_mm2,
                            total_cells, notes=None, sensor=None, manifest="", readings=None):
    levels = np.arange(N_LEVELS)
    raw_sum = hist @ levels
    loaded = hist[:, 1:].sum(axis=1)
    working = hist.sum(axis=1)
    notes = [""] * len(hist) if notes is None else notes
    return [
        CalibrationPoint(histogram=hist[i], load_N=float(load_N[i]), raw_sum=float(raw_sum[i]),
                         loaded_cells=int(loaded[i]), saturated_cells=int(hist[i, -1]),
                         source=str(source), frame=int(frames[i]), label=str(labels[i]),
                         sensel_area_mm2=float(sensel_area_mm2), working_cells=int(working[i]),
                         total_cells=int(total_cells), note=notes[i], sensor=dict(sensor or {}),
                         manifest=str(manifest),
                         readings=None if readings is None else readings[i])
        for i in range(len(hist))
    ]


def take_rows(array, mask):
    """Return ``array[mask]``, as a view (no copy) when the selected rows are contiguous.

    Movie calibration selects most of 100,000 histogram rows; copying them costs more than
    the fit.

    Examples
    --------
    >>> a = np.arange(10).reshape(5, 2)
    >>> np.shares_memory(take_rows(a, np.array([0, 1, 1, 1, 0], bool)), a)
    True
    """
    idx = np.flatnonzero(mask)
    if len(idx) and idx[-1] - idx[0] + 1 == len(idx):
        return array[idx[0]:idx[-1] + 1]
    return array[mask]


def keep_rows_in_place(rows, keep, *, piece_rows=4096):
    """Move the rows selected by ``keep`` to the top of ``rows``, in order; return that view.

    ``rows[keep]`` would allocate and fill a new array: for the (100,000, 256) float64
    histograms of a movie that is 205 MB of fresh pages. Here each run of kept rows is
    moved up by at most ``piece_rows`` rows at a time. The rows below the returned view
    are left in an unspecified state.

    Examples
    --------
    >>> a = np.arange(8.0).reshape(4, 2)
    >>> keep_rows_in_place(a, np.array([False, True, False, True])).tolist()
    [[2.0, 3.0], [6.0, 7.0]]
    """
    idx = np.flatnonzero(keep)
    if len(keep) != len(rows):
        raise TactilecalError(f"keep has {len(keep)} flags for {len(rows)} rows; expected one "
                              "per row")
    if not len(idx):
        return rows[:0]
    breaks = np.flatnonzero(np.diff(idx) != 1) + 1
    top = 0
    for first, last in zip(idx[np.r_[0, breaks]], idx[np.r_[breaks - 1, -1]], strict=True):
        if first != top:
            for a in range(first, last + 1, piece_rows):
                b = min(a + piece_rows, last + 1)
                rows[top + a - first:top + b - first] = rows[a:b]
        top += last + 1 - first
    return rows[:top]


def points_to_arrays(points):
    """Stack calibration points into arrays for fitting.

    Parameters
    ----------
    points : sequence of CalibrationPoint

    Returns
    -------
    histograms : numpy.ndarray
        int64 (n, 256).
    load_N : numpy.ndarray
        float64 (n,).

    Raises
    ------
    ValueError
        If ``points`` is empty.

    Examples
    --------
    >>> h, f = points_to_arrays(points_from_frames(np.full((2, 2, 2), 9.0), [1.0, 2.0]))
    >>> h.shape, f.tolist()
    ((2, 256), [1.0, 2.0])
    """
    if len(points) == 0:
        raise TactilecalError("points is empty; expected at least one calibration point")
    hist = np.stack([np.asarray(p.histogram, dtype=np.int64) for p in points])
    load = np.array([p.load_N for p in points], dtype=float)
    return hist, load
