"""Alignment and resampling of a sensor record and its reference (Gillis 2013, 4.3.2.1).

Convention used everywhere in :mod:`tactilecal.dynamic`: ``lag_s`` is the shift to *add* to
the reference's time stamps to put them on the sensor's clock. It is positive when the
reference record starts later than the sensor record (the thesis' case: the Tekscan
recording starts before the loading machine program).
"""

import warnings
from fractions import Fraction

import numpy as np
import xarray as xr
from scipy import interpolate, signal

from tactilecal._errors import TactilecalError
from tactilecal.dynamic._records import (
    MAX_ALIGN_JITTER,
    label,
    on_uniform_grid,
    sampling_rate_hz,
    time_and_values,
)

__all__ = ["estimate_lag", "resample_to", "align"]

#: Largest numerator/denominator of the polyphase up/down ratio (5000 -> 4000 Hz is 4/5).
MAX_RATIO_TERMS = 1000
#: Anti-alias FIR of the rate change: Kaiser window, beta 10 (stop band below -100 dB, where
#: scipy's default beta 5 leaves images at about -55 dB: 0.03 N on a 20 N sine), with
#: ``TAPS_PER_PHASE`` taps per polyphase branch (twice scipy's default length).
KAISER_BETA = 10.0
TAPS_PER_PHASE = 40
#: Smallest correlation coefficient of the overlapping records at the lag found by
#: ``"xcorr"``; below it the records are taken not to show the same loading.
MIN_CORRELATION = 0.5
#: Smallest overlap (fraction of the shorter record) of a lag ``"xcorr"`` considers.
MIN_OVERLAP = 0.5
#: Default half width, in sensor samples, of the window searched around ``near_lag_s``.
NEAR_SAMPLES = 16
#: Most lags of that window computed as dot products; a wider one is cut from the FFT
#: correlation of every lag (one lag of a 100,000-sample record costs about 1/200 of it,
#: so 641 lags as dot products cost more than the FFT correlation).
NEAR_MAX_DOTS = 128


def _polyphase(values, fs_in_hz, fs_out_hz):
    """Change the rate of ``values`` with :func:`scipy.signal.resample_poly`.

    The anti-alias filter is a Kaiser-window FIR (:func:`scipy.signal.firwin`, beta
    ``KAISER_BETA``). The record is detrended by the line through its first and last
    samples before filtering (``padtype="line"``) and extended by an odd reflection
    about each end sample (:func:`numpy.pad`, value and slope continuous) over the filter's
    half length; the extension is cut off again. Zero padding would cause edge
    transients on a record sitting on a large offset (120 lb in the thesis sweep) or cut
    mid-cycle.

    Returns
    -------
    values_out : numpy.ndarray
    fs_hz : float
        The rate actually obtained, ``fs_in_hz * up / down``.
    """
    ratio = Fraction(fs_out_hz / fs_in_hz).limit_denominator(MAX_RATIO_TERMS)
    up, down = ratio.numerator, ratio.denominator
    if up == down:
        return np.asarray(values, dtype=float), float(fs_in_hz)
    max_rate = max(up, down)
    taps = signal.firwin(TAPS_PER_PHASE * max_rate + 1, 1.0 / max_rate,
                         window=("kaiser", KAISER_BETA))
    values = np.asarray(values, dtype=float)
    pad = min(down * -(-taps.size // (2 * up * down)), values.size - 1)
    pad -= pad % down
    padded = np.pad(values, pad, mode="reflect", reflect_type="odd")
    out = signal.resample_poly(padded, up, down, window=taps, padtype="line")
    first = pad * up // down
    n_out = -(-values.size * up // down)
    return out[first:first + n_out], float(fs_in_hz) * up / down


def _parabolic_offset(y, i):
    """Sub-sample offset of the extremum at ``y[i]`` from the parabola through 3 points."""
    if i <= 0 or i >= y.size - 1:
        return 0.0
    left, mid, right = y[i - 1], y[i], y[i + 1]
    curvature = left - 2.0 * mid + right
    return 0.0 if curvature == 0 else float(0.5 * (left - right) / curvature)


def _normalised_xcorr(x_sens, x_ref, min_overlap, lag=None):
    """Pearson correlation of the overlapping parts of two records at every lag.

    The cross products come from one FFT correlation (:func:`scipy.signal.correlate`); the
    sums and sums of squares over each lag's overlap from cumulative sums
    (:func:`_overlap_sums`), so a lag that overlaps only part of the records is judged on
    that part alone: the plain correlation of de-meaned finite records is tilted toward
    the lags that overlap their flat (offset) stretches longest, which moved a
    ramp-and-hold alignment by several frames. Lags in the order of
    :func:`scipy.signal.correlation_lags` (``mode="full"``).

    ``lag`` (optional, int array): only these lags (where ``x_ref[0]`` falls on
    ``x_sens``), their cross products as one dot product each instead of the FFT
    correlation; equal to the full result at those lags to round-off.
    """
    s = x_sens - x_sens.mean()
    r = x_ref - x_ref.mean()
    if lag is None:
        lag = np.arange(-(r.size - 1), s.size)  # where r[0] falls on s
        cross = signal.correlate(s, r, mode="full", method="fft")
    else:
        cross = np.array([_overlap_dot(s, r, int(k)) for k in lag])
    sum_s, sum_ss, n = _overlap_sums(s, lag, r.size)
    sum_r, sum_rr, _ = _overlap_sums(r, -lag, s.size)
    n = np.maximum(n, 1)
    var_s = sum_ss - sum_s**2 / n
    var_r = sum_rr - sum_r**2 / n
    cov = cross - sum_s * sum_r / n
    tiny = 1e-12 * max(float(np.sum(s * s)), float(np.sum(r * r)), 1e-300)  # no BLAS call
    ok = (n >= min_overlap * min(s.size, r.size)) & (var_s > tiny) & (var_r > tiny)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(ok, cov / np.sqrt(var_s * var_r), -np.inf)


def _overlap_dot(s, r, lag):
    """``sum_j s[lag + j] r[j]`` over the ``j`` where both exist.

    An elementwise product and a sum, not a BLAS dot: each threaded BLAS call waits for
    its threads on busy cores.
    """
    lo, hi = max(lag, 0), min(lag + r.size, s.size)
    return float(np.sum(s[lo:hi] * r[lo - lag:hi - lag])) if hi > lo else 0.0


def _overlap_sums(x, start, other_size):
    """Return sums of ``x`` and ``x**2`` over ``x[start:start + other_size]`` and counts.

    The slice is clipped to ``x``. One cumulative sum each replaces an FFT correlation of
    ``x`` with a window of ones.
    """
    lo = np.clip(start, 0, x.size)
    hi = np.clip(start + other_size, 0, x.size)
    c1 = np.concatenate([[0.0], np.cumsum(x)])
    c2 = np.concatenate([[0.0], np.cumsum(x * x)])
    return c1[hi] - c1[lo], c2[hi] - c2[lo], hi - lo


def _lag_xcorr(t_sens, x_sens, fs_sens, t_ref, x_ref, fs_ref, max_lag_s, where, near=None):
    """Lag from the peak of the normalised cross-correlation of the de-meaned records.

    ``near`` (optional): ``(lag_s, half_width)``, a lag known to within about
    ``half_width`` samples (e.g. from the same records at a lower rate): the peak is looked
    for among the lags within ``half_width`` samples of it (computed alone, as dot
    products, up to ``NEAR_MAX_DOTS`` lags: :func:`_normalised_xcorr`), and among all lags
    if it lies at the window's edge or below ``MIN_CORRELATION``.
    """
    x_ref, _ = _polyphase(x_ref, fs_ref, fs_sens)
    lags = signal.correlation_lags(x_sens.size, x_ref.size, mode="full")
    lag_s = lags / fs_sens + (t_sens[0] - t_ref[0])
    corr = None  # over every lag, once computed
    if near is not None:
        centre = int(np.argmin(np.abs(lag_s - near[0])))
        part = slice(max(centre - int(near[1]), 0), centre + int(near[1]) + 1)
        if 2 * int(near[1]) + 1 <= NEAR_MAX_DOTS:
            near_corr = _bounded(_normalised_xcorr(x_sens, x_ref, MIN_OVERLAP, lag=lags[part]),
                                 lag_s[part], max_lag_s)
        else:  # cut from the correlation of every lag, kept if the window does not hold
            corr = _bounded(_normalised_xcorr(x_sens, x_ref, MIN_OVERLAP), lag_s, max_lag_s)
            near_corr = corr[part]
        i = int(np.argmax(near_corr))
        if 0 < i < near_corr.size - 1 and near_corr[i] >= MIN_CORRELATION:
            corr, lag_s = near_corr, lag_s[part]
    full = corr is None or corr.size == lag_s.size
    if corr is None:  # no window, or its peak may lie outside it: every lag
        corr = _bounded(_normalised_xcorr(x_sens, x_ref, MIN_OVERLAP), lag_s, max_lag_s)
    i = int(np.argmax(corr))
    if full and corr[i] >= MIN_CORRELATION:  # a lag near a known one is not ambiguous
        overlap = np.minimum(lags + x_ref.size, x_sens.size) - np.maximum(lags, 0)
        i = _unambiguous(corr, lag_s, i, overlap, where)
    if not np.isfinite(corr[i]):
        raise TactilecalError(f"{where}: no lag with an overlap of at least {MIN_OVERLAP} of the "
                              f"shorter record (max_lag_s={max_lag_s}); expected records of the "
                              "same loading that overlap")
    if not corr[i] >= MIN_CORRELATION:
        raise TactilecalError(f"{where}: the records correlate at best {corr[i]:.3g} (at lag "
                              f"{lag_s[i]:.6g} s): they do not show the same loading, or the "
                              "sensor's response distorts it too much to align them (a lightly "
                              "damped resonance); expected records of the same loading "
                              f"(correlation >= {MIN_CORRELATION})")
    window = corr[max(i - 1, 0):i + 2]
    offset = _parabolic_offset(window, 1) if window.size == 3 and np.all(
        np.isfinite(window)) else 0.0
    return float(lag_s[i] + offset / fs_sens)


AMBIGUITY = 0.01
"""Correlation peaks within this of the highest are equally likely lags (a periodic load).

A load repeated cycle after cycle correlates within a few thousandths as well a whole cycle
away (the simulated gait of the tests: 0.995 at every cycle); the side lobes of a sine sweep
or of a blind test's sine sets stay 0.02-0.04 below their main peak, which is right."""


def _unambiguous(corr, lag_s, i, overlap, where):
    """Among near-equal correlation peaks, the one with the most overlap; warn if several.

    A periodic loading (a gait cycle, a shaking table) correlates almost as well a whole
    period away; the highest peak is then a matter of noise, and a lag whole periods off
    leaves most frames outside the load record. Peaks within :data:`AMBIGUITY` of the
    highest (and standing out from their surroundings) are candidates; the one whose lag
    leaves the most overlap between the records (then the nearest to zero) is taken.
    """
    finite = np.where(np.isfinite(corr), corr, -1.0)
    peaks, _ = signal.find_peaks(finite, height=corr[i] - AMBIGUITY, prominence=2 * AMBIGUITY)
    peaks = np.union1d(peaks, [i])
    if peaks.size < 2:
        return i
    best = int(peaks[np.lexsort((np.abs(lag_s[peaks]), -overlap[peaks]))[0]])
    shown = ", ".join(f"{lag_s[k]:.4g} s ({corr[k]:.3f})" for k in peaks[:6])
    warnings.warn(f"{where}: the lag is ambiguous: {peaks.size} near-equal correlation peaks "
                  f"at {shown}{' ...' if peaks.size > 6 else ''}, "
                  f"{np.median(np.diff(lag_s[peaks])):.4g} s apart (a periodic loading); took "
                  f"{lag_s[best]:.4g} s, which overlaps the records most; give lag_s (or a "
                  "max_lag_s) if it is another", UserWarning, stacklevel=4)
    return best


def _bounded(corr, lag_s, max_lag_s):
    """``corr`` with the lags beyond ``max_lag_s`` (if given) set to -inf."""
    return corr if max_lag_s is None else np.where(np.abs(lag_s) <= max_lag_s, corr, -np.inf)


def _first_peak_time(time_s, values, prominence, where):
    """Time of the first peak whose prominence is at least ``prominence`` x the range."""
    span = float(values.max() - values.min())
    peaks, _ = signal.find_peaks(values, prominence=prominence * span)
    if span == 0 or peaks.size == 0:
        raise TactilecalError(f"{where}: no peak with prominence >= {prominence} x the record's "
                              f"range ({span:.6g}); expected a loading with a clear first peak "
                              "(lower `prominence` or use method='xcorr')")
    i = int(peaks[0])
    step = (time_s[-1] - time_s[0]) / (time_s.size - 1)
    return float(time_s[i] + _parabolic_offset(values, i) * step)


def estimate_lag(sensor, reference, *, method="xcorr", max_lag_s=None, prominence=0.2,
                 near_lag_s=None, near_width_s=None):
    """Estimate the time shift between a sensor record and its reference.

    Implements the alignment step of Gillis (2013), section 4.3.2.1.

    Parameters
    ----------
    sensor, reference : xarray.DataArray
        1-D records with a ``time`` coordinate in s (any units, any sampling rates, e.g.
        a 4000 Hz sensor force and a 5000 Hz load cell, or a 100 Hz summed raw signal and
        a 500 Hz load cell). Time stamps jittering up to 50 % of the step (real I-Scan
        movies: 0.10 and 0.11 s) are linearly interpolated onto a uniform grid first.
    method : {"xcorr", "first-peak"}
        ``"xcorr"`` (default): the reference is brought to the sensor's rate
        (polyphase), and the lag maximises the Pearson correlation of the overlapping
        parts (normalised cross-correlation from FFT correlations,
        :func:`scipy.signal.correlate`; lags overlapping less than ``MIN_OVERLAP`` = half
        the shorter record are not considered), refined to a fraction of a sample by a
        parabola through the three highest points.
        ``"first-peak"``: the thesis' method; the first peak of each record whose
        prominence (:func:`scipy.signal.find_peaks`) is at least ``prominence`` times the
        record's range is set to equal times (parabolic sub-sample refinement). It is
        only as precise as the first peak is sharp.
    max_lag_s : float, optional
        ``"xcorr"`` only: search lags with ``|lag_s| <= max_lag_s`` (useful for periodic
        loadings, whose correlation has several equal peaks).
    prominence : float
        ``"first-peak"`` only: fraction of the record's range (max - min).
    near_lag_s : float, optional
        ``"xcorr"`` only: a lag known to within about ``near_width_s`` (e.g. from the same
        records at a lower rate). The correlation is computed at the lags within
        ``near_width_s`` of it only (a dot product each, not an FFT correlation of the
        whole records), and at every lag if its peak lies at that window's edge or is
        below ``MIN_CORRELATION``. Movie
        calibration aligns twice, the second time near the first lag.
    near_width_s : float, optional
        Half width of that window in s (default: 16 samples of the sensor).

    Returns
    -------
    float
        ``lag_s``: the shift to add to the reference's time stamps to put them on the
        sensor's clock; positive when the reference record starts later.

    Raises
    ------
    ValueError
        Unknown method, bad records (see ``time_and_values``), irregular time stamps, no
        prominent peak, or (``"xcorr"``) records that do not overlap: their correlation
        at the best lag is below ``MIN_CORRELATION`` (0.5), or no lag overlaps enough.

    Notes
    -----
    A zero-phase frequency-dependent gain (the thesis' sensor model, eq. 4.1) does not
    move the correlation peak, so the lag is unbiased for it.

    Examples
    --------
    >>> import numpy as np, xarray as xr
    >>> t = np.arange(4000) / 1000.0
    >>> s = xr.DataArray(np.exp(-((t - 2.0) / 0.05) ** 2), dims="time", coords={"time": t})
    >>> tr = np.arange(5000) / 1250.0
    >>> r = xr.DataArray(np.exp(-((tr - 1.5) / 0.05) ** 2), dims="time", coords={"time": tr})
    >>> round(estimate_lag(s, r), 4)
    0.5
    """
    if method == "xcorr":
        return _xcorr_lag(sensor, reference, max_lag_s, near_lag_s, near_width_s)
    if near_lag_s is not None:
        raise TactilecalError(f"near_lag_s={near_lag_s!r} is for method='xcorr'; "
                              f"method={method!r} takes none")
    t_sens, x_sens, _ = on_uniform_grid(*time_and_values(sensor, "sensor"),
                                        label(sensor, "sensor"))
    t_ref, x_ref, _ = on_uniform_grid(*time_and_values(reference, "reference"),
                                      label(reference, "reference"))
    if method == "first-peak":
        return (_first_peak_time(t_sens, x_sens, prominence, label(sensor, "sensor"))
                - _first_peak_time(t_ref, x_ref, prominence, label(reference, "reference")))
    raise TactilecalError(f"method={method!r}; expected 'xcorr' or 'first-peak'")


def _xcorr_lag(sensor, reference, max_lag_s, near_lag_s, near_width_s):
    """:func:`estimate_lag` with ``method="xcorr"``, optionally near a known lag."""
    t_sens, x_sens, fs_sens = on_uniform_grid(*time_and_values(sensor, "sensor"),
                                              label(sensor, "sensor"))
    t_ref, x_ref, fs_ref = on_uniform_grid(*time_and_values(reference, "reference"),
                                           label(reference, "reference"))
    where = f"{label(sensor, 'sensor')} and {label(reference, 'reference')}"
    near = None
    if near_lag_s is not None:
        width = NEAR_SAMPLES if near_width_s is None else float(near_width_s) * fs_sens
        if not width >= 1:
            raise TactilecalError(f"near_width_s={near_width_s!r}; expected at least one sample "
                                  f"of the sensor ({1 / fs_sens:.6g} s)")
        near = (float(near_lag_s), int(round(width)))
    return _lag_xcorr(t_sens, x_sens, fs_sens, t_ref, x_ref, fs_ref, max_lag_s, where, near)


def _target_times(time_s):
    """Return ``(times, dim, coords-indexer-able DataArray or None)`` of the target grid."""
    if isinstance(time_s, xr.DataArray) and "time" in time_s.coords:
        return np.asarray(time_s["time"].values, dtype=float), time_s
    return np.asarray(time_s, dtype=float).ravel(), None


def resample_to(reference, time_s, *, lag_s=0.0):
    """Resample a reference record onto the sensor's time stamps.

    Implements the resampling step of Gillis (2013), section 4.3.2.1 (load cell at
    5000 Hz brought to the sensor's 4000 Hz).

    Parameters
    ----------
    reference : xarray.DataArray
        1-D record with a ``time`` coordinate in s, regularly sampled (a jitter up to 50 %
        of the step is first interpolated onto a uniform grid).
    time_s : array_like or xarray.DataArray
        Target time stamps in s on the sensor's clock, increasing, about regularly spaced
        (steps within 50 % of the median: real I-Scan frame times jitter); or a record whose
        ``time`` coordinate is used (its dimension, e.g. ``frame``, is kept).
    lag_s : float
        Added to the reference's time stamps first (see :func:`estimate_lag`).

    Returns
    -------
    xarray.DataArray
        The reference at the target time stamps **that fall inside the reference's
        span** (the overlap): stamps before its first or after its last sample are dropped,
        never extrapolated. Attributes of ``reference`` plus ``resampled_from_hz`` and
        ``lag_s``.

    Raises
    ------
    ValueError
        Bad or irregular records, or fewer than 2 target stamps inside the reference span
        (records that do not overlap in time).

    Notes
    -----
    The rate is changed by :func:`scipy.signal.resample_poly` with the rational ratio of
    the two rates (anti-alias FIR, ``padtype="line"``: detrended by the line through the end
    samples, so no edge transient), then a cubic spline through the resampled record places
    it on the exact target stamps (fractional-sample offset; attenuation below 1e-4 up to a
    tenth of the sampling rate).

    Examples
    --------
    >>> import numpy as np, xarray as xr
    >>> tr = np.arange(0, 2.0, 1 / 5000)
    >>> ref = xr.DataArray(120 + 20 * np.sin(2 * np.pi * 10 * tr), dims="time",
    ...                    coords={"time": tr})
    >>> out = resample_to(ref, np.arange(0, 3.0, 1 / 4000), lag_s=0.5)
    >>> float(out.time[0]), float(out.time[-1]), out.attrs["resampled_from_hz"]
    (0.5, 2.49975, 5000.0)
    >>> bool(np.allclose(out, 120 + 20 * np.sin(2 * np.pi * 10 * (out.time - 0.5)), atol=1e-3))
    True
    """
    where = label(reference, "reference")
    t_ref, x_ref, fs_in = on_uniform_grid(*time_and_values(reference, "reference"), where)
    t_ref = t_ref + float(lag_s)
    target, like = _target_times(time_s)
    if target.size < 2 or not np.all(np.diff(target) > 0):
        raise TactilecalError(f"{label(like, 'time_s')}: {target.size} target time stamps; "
                              "expected at least 2, strictly increasing")
    fs_out = sampling_rate_hz(target, label(like, "time_s"), max_jitter=MAX_ALIGN_JITTER)
    y, fs_y = _polyphase(x_ref, fs_in, fs_out)
    t_y = t_ref[0] + np.arange(y.size) / fs_y
    tol_s = 1e-6 / fs_out  # float round-off of the stamps
    keep = (target >= t_ref[0] - tol_s) & (target <= min(t_ref[-1], t_y[-1]) + tol_s)
    if np.count_nonzero(keep) < 2:
        raise TactilecalError(
            f"{where}: records do not overlap in time; the reference spans "
            f"{t_ref[0]:.6g}..{t_ref[-1]:.6g} s (lag_s={lag_s:.6g} added) and the target "
            f"{target[0]:.6g}..{target[-1]:.6g} s; expected a common time span")
    values = _cubic_through(t_y, y)(target[keep])
    attrs = {**reference.attrs, "resampled_from_hz": fs_in, "lag_s": float(lag_s)}
    if like is None:
        return xr.DataArray(values, dims="time", coords={"time": target[keep]}, attrs=attrs)
    dim = like.dims[0]
    out = like.isel({dim: np.flatnonzero(keep)}).copy(data=values)
    out.attrs = attrs
    out.name = reference.name
    return out


def _cubic_through(t, y):
    """Return the not-a-knot cubic spline through ``(t, y)``, extrapolated by its ends.

    :class:`scipy.interpolate.CubicSpline` (a tridiagonal solve) from 4 points, the same
    spline as ``make_interp_spline(t, y, k=3)`` (its B-spline form, a banded collocation
    solve) to round-off (6.7e-16 on 98,000 points) in 0.38 of its time; below 4 points
    ``make_interp_spline``, which says why it cannot.
    """
    if t.size >= 4:
        return interpolate.CubicSpline(t, y, bc_type="not-a-knot", extrapolate=True)
    spline = interpolate.make_interp_spline(t, y, k=3)
    return lambda x: spline(x, extrapolate=True)


def align(sensor, reference, *, method="xcorr", max_lag_s=None):
    """Estimate the lag and resample the reference onto the sensor's overlapping stamps.

    Parameters
    ----------
    sensor, reference : xarray.DataArray
        1-D records with a ``time`` coordinate (s).
    method, max_lag_s
        As in :func:`estimate_lag`.

    Returns
    -------
    sensor_overlap, reference_on_sensor : xarray.DataArray
        The sensor record cut to the overlap and the reference on the same stamps.
    lag_s : float
        See :func:`estimate_lag`.

    Examples
    --------
    >>> import numpy as np, xarray as xr
    >>> t = np.arange(0, 2, 1 / 1000)
    >>> s = xr.DataArray(np.sin(2 * np.pi * 3 * t**2), dims="time", coords={"time": t})
    >>> tr = np.arange(0, 1, 1 / 500)
    >>> r = xr.DataArray(np.sin(2 * np.pi * 3 * (tr + 0.25)**2), dims="time",
    ...                  coords={"time": tr})
    >>> s2, r2, lag = align(s, r)
    >>> round(lag, 3), s2.sizes["time"] == r2.sizes["time"]
    (0.25, True)
    """
    lag_s = estimate_lag(sensor, reference, method=method, max_lag_s=max_lag_s)
    ref = resample_to(reference, sensor, lag_s=lag_s)
    dim = sensor.dims[0]
    times = np.asarray(ref["time"].values)
    sensor_overlap = sensor.isel({dim: np.flatnonzero(np.isin(sensor["time"].values,
                                                                times))})
    return sensor_overlap, ref, lag_s
