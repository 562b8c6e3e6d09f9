"""Loading over time: pressure- and force-time integrals, loading rate, steps, alignment.

Integrals use the trapezoid rule on the recording's ``time`` coordinate. A step (a stance
phase of a foot, one loading of a joint) is a run of frames whose total force is above a
threshold; per step the table gives its peak, impulse, loading rate, peak pressure and
pressure-time integral and its centre-of-pressure path.
"""

from dataclasses import dataclass, field

import numpy as np
import pandas as pd
import xarray as xr

from tactilecal._contact import CONTACT_FORCE_SHARE
from tactilecal._errors import TactilecalError
from tactilecal._model import recording_name
from tactilecal.analysis._units import pressure_map_kPa

__all__ = ["time_s", "time_integral", "pressure_time_integral",
           "force_time_integral", "loading_rate", "steps", "Steps", "align_recordings",
           "ALIGN_CHOICES"]

LOADING_RATE_LEVELS = (0.2, 0.8)
"""The loading rate is the mean slope between these shares of the first force peak."""

ALIGN_CHOICES = ("time", "start", "onset")
"""How :func:`align_recordings` puts recordings on one time axis."""


def time_s(data):
    """Return the frame times in seconds of a recording, a summary or a per-frame series.

    The ``time`` coordinate; else ``frame index x seconds_per_frame``.

    Raises
    ------
    TactilecalError
        With neither, or with times that do not increase.
    """
    if "time" in data.coords:
        t = np.asarray(data["time"].values, dtype=float)
    elif "seconds_per_frame" in data.attrs:
        t = np.arange(data.sizes["frame"]) * float(data.attrs["seconds_per_frame"])
    else:
        raise TactilecalError(f"{recording_name(data)}: no time coordinate and no "
                              "seconds_per_frame; expected frame times to integrate over")
    if t.size > 1 and not np.all(np.diff(t) > 0):
        raise TactilecalError(f"{recording_name(data)}: frame times do not increase; expected "
                              "strictly increasing times")
    return t


def _trapezoid_weights(t):
    """Weights ``w`` with ``sum(w * y) = trapezoid(y, t)``."""
    w = np.zeros_like(t)
    if t.size > 1:
        dt = np.diff(t)
        w[:-1] += dt / 2
        w[1:] += dt / 2
    return w


def time_integral(values, t=None):
    """Integrate a per-frame quantity over time with the trapezoid rule.

    Parameters
    ----------
    values : xarray.DataArray
        Any array with dim ``frame`` (a force series, a pressure map...).
    t : array_like, optional
        Frame times [s]; default :func:`time_s` of ``values``.

    Returns
    -------
    xarray.DataArray
        ``values`` integrated over ``frame`` (NaN where any frame is NaN).

    Examples
    --------
    >>> y = xr.DataArray([0.0, 2.0, 2.0, 0.0], dims="frame",
    ...                  coords={"time": ("frame", [0.0, 1.0, 2.0, 3.0])})
    >>> float(time_integral(y))
    4.0
    """
    t = time_s(values) if t is None else np.asarray(t, dtype=float)
    weights = xr.DataArray(_trapezoid_weights(t), dims="frame")
    return xr.dot(values.drop_vars(["time", "frame"], errors="ignore"), weights, dim="frame")


def pressure_time_integral(recording, *, calibration=None):
    """Each sensel's pressure integrated over the recording [kPa s].

    Parameters
    ----------
    recording : xarray.DataArray
        Recording in the data model (raw needs ``calibration``).
    calibration : CalibrationResult or path, optional
        Applied to a raw recording.

    Returns
    -------
    xarray.DataArray
        ``pti_kPa_s`` with dims ``("row", "col")``; NaN outside the sensor.

    Notes
    -----
    ``PTI_k = integral p_k(t) dt`` by the trapezoid rule over the frame times: the
    pressure-time integral of plantar-pressure analysis (e.g. Melai et al. 2011); its
    largest value is the region's peak PTI.

    Examples
    --------
    >>> import numpy as np, xarray as xr
    >>> rec = xr.DataArray(np.full((3, 1, 2), 100.0), dims=("frame", "row", "col"),
    ...                    coords={"time": ("frame", [0.0, 0.5, 1.0])}, attrs={"units": "kPa"})
    >>> pressure_time_integral(rec).values
    array([[100., 100.]])
    """
    pressure = pressure_map_kPa(recording, calibration=calibration)
    out = time_integral(pressure, time_s(recording))
    out.name = "pti_kPa_s"
    out.attrs = {"units": "kPa s"}
    return out


def force_time_integral(recording, *, calibration=None):
    """Total force integrated over the recording: the impulse [N s].

    Examples
    --------
    >>> import numpy as np, xarray as xr
    >>> rec = xr.DataArray(np.full((3, 1, 1), 10.0), dims=("frame", "row", "col"),
    ...                    coords={"time": ("frame", [0.0, 1.0, 2.0])}, attrs={"units": "N"})
    >>> force_time_integral(rec)
    20.0
    """
    from tactilecal.analysis._maps import total_force

    return float(time_integral(total_force(recording, calibration=calibration),
                               time_s(recording)))


def _crossing(t, y, i, level):
    """Time at which ``y`` crosses ``level`` between samples ``i`` and ``i + 1`` (linear)."""
    y0, y1 = y[i], y[i + 1]
    return t[i] + (level - y0) / (y1 - y0) * (t[i + 1] - t[i])


def loading_rate(force, t=None):
    """Mean slope of the rise to the first force peak, 20 % to 80 % of that peak [N/s].

    Parameters
    ----------
    force : array_like or xarray.DataArray
        Total force of one loading (a step), starting before the rise.
    t : array_like, optional
        Frame times [s] (default :func:`time_s` of ``force``).

    Returns
    -------
    float
        ``0.6 F1 / (t80 - t20)``, where ``F1`` is the first local maximum of at least half
        the largest force and ``t20``, ``t80`` are the times (linearly interpolated) at
        which the force first reaches 20 % and 80 % of ``F1``; NaN when the force does not
        start below 20 % of ``F1``.

    Notes
    -----
    The average vertical loading rate of gait analysis, between 20 % and 80 % of the
    impact peak (e.g. Milner et al. 2006, Med Sci Sports Exerc 38(2):323).

    Examples
    --------
    >>> loading_rate([0.0, 100.0, 200.0, 300.0, 250.0], [0.0, 0.1, 0.2, 0.3, 0.4])
    1000.0
    """
    y = np.asarray(getattr(force, "values", force), dtype=float)
    t = time_s(force) if t is None else np.asarray(t, dtype=float)
    if y.size < 3 or not np.isfinite(y).all():
        return float("nan")
    peak = int(_first_peak(y))
    lo, hi = (level * y[peak] for level in LOADING_RATE_LEVELS)
    rise = y[:peak + 1]
    if rise[0] >= lo:
        return float("nan")
    i20 = int(np.argmax(rise >= lo)) - 1
    i80 = int(np.argmax(rise >= hi)) - 1
    t20, t80 = _crossing(t, y, i20, lo), _crossing(t, y, i80, hi)
    return float((hi - lo) / (t80 - t20))


def _first_peak(y):
    """Index of the first local maximum of at least half the largest value."""
    top = np.nanmax(y)
    for i in range(1, len(y) - 1):
        if y[i] >= 0.5 * top and y[i] >= y[i - 1] and y[i] > y[i + 1]:
            return i
    return int(np.nanargmax(y))


@dataclass
class Steps:
    """Stance phases (steps) of a recording, found from its total force.

    Attributes
    ----------
    table : pandas.DataFrame
        One row per step: ``step``, ``complete`` (it starts and ends inside the
        recording), ``first_frame``, ``last_frame``, ``start_s``, ``end_s`` (threshold
        crossings, linearly interpolated), ``duration_s``, ``peak_force_N``,
        ``peak_force_time_s``, ``impulse_N_s``, ``loading_rate_N_s``, ``peak_pressure_kPa``,
        ``pti_kPa_s`` (the peak pressure integrated over the step), ``cop_start_row_mm``,
        ``cop_start_col_mm``, ``cop_end_row_mm``, ``cop_end_col_mm``, ``cop_path_mm`` (length
        of the centre-of-pressure path) and ``saturated_frames``.
    paths : list of pandas.DataFrame
        Each step's centre-of-pressure path: ``time_s``, ``cof_row_mm``, ``cof_col_mm``.
    threshold_N : float
        A frame is in contact when its total force is above this.
    source : str
        The recording.
    """

    table: pd.DataFrame
    paths: list = field(default_factory=list)
    threshold_N: float = 0.0
    source: str = ""

    def __len__(self):
        return len(self.table)

    def __repr__(self):
        complete = int(self.table["complete"].sum()) if len(self.table) else 0
        return (f"Steps({len(self)} steps of {self.source or 'a recording'}, {complete} "
                f"complete; contact above {self.threshold_N:.4g} N)")

    def plot_paths(self, *, recording=None, ax=None):
        """Draw each step's centre-of-pressure path (column mm across, row mm down).

        Over the peak-pressure map of ``recording`` when given (at the sensor's scale).
        """
        from tactilecal.analysis._plots import plot_step_paths

        return plot_step_paths(self, ax=ax, recording=recording)


def steps(recording, *, threshold_N=None, min_duration_s=0.0, calibration=None, summary=None):
    """Find the steps (stance phases) of a recording and describe each one.

    Parameters
    ----------
    recording : xarray.DataArray
        Recording in the data model (raw needs ``calibration``).
    threshold_N : float, optional
        A frame is in contact when its total force is above this; default
        :data:`CONTACT_FORCE_SHARE` (5 %) of the recording's peak force.
    min_duration_s : float, default 0
        Shorter runs of contact are left out (and counted in ``Steps.table.attrs``).
    calibration : CalibrationResult or path, optional
        Applied to a raw recording.
    summary : xarray.Dataset, optional
        The recording's ``frame_summary()`` if already computed.

    Returns
    -------
    Steps

    Examples
    --------
    >>> import numpy as np, xarray as xr
    >>> f = np.array([0, 5, 10, 5, 0, 0, 6, 12, 6, 0], float)
    >>> rec = xr.DataArray(f[:, None, None], dims=("frame", "row", "col"),
    ...                    coords={"time": ("frame", np.arange(10) * 0.1)},
    ...                    attrs={"units": "N", "sensel_area_mm2": 1.0, "row_spacing_mm": 1.0,
    ...                           "col_spacing_mm": 1.0})
    >>> s = steps(rec, threshold_N=1.0)
    >>> s.table[["step", "peak_force_N", "impulse_N_s"]].round(6).values.tolist()
    [[1.0, 10.0, 2.0], [2.0, 12.0, 2.4]]
    """
    from tactilecal.analysis._maps import summary as frame_summary

    s = frame_summary(recording, calibration=calibration) if summary is None else summary
    s = s.compute()
    t = time_s(s)
    force = np.asarray(s["force_N"].values, dtype=float)
    peak = float(np.nanmax(force)) if np.isfinite(force).any() else 0.0
    threshold_N = CONTACT_FORCE_SHARE * peak if threshold_N is None else float(threshold_N)
    if not np.isfinite(threshold_N) or threshold_N < 0:
        raise TactilecalError(f"threshold_N is {threshold_N!r}; expected a finite force >= 0")
    runs = _runs(np.nan_to_num(force) > threshold_N)
    kept = [(a, b) for a, b in runs if _duration(t, a, b) >= min_duration_s]
    rows, paths = [], []
    bounds = [b for _, b in kept]
    for k, (a, b) in enumerate(kept, 1):
        previous_end = bounds[k - 2] if k > 1 else 0
        next_start = kept[k][0] if k < len(kept) else len(force) - 1
        row, path = _describe_step(s, t, force, (a, b), (previous_end, next_start),
                                   threshold_N)
        rows.append({"step": k, **row})
        paths.append(path)
    table = pd.DataFrame(rows, columns=_STEP_COLUMNS)
    table.attrs["runs_shorter_than_min_duration"] = len(runs) - len(kept)
    return Steps(table, paths, threshold_N, str(recording.attrs.get("source", "")))


_STEP_COLUMNS = ["step", "complete", "first_frame", "last_frame", "start_s", "end_s",
                 "duration_s", "peak_force_N", "peak_force_time_s", "impulse_N_s",
                 "loading_rate_N_s", "peak_pressure_kPa", "pti_kPa_s", "cop_start_row_mm",
                 "cop_start_col_mm", "cop_end_row_mm", "cop_end_col_mm", "cop_path_mm",
                 "saturated_frames"]


def _runs(flags):
    """``(first, last)`` index pairs of the runs of True in ``flags``."""
    edges = np.diff(np.concatenate([[0], flags.astype(np.int8), [0]]))
    return list(zip(np.flatnonzero(edges == 1), np.flatnonzero(edges == -1) - 1, strict=True))


def _duration(t, a, b):
    return t[b] - t[a]


def _foot(force, i, step, stop):
    """Walk from frame ``i`` while the force keeps falling, not past ``stop``."""
    while i != stop and np.nan_to_num(force[i + step]) < np.nan_to_num(force[i]):
        i += step
    return i


def _describe_step(s, t, force, run, limits, level):
    """One row of the step table; integrals span the step's whole rise and fall.

    The span runs from the last minimum of the force before the threshold crossing to
    the first after it (never into the neighbouring steps), so the parts of the loading
    below the threshold are integrated too.
    """
    a, b = run
    n = len(force)
    lo, hi = _foot(force, a, -1, limits[0]), _foot(force, b, 1, limits[1])
    start = _crossing(t, force, a - 1, level) if a > 0 else t[a]
    end = _crossing(t, force, b, level) if b < n - 1 else t[b]
    span = slice(lo, hi + 1)
    i_peak = a + int(np.nanargmax(force[a:b + 1]))
    rows = np.asarray(s["cof_row_mm"].values[a:b + 1], float)
    cols = np.asarray(s["cof_col_mm"].values[a:b + 1], float)
    ok = np.isfinite(rows) & np.isfinite(cols)
    path = pd.DataFrame({"time_s": t[a:b + 1][ok], "cof_row_mm": rows[ok],
                         "cof_col_mm": cols[ok]})
    length = float(np.hypot(np.diff(path["cof_row_mm"]), np.diff(path["cof_col_mm"])).sum())
    peak_kPa = np.asarray(s["peak_kPa"].values, float)
    saturated = (int((s["saturated_sensels"].values[a:b + 1] > 0).sum())
                 if "saturated_sensels" in s else None)
    first, last = (path.iloc[0], path.iloc[-1]) if len(path) else (None, None)
    return {
        "complete": bool(a > 0 and b < n - 1),
        "first_frame": int(s["frame"].values[a]) if "frame" in s.coords else int(a),
        "last_frame": int(s["frame"].values[b]) if "frame" in s.coords else int(b),
        "start_s": float(start), "end_s": float(end), "duration_s": float(end - start),
        "peak_force_N": float(force[i_peak]), "peak_force_time_s": float(t[i_peak]),
        "impulse_N_s": float(np.dot(_trapezoid_weights(t[span]), force[span])),
        "loading_rate_N_s": loading_rate(force[lo:b + 1], t[lo:b + 1]) if a > 0 else np.nan,
        "peak_pressure_kPa": float(np.nanmax(peak_kPa[a:b + 1])),
        "pti_kPa_s": float(np.dot(_trapezoid_weights(t[span]), np.nan_to_num(peak_kPa[span]))),
        "cop_start_row_mm": np.nan if first is None else float(first["cof_row_mm"]),
        "cop_start_col_mm": np.nan if first is None else float(first["cof_col_mm"]),
        "cop_end_row_mm": np.nan if last is None else float(last["cof_row_mm"]),
        "cop_end_col_mm": np.nan if last is None else float(last["cof_col_mm"]),
        "cop_path_mm": length, "saturated_frames": saturated,
    }, path


def align_recordings(recordings, *, how="time", threshold_share=CONTACT_FORCE_SHARE):
    """Put several recordings on one time axis (left and right foot of one walk...).

    Parameters
    ----------
    recordings : sequence of xarray.DataArray
        Recordings in the data model, calibrated (pressure or force units).
    how : {"time", "start", "onset"}
        ``"time"``: each recording's own ``time`` (recordings of one session share the
        clock, as the left and right insoles of an F-Scan walk do); ``"start"``: each one's
        first frame at 0; ``"onset"``: each one's first frame with a total force above
        ``threshold_share`` of its peak at 0.
    threshold_share : float
        See ``how="onset"``.

    Returns
    -------
    list of xarray.DataArray
        The recordings with their ``time`` coordinate shifted; ``attrs["time_shift_s"]``
        says by how much (added to their own times).

    Examples
    --------
    >>> a = xr.DataArray(np.zeros((3, 1, 1)), dims=("frame", "row", "col"),
    ...                  coords={"time": ("frame", [1.0, 2.0, 3.0])}, attrs={"units": "N"})
    >>> [float(r.time[0]) for r in align_recordings([a, a], how="start")]
    [0.0, 0.0]
    """
    from tactilecal.analysis._maps import total_force

    if how not in ALIGN_CHOICES:
        raise TactilecalError(f"alignment (how=, --align) {how!r}; expected one of "
                              f"{', '.join(ALIGN_CHOICES)}")
    out = []
    for rec in recordings:
        t = time_s(rec)
        if how == "time":
            shift = 0.0
        elif how == "start":
            shift = -t[0]
        else:
            force = np.asarray(total_force(rec).values, dtype=float)
            loaded = np.flatnonzero(np.nan_to_num(force) > threshold_share * np.nanmax(force))
            if not loaded.size:
                raise TactilecalError(f"{recording_name(rec)}: no frame with force; expected a "
                                      "loading to align on (how='onset')")
            shift = -t[loaded[0]]
        out.append(rec.assign_coords(time=("frame", t + shift)).assign_attrs(
            time_shift_s=float(shift)))
    return out
