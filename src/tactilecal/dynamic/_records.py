"""Checks shared by the dynamic-calibration functions: 1-D records with a time axis.

A *record* is a 1-D :class:`xarray.DataArray` whose only dimension carries a ``time``
coordinate in seconds: a load-cell series from ``read_timeseries`` (dim ``time``) or a
summed/averaged sensor recording (dim ``frame`` with a ``time`` coordinate).
"""

import numpy as np

from tactilecal._errors import TactilecalError

#: Largest deviation of one time step from the median step, as a fraction of it, for the
#: FFT-based steps (transfer function, filtering), which treat samples as equally spaced.
MAX_STEP_JITTER = 0.05
#: The same for alignment and resampling, which first place a jittered record on a uniform
#: grid: real I-Scan movies carry frame times with 0.10 s and 0.11 s steps.
MAX_ALIGN_JITTER = 0.5
#: Largest distance of a time stamp from the uniform grid at the record's mean rate, as a
#: fraction of a step, for which the record counts as uniform although its steps vary:
#: I-Scan 6.10I prints frame times to 0.01 s, so a 0.10097 s step reads as 0.10 or 0.11 s
#: (the real export in shared/realdata: 0.065 of a step).
MAX_GRID_JITTER = 0.1


def label(record, name):
    """Return how error messages name ``record``: its ``source`` file, else ``name``."""
    attrs = getattr(record, "attrs", {}) or {}
    return str(attrs.get("source", name))


def time_and_values(record, name):
    """Return ``(time_s, values)`` of a 1-D record after checking it.

    Parameters
    ----------
    record : xarray.DataArray
        1-D, with a ``time`` coordinate (s) along its only dimension.
    name : str
        Parameter name used in error messages when the record has no ``source``.

    Returns
    -------
    time_s, values : numpy.ndarray
        float64 arrays of equal length.

    Raises
    ------
    ValueError
        Not 1-D, no ``time`` coordinate, fewer than 4 samples, NaN values or time stamps
        that do not increase.
    """
    where = label(record, name)
    if getattr(record, "ndim", None) != 1:
        raise TactilecalError(f"{where}: expected a 1-D record (one value per time step); "
                              f"found dims {getattr(record, 'dims', type(record).__name__)}")
    if "time" not in record.coords:
        raise TactilecalError(f"{where}: no 'time' coordinate (s); expected one along "
                              f"{record.dims[0]!r}")
    time_s = np.asarray(record["time"].values, dtype=float)
    values = np.asarray(record.values, dtype=float)
    if values.size < 4:
        raise TactilecalError(f"{where}: {values.size} samples; expected at least 4")
    bad = np.flatnonzero(~np.isfinite(values))
    if bad.size:
        raise TactilecalError(f"{where}: {bad.size} NaN/inf values (gap starting at t = "
                              f"{time_s[bad[0]]:.6g} s); expected a complete record "
                              "(fill or cut the gap first)")
    if not np.all(np.diff(time_s) > 0):
        raise TactilecalError(f"{where}: time stamps do not increase strictly; expected a "
                              "time column in seconds, increasing")
    return time_s, values


def sampling_rate_hz(time_s, where, *, max_jitter=MAX_STEP_JITTER):
    """Infer the sampling rate of regularly spaced time stamps.

    Parameters
    ----------
    time_s : array_like
        Increasing time stamps in s.
    where : str
        File or parameter named in the error message.
    max_jitter : float
        Largest allowed ``|step - median step| / median step``.

    Returns
    -------
    float
        ``(n - 1) / (t[-1] - t[0])`` in Hz.

    Raises
    ------
    ValueError
        When a step differs from the median step by more than ``max_jitter`` of it, unless
        every stamp lies within ``MAX_GRID_JITTER`` of a step from the uniform grid at the
        mean rate (stamps rounded on export, as I-Scan's 0.10 / 0.11 s steps).

    Examples
    --------
    >>> sampling_rate_hz(np.arange(5) / 4000.0, "x")
    4000.0
    """
    time_s = np.asarray(time_s, dtype=float)
    if time_s.size < 2:
        raise TactilecalError(f"{where}: {time_s.size} time stamps; cannot infer a sampling rate")
    steps = np.diff(time_s)
    median = np.median(steps)
    rounded = median > 0 and time_jitter_s(time_s) <= MAX_GRID_JITTER * median
    if median <= 0 or (np.max(np.abs(steps - median)) > max_jitter * median and not rounded):
        raise TactilecalError(
            f"{where}: irregular time column, steps range from {steps.min():.6g} to "
            f"{steps.max():.6g} s (median {median:.6g} s); cannot infer a sampling rate, "
            "expected a constant sampling interval")
    return float((time_s.size - 1) / (time_s[-1] - time_s[0]))


def time_jitter_s(time_s):
    """Largest distance in s of a time stamp from the uniform grid at the mean rate.

    Examples
    --------
    >>> round(time_jitter_s(np.array([0.0, 0.1, 0.21, 0.3])), 3)
    0.01
    """
    time_s = np.asarray(time_s, dtype=float)
    if time_s.size < 3:
        return 0.0
    grid = np.linspace(time_s[0], time_s[-1], time_s.size)
    return float(np.max(np.abs(time_s - grid)))


def on_uniform_grid(time_s, values, where):
    """Return ``(time_s, values, fs_hz)`` on equally spaced stamps.

    Records whose steps stay within ``MAX_STEP_JITTER`` are returned as they are; records
    with a jitter up to ``MAX_ALIGN_JITTER`` (e.g. I-Scan frame times 0.10/0.11 s) are
    linearly interpolated onto ``t0 + k / fs`` at their mean rate.

    Examples
    --------
    >>> t, v, fs = on_uniform_grid(np.array([0, 0.1, 0.21, 0.3]), np.arange(4.0), "x")
    >>> fs, t.tolist()
    (10.0, [0.0, 0.1, 0.2, 0.3])
    """
    fs_hz = sampling_rate_hz(time_s, where, max_jitter=MAX_ALIGN_JITTER)
    steps = np.diff(time_s)
    if np.max(np.abs(steps - np.median(steps))) <= MAX_STEP_JITTER * np.median(steps):
        return time_s, values, fs_hz
    grid = time_s[0] + np.arange(time_s.size) / fs_hz
    return grid, np.interp(grid, time_s, values), fs_hz
