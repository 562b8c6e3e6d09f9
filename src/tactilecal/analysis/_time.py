"""Time effects: drift and creep under a held load, hysteresis between loading and unloading.

Gillis (2013) section 2.1 reviews Paikowsky and Hajduk (1997): creep is the drift of the
sensor's response under a steady load, with a rate-dependent non-linear zone in the first
30 minutes and a linear zone after it; hysteresis is the difference between the loading
and the unloading response at the same load. :func:`creep` fits both zones' forms
(linear in time and linear in log-time) and :func:`hysteresis` measures the loop.
"""

from dataclasses import asdict, dataclass, fields

import numpy as np
import xarray as xr

from tactilecal._errors import TactilecalError
from tactilecal._jsonutil import to_jsonable
from tactilecal._result import SavedResult
from tactilecal._validate import check_number, require_keys

__all__ = ["CreepResult", "HysteresisResult", "creep", "hysteresis"]


def _as_series(signal, time_s, calibration, what):
    """Return ``(values, time_s, units)`` for a 1-D signal or a recording (total force)."""
    if isinstance(signal, xr.DataArray) and signal.ndim == 3:
        from tactilecal.analysis._maps import total_force

        signal = total_force(signal, calibration=calibration)
    units = signal.attrs.get("units", "") if isinstance(signal, xr.DataArray) else ""
    if time_s is None:
        if not isinstance(signal, xr.DataArray) or "time" not in signal.coords:
            raise TactilecalError(f"{what} has no 'time' coordinate; expected a DataArray with "
                                  "time in s or time_s=...")
        time_s = signal["time"].values
    values = np.asarray(signal, dtype=float)
    time_s = np.asarray(time_s, dtype=float)
    if values.ndim != 1 or values.shape != time_s.shape:
        raise TactilecalError(f"{what} has shape {values.shape} and time {time_s.shape}; "
                              "expected two 1-D arrays of the same length")
    return values, time_s, units


class _TimeResult(SavedResult):
    """A saved time-effect result: its fields as JSON numbers, equal by value."""

    def _to_dict(self):
        return to_jsonable(asdict(self))

    @classmethod
    def _from_dict(cls, data, source):
        require_keys(data, [f.name for f in fields(cls)], source, expected=cls.DESCRIPTION)
        values = {}
        for f in fields(cls):
            where = f"key '{f.name}' of {source}"
            if f.type is str:
                values[f.name] = str(data[f.name])
            else:  # numbers; NaN was saved as null (an undefined R2 or rate)
                value = check_number(data[f.name], where, allow_none=f.type is float,
                                     integer=f.type is int, minimum=0 if f.type is int else None)
                values[f.name] = float("nan") if value is None else value
        return cls(**values)

    def _repr_fields(self):
        return [(f.name, getattr(self, f.name)) for f in fields(self)][:8]


@dataclass(frozen=True, eq=False, repr=False)
class CreepResult(_TimeResult):
    """Drift of a signal held under a constant load (see :func:`creep`).

    Saved with :meth:`to_json` (``"format": "tactilecal-creep/1"``), read by
    ``tactilecal.load``.

    Attributes
    ----------
    units : str
        Units of the signal (``N`` for a recording's total force).
    n : int
        Samples in the window used by the linear fit.
    start_s, stop_s, t_load_s : float
        Window and time of load application [s].
    reference : float
        Fitted value at ``start_s``: the base of the percentages.
    slope_per_min, slope_stderr_per_min : float
        Linear drift [units/min] and its standard error.
    rate_pct_per_min, rate_stderr_pct_per_min : float
        ``100 * slope / reference`` [% per minute] and its standard error.
    log_n : int
        Samples used by the log-time fit (those after ``t_load_s``).
    log_slope_per_decade, log_stderr_per_decade : float
        Change per decade of time since loading [units/decade] and its standard error.
    log_rate_pct_per_decade : float
        ``100 * log_slope / reference`` [% per decade].
    linear_r2, log_r2 : float
        Coefficients of determination of the two fits.
    """

    units: str
    n: int
    start_s: float
    stop_s: float
    t_load_s: float
    reference: float
    slope_per_min: float
    slope_stderr_per_min: float
    rate_pct_per_min: float
    rate_stderr_pct_per_min: float
    log_n: int
    log_slope_per_decade: float
    log_stderr_per_decade: float
    log_rate_pct_per_decade: float
    linear_r2: float
    log_r2: float

    FORMAT_KIND = "creep"
    DESCRIPTION = "a creep result JSON"

    def summary(self):
        """Return a short human-readable summary."""
        return (f"creep over {self.start_s:g}-{self.stop_s:g} s ({self.n} samples): "
                f"{self.rate_pct_per_min:+.3f} +- {self.rate_stderr_pct_per_min:.3f} %/min "
                f"(R2 {self.linear_r2:.3f}); log-time "
                f"{self.log_rate_pct_per_decade:+.3f} %/decade (R2 {self.log_r2:.3f})")


def creep(signal, *, time_s=None, start_s=None, stop_s=None, t_load_s=None,
          calibration=None):
    """Drift rate of a signal under a held load: linear and log-time fits.

    Parameters
    ----------
    signal : xarray.DataArray or array_like
        1-D series (e.g. ``total_force``) with a ``time`` coordinate, or a recording
        ``("frame", "row", "col")`` whose total force is used, or an array with ``time_s``.
    time_s : array_like, optional
        Times in s when ``signal`` carries none.
    start_s, stop_s : float, optional
        Window of the held load (inclusive); default the whole series.
    t_load_s : float, optional
        Time the load was applied (origin of log-time); default ``start_s``.
    calibration : CalibrationResult or path, optional
        For a raw recording.

    Returns
    -------
    CreepResult

    Raises
    ------
    ValueError
        If fewer than 3 samples lie in the window (or after ``t_load_s``), or the fitted
        reference value is not positive.

    Notes
    -----
    Linear zone (Paikowsky and Hajduk 1997, in Gillis 2013 section 2.1):
    ``y(t) = y0 + s (t - start_s)``, rate ``100 s / y0`` in % per minute. Early zone:
    ``y(t) = a + c log10(t - t_load_s)``, rate ``100 c / y0`` in % per decade of time.
    Both by ordinary least squares (:func:`scipy.stats.linregress`).

    Examples
    --------
    >>> import numpy as np
    >>> t = np.arange(0, 601.0, 1.0)
    >>> r = creep(100.0 * (1 + 0.001 * t / 60), time_s=t)
    >>> round(r.rate_pct_per_min, 6)
    0.1
    """
    from scipy import stats

    values, t, units = _as_series(signal, time_s, calibration, "signal")
    start_s = float(np.nanmin(t)) if start_s is None else float(start_s)
    stop_s = float(np.nanmax(t)) if stop_s is None else float(stop_s)
    t_load_s = start_s if t_load_s is None else float(t_load_s)
    keep = (t >= start_s) & (t <= stop_s) & np.isfinite(values) & np.isfinite(t)
    if keep.sum() < 3:
        raise TactilecalError(f"creep window {start_s:g}-{stop_s:g} s holds {int(keep.sum())} "
                              "samples; expected at least 3")
    lin = stats.linregress((t[keep] - start_s) / 60.0, values[keep])
    reference = float(lin.intercept)
    if reference <= 0:
        raise TactilecalError(f"fitted signal at start_s={start_s:g} s is {reference:g}; expected "
                              "a positive held load")
    after = keep & (t > t_load_s)
    if after.sum() < 3:
        raise TactilecalError(f"{int(after.sum())} samples after t_load_s={t_load_s:g} s in the "
                              "window; expected at least 3 for the log-time fit")
    log = stats.linregress(np.log10(t[after] - t_load_s), values[after])
    return CreepResult(
        units=units, n=int(keep.sum()), start_s=start_s, stop_s=stop_s, t_load_s=t_load_s,
        reference=reference, slope_per_min=float(lin.slope),
        slope_stderr_per_min=float(lin.stderr),
        rate_pct_per_min=100 * float(lin.slope) / reference,
        rate_stderr_pct_per_min=100 * float(lin.stderr) / reference,
        log_n=int(after.sum()), log_slope_per_decade=float(log.slope),
        log_stderr_per_decade=float(log.stderr),
        log_rate_pct_per_decade=100 * float(log.slope) / reference,
        linear_r2=float(lin.rvalue) ** 2, log_r2=float(log.rvalue) ** 2,
    )


@dataclass(frozen=True, eq=False, repr=False)
class HysteresisResult(_TimeResult):
    """Loading/unloading loop of a sensor against a reference (see :func:`hysteresis`).

    Saved with :meth:`to_json` (``"format": "tactilecal-hysteresis/1"``), read by
    ``tactilecal.load``.

    Attributes
    ----------
    n_loading, n_unloading : int
        Samples in each branch (the peak belongs to both).
    reference_range, measured_range : float
        Peak-to-peak of the reference and of the measured signal.
    max_gap : float
        Largest ``|unloading - loading|`` at equal reference [measured units].
    max_gap_at : float
        Reference value where it occurs.
    max_gap_pct : float
        ``100 * max_gap / measured_range``.
    area : float
        Signed area between the branches, ``integral (unloading - loading) d(reference)``
        (positive when unloading reads high).
    area_pct : float
        ``100 * area / (reference_range * measured_range)``.
    """

    n_loading: int
    n_unloading: int
    reference_range: float
    measured_range: float
    max_gap: float
    max_gap_at: float
    max_gap_pct: float
    area: float
    area_pct: float

    FORMAT_KIND = "hysteresis"
    DESCRIPTION = "a hysteresis result JSON"

    def summary(self):
        """Return a short human-readable summary."""
        return (f"hysteresis: max gap {self.max_gap:.4g} ({self.max_gap_pct:.2f}% of range) "
                f"at reference {self.max_gap_at:.4g}; loop area {self.area_pct:.2f}% "
                "of the range box")


def _branch(reference, measured, grid):
    order = np.argsort(reference, kind="stable")
    return np.interp(grid, reference[order], measured[order])


def hysteresis(reference, measured, *, n_grid=501):
    """Hysteresis of one loading-unloading cycle.

    Parameters
    ----------
    reference : array_like
        Applied load (or pressure) over one cycle: rising to its peak, then falling.
    measured : array_like
        Sensor reading at the same instants.
    n_grid : int, default 501
        Reference values at which the two branches are compared.

    Returns
    -------
    HysteresisResult

    Raises
    ------
    ValueError
        If the arrays differ in length, hold NaN, or a branch has fewer than 2 samples.

    Notes
    -----
    The cycle is split at the peak of ``reference``; each branch is interpolated
    linearly at ``n_grid`` reference values over the range both branches cover, and the
    gap ``g(x) = m_unload(x) - m_load(x)`` gives the largest gap and the loop area
    ``integral g dx`` (trapezoid rule). Hysteresis after Paikowsky and Hajduk (1997),
    reviewed in Gillis (2013) section 2.1: "the difference in the sensor's recording for
    a loading and unloading trial back to the same pressure".

    Examples
    --------
    >>> import numpy as np
    >>> up = np.linspace(0, 10, 101)
    >>> down = up[::-1][1:]
    >>> ref = np.r_[up, down]
    >>> meas = np.r_[up, down + 2 * np.sin(np.pi * down / 10)]
    >>> r = hysteresis(ref, meas)
    >>> round(r.max_gap, 3), round(r.max_gap_at, 3), round(r.area, 2)
    (2.0, 5.0, 12.73)
    """
    from scipy.integrate import trapezoid

    ref = np.asarray(reference, dtype=float)
    meas = np.asarray(measured, dtype=float)
    if ref.ndim != 1 or ref.shape != meas.shape:
        raise TactilecalError(f"reference has shape {ref.shape} and measured {meas.shape}; "
                              "expected two 1-D arrays of the same length")
    if not (np.isfinite(ref).all() and np.isfinite(meas).all()):
        raise TactilecalError("reference or measured holds NaN or inf; expected finite values")
    peak = int(np.argmax(ref))
    if peak < 1 or peak > ref.size - 2:
        raise TactilecalError(f"the reference peaks at sample {peak} of {ref.size}; expected a "
                              "loading branch and an unloading branch of at least 2 samples each")
    load, unload = slice(0, peak + 1), slice(peak, None)
    lo = max(ref[load].min(), ref[unload].min())
    grid = np.linspace(lo, ref[peak], n_grid)
    gap = _branch(ref[unload], meas[unload], grid) - _branch(ref[load], meas[load], grid)
    ref_range, meas_range = float(np.ptp(ref)), float(np.ptp(meas))
    i = int(np.argmax(np.abs(gap)))
    area = float(trapezoid(gap, grid))
    return HysteresisResult(
        n_loading=peak + 1, n_unloading=ref.size - peak, reference_range=ref_range,
        measured_range=meas_range, max_gap=float(abs(gap[i])), max_gap_at=float(grid[i]),
        max_gap_pct=100 * float(abs(gap[i])) / meas_range, area=area,
        area_pct=100 * area / (ref_range * meas_range),
    )
