"""Movie calibration: every frame of a recording paired with a load-cell reading.

I-Scan's movie calibration pairs each frame with a load from a text file and fails on a
count mismatch (Gillis 2013, sec. 3.5). With a time column, the load-cell record is aligned
with the sensor's total raw signal by cross-correlation
(:func:`tactilecal.dynamic.estimate_lag`), resampled onto the frame times
(:func:`tactilecal.dynamic.resample_to`), saturated frames are trimmed (the default point
selection) and every remaining frame becomes a calibration point.
"""

import dataclasses
import os
import warnings
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np
import pandas as pd
import xarray as xr

from tactilecal._errors import TactilecalError
from tactilecal._progress import resolve
from tactilecal._provenance import provenance_of
from tactilecal.calibration._calibrate import DEFAULT_METHOD, fit_arrays, method_options
from tactilecal.calibration._fit import FitData
from tactilecal.calibration._models import force_table
from tactilecal.calibration._pipeline import as_equilibration, chain
from tactilecal.calibration._points import (
    _frame_histograms,
    _points_from_histograms,
    keep_rows_in_place,
)
from tactilecal.calibration._powerfit import COMPILED_MIN_POINTS, hist_products
from tactilecal.calibration._sensels import find_dead_sensels
from tactilecal.calibration.methods import MODULES

__all__ = ["read_movie_loads", "movie_points", "calibrate_movie"]

_CHUNK = 2048
_GROUP_FRAMES = 16 * _CHUNK  # frames of dask blocks computed together
_FIRST_PASS_POINTS = 5000  # frames of the fit that shapes the second alignment's signal
#: Half width, in decimation blocks of the first alignment, of the lag window the second
#: alignment searches first (all lags if its peak is at the window's edge): the two lags
#: were 3.9 frames (1.9 blocks) apart on the 100,000-frame movie of ``bench_movie.py``.
NEAR_BLOCKS = 16


def read_movie_loads(path, *, time_col=None, load_col=None):
    """Read a movie calibration's loads: a time series, or one load per frame.

    A CSV with one column (a header then one load per line, I-Scan's format) gives a plain
    array with no time; otherwise :func:`tactilecal.io.read_timeseries` reads time and load.
    Loads are converted to newtons from the unit in the column name (``Load (lbf)``); a
    column without a unit is taken as newtons.

    Returns
    -------
    numpy.ndarray or xarray.DataArray
        The loads in N (array when the file has no time column).

    Raises
    ------
    ValueError
        For a load column whose unit is not a force or a mass, or a non-numeric load.
    """
    from tactilecal._units import force_to_N, mass_to_N, unit_from_column, unit_kind
    from tactilecal.io import read_timeseries

    path = Path(path)
    header = pd.read_csv(path, nrows=0, encoding="utf-8-sig").columns
    if len(header) > 1 or time_col is not None:
        series = read_timeseries(path, time_col=time_col, value_col=load_col)
        if series.attrs.get("units") not in ("N", "unknown"):
            raise TactilecalError(f"{path}: load column {series.attrs.get('column')!r} is in "
                                  f"{series.attrs['units']!r}; expected a force or mass unit")
        return series.assign_attrs(units="N")
    column = str(header[0]).strip()
    unit = unit_from_column(column, where=f"column {column!r} of {path}")
    table = pd.read_csv(path, encoding="utf-8-sig")
    values = pd.to_numeric(table.iloc[:, 0], errors="coerce").to_numpy(float)
    bad = np.flatnonzero(~np.isfinite(values))
    if bad.size:
        raise TactilecalError(f"line {bad[0] + 2} of {path}: load {table.iloc[bad[0], 0]!r} is "
                              "not a number; expected one load per frame")
    if unit is None:
        return values
    kind = unit_kind(unit)
    if kind not in ("force", "mass"):
        raise TactilecalError(f"{path}: load column {column!r} is in {unit!r}; expected a force "
                              "or mass unit")
    return force_to_N(values, unit) if kind == "force" else mass_to_N(values, unit)


def _count_dtype(values):
    """uint16 counts when a frame has fewer than 2**16 sensels (a 44 x 44 one has 1936)."""
    return np.uint16 if int(np.prod(values.shape[1:])) < 2 ** 16 else np.int64


def _histograms(values, mask, equilibration, progress, numba_loaded=False):
    """Histograms of all frames in :func:`_count_dtype` (gains applied, mask skipped).

    ``numba_loaded``: the caller will import numba anyway (a power fit of
    ``COMPILED_MIN_POINTS`` frames or more), so its start-up no longer speaks against the
    compiled counting of a movie below ``COMPILED_MIN_VALUES`` readings.

    uint16 rather than float64 (as until session 8): 51 rather than 205 MB of fresh pages per
    100,000 frames, and a quarter of the bytes for every later product
    (:func:`tactilecal.calibration._powerfit.hist_products`). In memory, the compiled kernels (which
    release the GIL) count blocks of ``_CHUNK`` frames on every core, in threads.

    ``values`` may be a dask array (a recording larger than memory, perhaps on a cluster):
    each block of frames is counted where it is computed, by dask's scheduler, and only the
    (frames, 256) histograms are gathered. ``progress`` (the protocol of
    :mod:`tactilecal._progress`) wraps the chunks of movies of ``20 * _CHUNK`` frames or more.
    """
    from tactilecal.calibration._histogram import COMPILED_MIN_VALUES

    prepare = None if equilibration is None else equilibration.apply
    n = len(values)
    hist = np.empty((n, 256), _count_dtype(values))
    compiled = numba_loaded or values.size >= COMPILED_MIN_VALUES  # the whole movie decides
    if _is_dask(values):
        import dask.array as da

        lazy = _dask_histograms(values, mask, prepare, compiled)
        bounds = _block_groups(values.chunks[0], _GROUP_FRAMES)
    else:
        bounds = [*range(0, n, _CHUNK), n]
    spans = list(zip(bounds[:-1], bounds[1:], strict=True))

    def count(span):
        a, b = span
        if _is_dask(values):
            da.store(lazy[a:b], hist[a:b], lock=False)
        else:
            _frame_histograms(values[a:b], out=hist[a:b], prepare=prepare, mask=mask,
                              compiled=compiled)

    workers = 1 if _is_dask(values) or not compiled else min(os.cpu_count() or 1, len(spans))
    with ThreadPoolExecutor(max_workers=workers) as pool:
        done = pool.map(count, spans) if workers > 1 else map(count, spans)
        if n >= 20 * _CHUNK:
            done = progress(done, total=len(spans), desc="histograms")
        for _ in done:
            pass
    return hist


def _is_dask(values):
    return type(values).__module__.startswith("dask.")


def _block_groups(chunks, min_frames):
    """Bounds of consecutive dask blocks grouped to at least ``min_frames`` frames."""
    bounds, size = [0], 0
    for c in chunks:
        size += c
        if size >= min_frames:
            bounds.append(bounds[-1] + size)
            size = 0
    if size:
        bounds.append(bounds[-1] + size)
    return bounds


def _dask_histograms(values, mask, prepare, compiled):
    """Lazy (frames, 256) histograms, one task per block of whole frames."""
    whole_frames = values.rechunk({1: -1, 2: -1})
    dtype = _count_dtype(values)
    return whole_frames.map_blocks(_block_histograms, mask=mask, prepare=prepare,
                                   compiled=compiled, counts=dtype, dtype=dtype, drop_axis=[1, 2],
                                   new_axis=[1], chunks=(whole_frames.chunks[0], (256,)))


def _block_histograms(block, *, mask, prepare, compiled, counts):
    return _frame_histograms(block, out=np.empty((len(block), 256), counts), prepare=prepare,
                             mask=mask, compiled=compiled)


def _frame_times(recording, n):
    if "time" in recording.coords:
        return np.asarray(recording["time"].values, dtype=float)
    spf = recording.attrs.get("seconds_per_frame")
    if spf is None:
        raise TactilecalError("recording has neither a time coordinate nor seconds_per_frame; "
                              "expected frame times to align the load record")
    return np.arange(n) * float(spf)


def _lag_on(total, times, loads, max_lag_s, near=None):
    """Lag of the load record against the frames' ``total`` signal (cross-correlation).

    ``near``: ``(lag_s, half_width_s)``, search within ``half_width_s`` of ``lag_s`` first
    (``near_lag_s`` of :func:`tactilecal.dynamic.estimate_lag`).

    Returns the lag and what :func:`tactilecal.dynamic.estimate_lag` warned (e.g. a lag
    made ambiguous by a periodic load; the warnings are passed on too).
    """
    from tactilecal.dynamic import estimate_lag

    sensor = xr.DataArray(total, dims="time", coords={"time": times}, name="total raw")
    near_lag_s, width_s = (None, None) if near is None else near
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        lag = float(estimate_lag(sensor, loads, method="xcorr", max_lag_s=max_lag_s,
                                 near_lag_s=near_lag_s, near_width_s=width_s))
    for w in caught:
        warnings.warn(w.message, w.category, stacklevel=3)
    return lag, "; ".join(str(w.message) for w in caught)


def _align_loads(loads, total, times, n, name, lag_s, max_lag_s, near=None):
    """Return the load on each frame (NaN outside the record) and an alignment report.

    ``near``: see :func:`_lag_on`.
    """
    if not isinstance(loads, xr.DataArray):
        loads = np.asarray(loads, dtype=float).ravel()
        if len(loads) != n:
            raise TactilecalError(f"loads have {len(loads)} values and no time column; expected "
                                  f"{n} (one per frame of {name}), as I-Scan's movie calibration")
        return loads, {"lag_s": None, "aligned": "one load per frame (no time column)"}
    note = ""
    if lag_s is None:
        lag_s, note = _lag_on(total, times, loads, max_lag_s, near)
    return (_loads_at(loads, times, lag_s),
            {"lag_s": lag_s, "aligned": "cross-correlation with the total raw signal",
             "lag_note": note})


def _loads_at(loads, times, lag_s):
    """Resample the load record onto ``times`` (:func:`tactilecal.dynamic.resample_to`).

    NaN at the times outside the record.
    """
    from tactilecal.dynamic import resample_to

    on_frames = resample_to(loads, times, lag_s=lag_s)
    load = np.full(len(times), np.nan)
    load[np.searchsorted(times, on_frames["time"].values)] = on_frames.values
    return load


def _mean_rate_hz(record):
    """Return the samples per second of a record's ``time`` coordinate (0 if none).

    Unchecked: :func:`tactilecal.dynamic.estimate_lag` checks the record and says what is
    wrong with it.
    """
    if "time" not in record.coords:
        return 0.0
    return _rate_hz(np.asarray(record["time"].values, dtype=float).ravel())


def _rate_hz(times):
    span = float(times[-1] - times[0]) if times.size > 1 else 0.0
    return (times.size - 1) / span if span > 0 else 0.0


def _decimated(total, times, rate_hz):
    """Block means of ``total`` and ``times`` down to no less than ``rate_hz`` (or as is)."""
    q = int(_rate_hz(times) / rate_hz * (1 + 1e-9)) if rate_hz > 0 else 0  # 4 kHz / 2 kHz: 2
    if q < 2 or len(total) // q < 64:
        return total, times
    m = len(total) // q * q
    return total[:m].reshape(-1, q).mean(axis=1), times[:m].reshape(-1, q).mean(axis=1)


def movie_points(recording, loads, *, lag_s=None, max_lag_s=None, mask=None,
                 equilibration=None, min_load_fraction=0.02, progress=None):
    """Make one calibration point per frame of a movie paired with a load-cell record.

    Parameters
    ----------
    recording : xarray.DataArray
        Raw movie (frame, row, col) with a ``time`` coordinate; uint8 values are fine.
    loads : xarray.DataArray or array_like
        Load-cell record in N with dim ``time`` (aligned and resampled), or one load per
        frame (no time: the counts must match).
    lag_s : float, optional
        Known lag (s to add to the load times); estimated by cross-correlation if None.
    max_lag_s : float, optional
        Bound on the cross-correlation lag search.
    mask : array_like of bool, optional
        Non-working sensels to leave out.
    equilibration : Equilibration, optional
        Gains applied to each frame first.
    min_load_fraction : float
        Frames whose load is below this fraction of the largest load are not made into
        points (unloaded stretches); they are counted in the report.
    progress : callable, optional
        ``progress(iterable, total=, desc=)`` wrapping the chunks of frames of long movies,
        e.g. a progress bar (see :mod:`tactilecal._progress`); None: no bar.

    Returns
    -------
    points : list of CalibrationPoint
    report : dict
        Lag, counts of frames outside the load record and below the load floor, and a text
        ``report``.

    Raises
    ------
    ValueError
        A count mismatch without a time column, records that do not overlap in time.
    """
    progress = resolve(progress)
    hist = _histograms(recording.data, None if mask is None else np.asarray(mask, bool),
                       equilibration, progress)
    return _points_from_movie(recording, hist, loads, lag_s=lag_s, max_lag_s=max_lag_s,
                              min_load_fraction=min_load_fraction)


def _frame_sums(hist):
    """Per-frame raw sum ``R_T`` and working, loaded and saturated sensels, from histograms.

    ``R_T = hist @ (0..255)`` (Zvyagin 2022, eq. 4) and the working count ``hist @ 1`` come
    from one product over the histograms (exact: integer sums below 2**53); loaded cells are
    the working ones minus bin 0, saturated cells bin 255.
    """
    raw_sum, working = hist_products(hist, np.column_stack([np.arange(256.0), np.ones(256)]))
    return {"raw_sum": raw_sum, "working_cells": working.astype(np.int64),
            "loaded_cells": (working - hist[:, 0]).astype(np.int64),
            "saturated_cells": hist[:, 255].astype(np.int64)}


def _movie_loads(recording, signal, loads, *, lag_s, max_lag_s, aligned_on="raw sum",
                 near=None):
    """Return each frame's load (NaN outside the record), aligned on ``signal``."""
    name = str(recording.attrs.get("source", "recording"))
    n = len(signal)
    load, report = _align_loads(loads, signal, _frame_times(recording, n), n, name, lag_s,
                                max_lag_s, near)
    report["aligned_on"] = aligned_on
    return load, report


def _movie_arrays(recording, hist, loads, *, lag_s, max_lag_s, min_load_fraction,
                  signal_N=None, sums=None, near=None, window=None):
    """Align the loads on ``hist @ signal_N`` (default: the raw sum) and keep the frames.

    Returns ``(hist, load, meta, report)`` of the frames kept as points. The kept rows are
    moved to the top of ``hist`` in place (``hist`` is not used afterwards), so the
    returned histograms are a view of it and no copy of the movie's histograms is made.
    ``sums`` are :func:`_frame_sums` of ``hist``, computed if not given; ``near``: the
    lag is searched near a known one first (:func:`_lag_on`). ``window``: ``(from_s, to_s,
    min_load_N)`` (each may be None), the frames to fit: within that time of the
    recording's clock and carrying at least that load (after the alignment, which uses the
    whole records).
    """
    name = str(recording.attrs.get("source", "recording"))
    n = len(hist)
    sums = _frame_sums(hist) if sums is None else sums
    signal = sums["raw_sum"] if signal_N is None else hist_products(hist, signal_N)[0]
    load, report = _movie_loads(recording, signal, loads, lag_s=lag_s, max_lag_s=max_lag_s,
                                aligned_on="raw sum" if signal_N is None else
                                "calibrated force", near=near)
    outside = ~np.isfinite(load)
    low = ~outside & (load < min_load_fraction * np.nanmax(load))
    from_s, to_s, min_load_N = (None, None, None) if window is None else window
    times = _frame_times(recording, n)
    excluded = np.zeros(n, dtype=bool)
    if from_s is not None:
        excluded |= times < from_s
    if to_s is not None:
        excluded |= times > to_s
    if min_load_N is not None:
        excluded |= ~outside & (load < min_load_N)
    excluded &= ~outside & ~low
    keep = ~outside & ~low & ~excluded
    frames = (recording["frame"].values if "frame" in recording.coords
              else np.arange(1, n + 1))
    kept = keep_rows_in_place(hist, keep)
    m = len(kept)
    meta = {"file": _repeated(Path(name).name, m), "frame": frames[keep],
            "raw_sum": sums["raw_sum"][keep], "loaded_cells": sums["loaded_cells"][keep],
            "saturated_cells": sums["saturated_cells"][keep],
            "label": _repeated("", m), "note": _repeated("", m),
            "sensel_area_mm2": np.full(m, float(recording.attrs.get("sensel_area_mm2",
                                                                     np.nan))),
            "working_cells": sums["working_cells"][keep],
            "total_cells": np.full(m, int(np.isfinite(np.asarray(recording.data[0],
                                                                 dtype=float)).sum()))}
    report.update({
        "n_frames": n, "n_points": m, "n_outside_load_record": int(outside.sum()),
        "n_below_load_floor": int(low.sum()), "min_load_fraction": min_load_fraction,
        "n_outside_window": int(excluded.sum()),
        "window": {"from_s": from_s, "to_s": to_s, "min_load_N": min_load_N},
        "n_saturated_frames": int((meta["saturated_cells"] > 0).sum()),
    })
    lag_txt = "none" if report["lag_s"] is None else f"{report['lag_s']:.6g} s"
    report["report"] = (
        f"movie {name}: {n} frames, lag {lag_txt} ({report['aligned']}, on the "
        f"{report['aligned_on']}); {report['n_outside_load_record']} frames outside the load "
        f"record and {report['n_below_load_floor']} below {min_load_fraction:.0%} of the "
        f"largest load left out"
        + (f", {report['n_outside_window']} outside the window asked for" if window else "")
        + f"; {m} points, of which {report['n_saturated_frames']} have saturated sensels")
    return kept, load[keep], meta, report


def _repeated(text, m):
    """Return an object array of ``m`` references to ``text``.

    ``np.full(m, text, dtype=object)`` makes a new string per element; this copies one
    reference.
    """
    out = np.empty(m, dtype=object)
    out.fill(text)
    return out


def _points_from_movie(recording, hist, loads, **kwargs):
    """Like :func:`_movie_arrays` but returning CalibrationPoint objects."""
    kept, load, meta, report = _movie_arrays(recording, hist, loads, **kwargs)
    some = len(load) > 0
    points = _points_from_histograms(
        kept.astype(np.int64), load, source=meta["file"][0] if some else "",
        labels=meta["label"], frames=meta["frame"],
        sensel_area_mm2=meta["sensel_area_mm2"][0] if some else np.nan,
        total_cells=meta["total_cells"][0] if some else 0)
    return points, report


def _first_pass(recording, hist, raw_sum, loads, setup, min_load_fraction, max_lag_s,
                max_points=_FIRST_PASS_POINTS):
    """Align on the raw sum and fit the table that shapes the second alignment's signal.

    Neither needs the frame rate: the lag is estimated on the raw sum block-averaged to no
    less than ``4 x`` the load record's rate (:func:`_decimated`), and the loads are
    resampled onto, and fitted on, at most ``max_points`` frames evenly spread over the
    movie. The second alignment (:func:`_movie_arrays`) works at the frame rate.

    Returns
    -------
    signal_N : numpy.ndarray
        The first fit's force table (256,).
    fit : Fit
    report : dict
        ``{"lag_s": ..., "near": (lag_s, half_width_s)}`` of the first alignment: the second
        searches within ``NEAR_BLOCKS`` decimation blocks of it first (:func:`_lag_on`).
    """
    n = len(raw_sum)
    times = _frame_times(recording, n)
    total, block_times = _decimated(raw_sum, times, 4.0 * _mean_rate_hz(loads))
    lag_s, note = _lag_on(total, block_times, loads, max_lag_s)
    step = max(1, n // max_points)
    load = _loads_at(loads, times[::step], lag_s)
    rate_hz = _rate_hz(times)
    near = (lag_s, NEAR_BLOCKS * (n // len(total)) / rate_hz) if rate_hz > 0 else None
    return (*_first_pass_table(hist[::step], load, setup, min_load_fraction),
            {"lag_s": lag_s, "near": near, "lag_note": note})


def _first_pass_table(hist, load, setup, min_load_fraction):
    """Fit on arrays to get a force table for the second alignment.

    It only has to make the alignment signal proportional to the load; ``hist`` and
    ``load`` are those of a few thousand frames (:func:`_first_pass`).
    """
    module, common, options = setup
    if module.NAME in ("zvyagin", "auto"):  # power shapes the alignment signal as well
        module, options = MODULES["power"], MODULES["power"].Options()
    if module.NAME != "power" or len(hist) < COMPILED_MIN_POINTS:  # power: products of counts
        hist = hist.astype(float)
    keep = np.isfinite(load)
    keep[keep] = load[keep] >= min_load_fraction * load[keep].max()
    keep &= hist[:, 1:].any(axis=1)
    if common.saturated == "drop":
        keep &= hist[:, 255] == 0
    fit = module.fit(FitData(hist[keep], load[keep]), options)
    return force_table(fit.model, fit.params), fit


def _load_record(loads, time_col, load_col):
    """Return a load record given as a DataFrame of (time, load) as a DataArray in N.

    The units come from the column names (``Time (ms)``, ``Load (lbf)``); a column without
    a unit is taken as seconds or newtons. Other inputs are returned unchanged.
    """
    if not isinstance(loads, pd.DataFrame):
        return loads
    from tactilecal._units import force_to_N, mass_to_N, time_to_s, unit_from_column, unit_kind

    columns = [str(c) for c in loads.columns]
    if len(columns) != 2 and (time_col is None or load_col is None):
        raise TactilecalError(f"loads is a DataFrame with columns {columns}; expected two "
                              "columns (time, load) or time_col= and load_col=")
    t_name = columns[0] if time_col is None else str(time_col)
    v_name = columns[1] if load_col is None else str(load_col)
    for name in (t_name, v_name):
        if name not in columns:
            raise TactilecalError(f"column {name!r} is not in the loads DataFrame; expected "
                                  f"one of {columns}")
    t_unit = unit_from_column(t_name, where=f"column {t_name!r} of the loads") or "s"
    v_unit = unit_from_column(v_name, where=f"column {v_name!r} of the loads") or "N"
    times = time_to_s(pd.to_numeric(loads[t_name]).to_numpy(float), t_unit)
    values = pd.to_numeric(loads[v_name]).to_numpy(float)
    kind = unit_kind(v_unit)
    if kind not in ("force", "mass"):
        raise TactilecalError(f"column {v_name!r} of the loads is in {v_unit!r}; expected a "
                              "force or mass unit")
    values = force_to_N(values, v_unit) if kind == "force" else mass_to_N(values, v_unit)
    return xr.DataArray(values, dims="time", coords={"time": times}, name=v_name,
                        attrs={"units": "N", "source": "DataFrame"})


def _with_learned_gains(recording, kept, load, meta, dead, equilibration, progress, compiled):
    """Learn gains on up to ``MAX_PATCHES`` kept frames; count every frame again with them.

    Returns the kept frames' histograms, the equilibration to apply (the given one, then the
    learned gains) and the learning's record.
    """
    from tactilecal.calibration._gains import MAX_PATCHES, learn_gains

    numbers = pd.Index(recording["frame"].values if "frame" in recording.coords
                       else np.arange(1, recording.shape[0] + 1))
    positions = numbers.get_indexer(meta["frame"])
    sample = np.linspace(0, len(positions) - 1, min(len(positions), MAX_PATCHES)).astype(int)
    frames = np.asarray(recording.data[np.sort(positions[sample])], dtype=float)
    order = np.argsort(np.argsort(positions[sample]))  # back to the sample's order
    frames = frames[order]
    if dead is not None:
        frames[:, dead.mask] = np.nan
    if equilibration is not None:
        frames = equilibration.apply(frames)
    gains, record = learn_gains(frames, load[sample], meta["saturated_cells"][sample] == 0,
                                where=str(recording.attrs.get("source", "the movie")))
    if gains is None:
        return kept, equilibration, record
    combined = chain(equilibration, gains)
    hist = _histograms(recording.data, None if dead is None else dead.mask, combined, progress,
                       compiled)
    return hist[positions], combined, record


def calibrate_movie(recording, loads, *, method=DEFAULT_METHOD, time_col=None, load_col=None,
                    lag_s=None, max_lag_s=None, mask_dead=False, equilibration=None,
                    min_load_fraction=0.02, from_s=None, to_s=None, min_load_N=None,
                    progress=None, **options):
    """Movie calibration: align, resample, trim saturated frames, fit every frame.

    Parameters
    ----------
    recording : str, os.PathLike or xarray.DataArray
        Raw movie (a path is read with :func:`tactilecal.io.open_recording`).
    loads : str, os.PathLike, xarray.DataArray, pandas.DataFrame or array_like
        Load-cell record: a CSV path (read with :func:`read_movie_loads`), a time series
        (DataArray along ``time`` in N, or a DataFrame of time and load columns, units in
        their names), or one load per frame in N (I-Scan's movie calibration).
    method : str
        Calibration method (see :func:`calibrate`).
    time_col, load_col : str or int, optional
        Columns of the load-cell CSV or DataFrame.
    lag_s, max_lag_s, min_load_fraction, progress
        See :func:`movie_points`. A periodic load (a gait cycle) correlates almost as well
        a whole period away: of near-equal correlation peaks the lag that overlaps the
        records most is taken, with a warning that gives the others.
    from_s, to_s : float, optional
        Fit only the frames between these times of the recording's clock (e.g. the
        stance phases of a gait trial, or the steady part of a run); the alignment uses the
        whole records.
    min_load_N : float, optional
        Fit only the frames carrying at least this load (e.g. stance, not swing).
    mask_dead : bool
        Detect non-working sensels over the movie (:func:`find_dead_sensels`) and mask them.
    equilibration : Equilibration, str or os.PathLike, optional
        Per-sensel gains (or the path of their JSON) applied to every frame first.
    **options
        The options of :func:`calibrate` (saturated frames are left out by default).

    Returns
    -------
    CalibrationResult
        With ``diagnostics["movie"]`` holding the alignment report (also in
        :meth:`CalibrationResult.summary`). With a load record and no ``lag_s``, the loads
        are aligned twice: first on the raw sum (``lag_s_raw_sum``, estimated on the raw sum
        block-averaged to at least 4 x the load record's rate), then, at the frame rate, on
        the force of a first fit (``first_pass_params``) to at most 5000 frames, over the
        lags within ``NEAR_BLOCKS`` (16) decimation blocks of the first lag (over every lag
        if the correlation peaks at that window's edge).

    Raises
    ------
    TactilecalError
        A recording that is not raw, loads that cannot be paired with the frames, a bad
        option, and every error of :func:`calibrate`.

    Examples
    --------
    >>> from tactilecal.simulate import make_sensor, ramp_hold
    >>> sensor = make_sensor("9500", seed=1)  # A_N = 0.0035, b = 1.16
    >>> session = ramp_hold(sensor, loads_N=(100.0, 200.0, 300.0), hold_s=1.0, ramp_s=1.0,
    ...                     seed=1)  # the load cell starts 0.37 s after the sensor
    >>> cal = calibrate_movie(session.raw, session.loadcell, method="power")
    >>> round(cal.params["b"], 2), round(cal.diagnostics["movie"]["lag_s"], 2)
    (1.16, 0.37)
    """
    setup = method_options(method, options)  # before anything is read
    module, common, method_opts = setup
    equilibration = as_equilibration(equilibration)  # the object, or its JSON's path
    if not isinstance(recording, xr.DataArray):
        from tactilecal.io import open_recording

        recording = open_recording(recording)
    if recording.attrs.get("units", "raw") != "raw":
        raise TactilecalError(f"recording {recording.attrs.get('source', '')!r} has units "
                              f"{recording.attrs['units']!r}; expected raw readings")
    files = [loads] if isinstance(loads, str | Path) else []
    if files:
        loads = read_movie_loads(loads, time_col=time_col, load_col=load_col)
    loads = _load_record(loads, time_col, load_col)
    dead = find_dead_sensels(recording.data) if mask_dead else None  # dask: streamed
    fits_compiled = module.NAME in ("power", "piecewise") and \
        recording.sizes[recording.dims[0]] >= COMPILED_MIN_POINTS  # fit_power's kernels
    hist = _histograms(recording.data, None if dead is None else dead.mask, equilibration,
                       resolve(progress), fits_compiled)
    sums = _frame_sums(hist)
    signal_N, first = None, None
    if lag_s is None and isinstance(loads, xr.DataArray):
        # The raw sum is not proportional to the load (b != 1): align on it, fit, then
        # align again on the force that fit gives (Gillis 2013 aligns force on force).
        signal_N, first, first_report = _first_pass(recording, hist, sums["raw_sum"], loads,
                                                    setup, min_load_fraction, max_lag_s)
    window = None if from_s is None and to_s is None and min_load_N is None \
        else (from_s, to_s, min_load_N)
    kept, load, meta, report = _movie_arrays(
        recording, hist, loads, lag_s=lag_s, max_lag_s=max_lag_s,
        min_load_fraction=min_load_fraction, signal_N=signal_N, sums=sums,
        near=None if first is None else first_report["near"], window=window)
    gains_record = None
    if common.gains == "learn":  # learned on a sample of the frames, applied to every one
        kept, equilibration, gains_record = _with_learned_gains(
            recording, kept, load, meta, dead, equilibration, resolve(progress), fits_compiled)
        common = dataclasses.replace(common, gains="none")
    if module.NAME != "power":  # the power fit reads counts (hist_products); others floats
        kept = kept.astype(float)
    result = fit_arrays(kept, load, meta, module=module, common=common, options=method_opts)
    if gains_record is not None:
        result.diagnostics["gains"] = gains_record
    if first is not None:
        report["lag_s_raw_sum"] = first_report["lag_s"]
        report["lag_note"] = first_report["lag_note"] or report.get("lag_note", "")
    if report.get("lag_note"):
        report["report"] += "; the lag is ambiguous (a periodic load): see lag_note"
        report["first_pass_params"] = first.params
        if "n_evaluations" in result.diagnostics:
            result.diagnostics["n_evaluations"] += first.diagnostics.get("n_evaluations", 0)
    result.diagnostics["movie"] = report
    result.equilibration, result.non_working = equilibration, dead
    result.provenance = provenance_of([recording, loads], files=files)
    return result
