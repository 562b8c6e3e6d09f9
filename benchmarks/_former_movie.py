"""``calibrate_movie`` as it was on main at bbea5f0 (session 7), the benchmark's "former".

A copy of that commit's ``tactilecal/calibration/_movie.py`` (the calibration path: the
float64 histograms, two alignments at the frame rate, the first-pass table) and of the
power fit's search for many points in ``tactilecal/_powerfit.py`` (13-exponent nested grids,
Chebyshev moments over the first grid's bracket from BLAS products).
:func:`calibrate_movie` runs it with the package's ``_minimise_b_many`` replaced by that
copy; everything else (the histogram kernels, ``dynamic``, ``calibrate_arrays``) is today's.
Methods outside ``FITTERS`` (zvyagin) are not copied.
"""

from pathlib import Path

import numpy as np
import xarray as xr
from scipy import optimize

import tactilecal._powerfit as powerfit
from tactilecal._powerfit import (
    COMPILED_MIN_POINTS,
    LEVELS,
    _chebyshev_basis,
    _chebyshev_t,
    _check_interior,
    _costs_many,
    _median_window,
    objective_weights,
)
from tactilecal._progress import from_quiet
from tactilecal._provenance import provenance_of
from tactilecal._saturation import resolve_saturated
from tactilecal.calibration._calibrate import calibrate_arrays
from tactilecal.calibration._methods import FITTERS
from tactilecal.calibration._models import force_table
from tactilecal.calibration._movie import read_movie_loads
from tactilecal.calibration._pipeline import as_equilibration
from tactilecal.calibration._points import _frame_histograms, keep_rows_in_place
from tactilecal.calibration._sensels import find_dead_sensels

_CHUNK = 2048
_GROUP_FRAMES = 16 * _CHUNK


def calibrate_movie(recording, loads, **kwargs):
    """The former ``calibrate_movie`` (bbea5f0), its power fits by the former search."""
    saved = powerfit._minimise_b_many
    powerfit._minimise_b_many = _former_minimise_b_many
    try:
        return _calibrate_movie(recording, loads, **kwargs)
    finally:
        powerfit._minimise_b_many = saved


def _histograms(values, mask, equilibration, progress, numba_loaded=False):
    """Float64 histograms of all frames (gains applied and mask skipped chunk by chunk).

    ``numba_loaded``: the caller will import numba anyway (a power fit of
    ``COMPILED_MIN_POINTS`` frames or more), so its start-up no longer speaks against the
    compiled counting of a movie below ``COMPILED_MIN_VALUES`` readings.

    Float64 because every later use is a matrix product; counts are exact in float64.
    ``values`` may be a dask array (a recording larger than memory, perhaps on a cluster):
    each block of frames is counted where it is computed, by dask's scheduler, and only the
    (frames, 256) histograms are gathered. ``progress`` (the protocol of
    :mod:`tactilecal._progress`) wraps the chunks of movies of ``20 * _CHUNK`` frames or more.
    """
    from tactilecal.calibration._histogram import COMPILED_MIN_VALUES

    prepare = None if equilibration is None else equilibration.apply
    n = len(values)
    hist = np.empty((n, 256))
    compiled = numba_loaded or values.size >= COMPILED_MIN_VALUES  # the whole movie decides
    if _is_dask(values):
        import dask.array as da

        lazy = _dask_histograms(values, mask, prepare, compiled)
        bounds = _block_groups(values.chunks[0], _GROUP_FRAMES)
    else:
        bounds = [*range(0, n, _CHUNK), n]
    spans = zip(bounds[:-1], bounds[1:], strict=True)
    if n >= 20 * _CHUNK:
        spans = progress(spans, total=len(bounds) - 1, desc="histograms")
    for a, b in spans:
        if _is_dask(values):
            da.store(lazy[a:b], hist[a:b], lock=False)
        else:
            _frame_histograms(values[a:b], out=hist[a:b], prepare=prepare, mask=mask,
                              compiled=compiled)
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
    """Lazy (frames, 256) float64 histograms, one task per block of whole frames."""
    whole_frames = values.rechunk({1: -1, 2: -1})
    return whole_frames.map_blocks(_block_histograms, mask=mask, prepare=prepare,
                                   compiled=compiled, drop_axis=[1, 2], new_axis=[1],
                                   chunks=(whole_frames.chunks[0], (256,)), dtype=float)


def _block_histograms(block, *, mask, prepare, compiled):
    return _frame_histograms(block, out=np.empty((len(block), 256)), prepare=prepare,
                             mask=mask, compiled=compiled)


def _frame_times(recording, n):
    if "time" in recording.coords:
        return np.asarray(recording["time"].values, dtype=float)
    spf = recording.attrs.get("seconds_per_frame")
    if spf is None:
        raise ValueError("recording has neither a time coordinate nor seconds_per_frame; "
                         "expected frame times to align the load record")
    return np.arange(n) * float(spf)


def _align_loads(loads, total, times, n, name, lag_s, max_lag_s):
    """Return the load on each frame (NaN outside the record) and an alignment report."""
    from tactilecal.dynamic import estimate_lag, resample_to

    if not isinstance(loads, xr.DataArray):
        loads = np.asarray(loads, dtype=float).ravel()
        if len(loads) != n:
            raise ValueError(f"loads have {len(loads)} values and no time column; expected "
                             f"{n} (one per frame of {name}), as I-Scan's movie calibration")
        return loads, {"lag_s": None, "aligned": "one load per frame (no time column)"}
    sensor = xr.DataArray(total, dims="time", coords={"time": times}, name="total raw")
    if lag_s is None:
        lag_s = float(estimate_lag(sensor, loads, method="xcorr", max_lag_s=max_lag_s))
    on_frames = resample_to(loads, times, lag_s=lag_s)
    load = np.full(n, np.nan)
    load[np.searchsorted(times, on_frames["time"].values)] = on_frames.values
    return load, {"lag_s": lag_s, "aligned": "cross-correlation with the total raw signal"}


def _frame_sums(hist):
    """Per-frame raw sum ``R_T`` and working, loaded and saturated sensels, from histograms.

    ``R_T = hist @ (0..255)`` (Zvyagin 2022, eq. 4) and the working count ``hist @ 1`` come
    from one product over the histograms (exact: integer sums below 2**53); loaded cells are
    the working ones minus bin 0, saturated cells bin 255.
    """
    both = hist @ np.column_stack([np.arange(256.0), np.ones(256)])
    working = both[:, 1]
    return {"raw_sum": both[:, 0], "working_cells": working.astype(np.int64),
            "loaded_cells": (working - hist[:, 0]).astype(np.int64),
            "saturated_cells": hist[:, 255].astype(np.int64)}


def _movie_loads(recording, signal, loads, *, lag_s, max_lag_s, aligned_on="raw sum"):
    """Return each frame's load (NaN outside the record), aligned on ``signal``."""
    name = str(recording.attrs.get("source", "recording"))
    n = len(signal)
    load, report = _align_loads(loads, signal, _frame_times(recording, n), n, name, lag_s,
                                max_lag_s)
    report["aligned_on"] = aligned_on
    return load, report


def _movie_arrays(recording, hist, loads, *, lag_s, max_lag_s, min_load_fraction,
                  signal_N=None, sums=None):
    """Align the loads on ``hist @ signal_N`` (default: the raw sum) and keep the frames.

    Returns ``(hist, load, meta, report)`` of the frames kept as points. The kept rows are
    moved to the top of ``hist`` in place (``hist`` is not used afterwards), so the
    returned histograms are a view of it and no copy of the movie's histograms is made.
    ``sums`` are :func:`_frame_sums` of ``hist``, computed if not given.
    """
    name = str(recording.attrs.get("source", "recording"))
    n = len(hist)
    sums = _frame_sums(hist) if sums is None else sums
    signal = sums["raw_sum"] if signal_N is None else hist @ signal_N
    load, report = _movie_loads(recording, signal, loads, lag_s=lag_s, max_lag_s=max_lag_s,
                                aligned_on="raw sum" if signal_N is None else
                                "calibrated force")
    outside = ~np.isfinite(load)
    low = ~outside & (load < min_load_fraction * np.nanmax(load))
    keep = ~outside & ~low
    frames = (recording["frame"].values if "frame" in recording.coords
              else np.arange(1, n + 1))
    kept = keep_rows_in_place(hist, keep)
    m = len(kept)
    meta = {"file": np.full(m, Path(name).name, dtype=object), "frame": frames[keep],
            "raw_sum": sums["raw_sum"][keep], "loaded_cells": sums["loaded_cells"][keep],
            "saturated_cells": sums["saturated_cells"][keep],
            "label": np.full(m, "", dtype=object),
            "note": np.full(m, "", dtype=object),
            "sensel_area_mm2": np.full(m, float(recording.attrs.get("sensel_area_mm2",
                                                                     np.nan))),
            "working_cells": sums["working_cells"][keep],
            "total_cells": np.full(m, int(np.isfinite(np.asarray(recording.data[0],
                                                                 dtype=float)).sum()))}
    report.update({
        "n_frames": n, "n_points": m, "n_outside_load_record": int(outside.sum()),
        "n_below_load_floor": int(low.sum()), "min_load_fraction": min_load_fraction,
        "n_saturated_frames": int((meta["saturated_cells"] > 0).sum()),
    })
    lag_txt = "none" if report["lag_s"] is None else f"{report['lag_s']:.6g} s"
    report["report"] = (
        f"movie {name}: {n} frames, lag {lag_txt} ({report['aligned']}, on the "
        f"{report['aligned_on']}); {report['n_outside_load_record']} frames outside the load "
        f"record and {report['n_below_load_floor']} below {min_load_fraction:.0%} of the "
        f"largest load left out; {m} points, of which "
        f"{report['n_saturated_frames']} have saturated sensels")
    return kept, load[keep], meta, report


def _first_pass_table(hist, load, method, options, min_load_fraction, max_points=5000):
    """Fit on arrays to get a force table for the second alignment.

    It only has to make the alignment signal proportional to the load, so it uses at most
    ``max_points`` frames evenly spread over the movie.
    """
    step = max(1, len(load) // max_points)
    hist, load = hist[::step], load[::step]
    keep = np.isfinite(load)
    keep[keep] = load[keep] >= min_load_fraction * load[keep].max()
    keep &= hist[:, 1:].any(axis=1)
    if resolve_saturated(options.get("saturated"), options.get("keep_saturated")) == "drop":
        keep &= hist[:, 255] == 0
    generic = {"saturated", "keep_saturated", "scale_by_working", "n_bootstrap", "seed",
               "sensel_area_mm2"}
    fit = FITTERS[method](hist[keep], load[keep],
                          **{k: v for k, v in options.items() if k not in generic})
    return force_table(fit.model, fit.params), fit


def _calibrate_movie(recording, loads, *, method="power", time_col=None, load_col=None,
                    lag_s=None, max_lag_s=None, mask_dead=False, equilibration=None,
                    min_load_fraction=0.02, progress=None, quiet=None, **options):
    """Movie calibration: align, resample, trim saturated frames, fit every frame.

    ``equilibration`` may also be the path of an equilibration JSON.

    Parameters
    ----------
    recording : str, os.PathLike or xarray.DataArray
        Raw movie (a path is read with :func:`tactilecal.io.open_recording`).
    loads : str, os.PathLike, xarray.DataArray or array_like
        Load-cell record (a path is read with :func:`read_movie_loads`).
    method : str
        Calibration method (see :func:`calibrate`).
    time_col, load_col : str or int, optional
        Columns of the load-cell CSV.
    lag_s, max_lag_s, equilibration, min_load_fraction, progress, quiet
        See :func:`movie_points`.
    mask_dead : bool
        Detect non-working sensels over the movie (:func:`find_dead_sensels`) and mask them.
    **options
        Passed to :func:`calibrate` (saturated frames are left out unless
        ``keep_saturated=True``).

    Returns
    -------
    CalibrationResult
        With ``details["movie"]`` holding the alignment report.
    """
    equilibration = as_equilibration(equilibration)  # the object, or its JSON's path
    if not isinstance(recording, xr.DataArray):
        from tactilecal.io import open_recording

        recording = open_recording(recording)
    if recording.attrs.get("units", "raw") != "raw":
        raise ValueError(f"recording {recording.attrs.get('source', '')!r} has units "
                         f"{recording.attrs['units']!r}; expected raw readings")
    files = [loads] if isinstance(loads, str | Path) else []
    if files:
        loads = read_movie_loads(loads, time_col=time_col, load_col=load_col)
    dead = find_dead_sensels(recording.data) if mask_dead else None  # dask: streamed
    fits_compiled = method in ("power", "piecewise") and \
        recording.sizes[recording.dims[0]] >= COMPILED_MIN_POINTS  # fit_power's kernels
    hist = _histograms(recording.data, None if dead is None else dead.mask, equilibration,
                       from_quiet(progress, quiet, "calibrate_movie"), fits_compiled)
    sums = _frame_sums(hist)
    signal_N, first = None, None
    if lag_s is None and isinstance(loads, xr.DataArray) and method in FITTERS:
        # The raw sum is not proportional to the load (b != 1): align on it, fit, then
        # align again on the force that fit gives (Gillis 2013 aligns force on force).
        load, first_report = _movie_loads(recording, sums["raw_sum"], loads, lag_s=None,
                                          max_lag_s=max_lag_s)
        signal_N, first = _first_pass_table(hist, load, method, options, min_load_fraction)
    kwargs = {"lag_s": lag_s, "max_lag_s": max_lag_s, "min_load_fraction": min_load_fraction,
              "signal_N": signal_N, "sums": sums}
    if method in FITTERS:
        kept, load, meta, report = _movie_arrays(recording, hist, loads, **kwargs)
        result = calibrate_arrays(kept, load, meta, method=method, **options)
    else:  # e.g. zvyagin: not timed here
        raise ValueError(f"former calibrate_movie is kept for FITTERS only, not {method!r}")
    if first is not None:
        report["lag_s_raw_sum"] = first_report["lag_s"]
        report["first_pass_params"] = first.params
        if "n_evaluations" in result.details:
            result.details["n_evaluations"] += first.details.get("n_evaluations", 0)
    result.details["movie"] = report
    if dead is not None:
        result.details["non_working_sensels"] = dead.to_dict()
    if equilibration is not None:
        result.details["equilibration"] = equilibration.to_dict()
    result.provenance = provenance_of([recording, loads], files=files)
    return result


# ---- tactilecal/_powerfit.py at bbea5f0: the search for many points
class _Sums:
    """``S_T(b)`` (Zvyagin 2022, eq. 2) for exponents in a bracket, from one product.

    ``hist @ coef`` of :func:`_chebyshev_basis` reads the histograms once; every later
    ``S_T(b) = hist @ LEVELS**b`` in the bracket is then a product with ``T(t(b))``, of
    about 20 rather than 256 terms, equal to the direct sum to round-off.
    """

    def __init__(self, hist, lo, hi):
        coef, self.mid, self.half = _chebyshev_basis(lo, hi)
        self.moments = coef.T @ hist.T  # (J, n)

    def __call__(self, b_values, slope=False):
        """(m, n) sums at ``b_values`` (and their derivatives in b if ``slope``)."""
        from tactilecal._powerfit_kernels import series_sums

        T, dT = _chebyshev_t((np.asarray(b_values) - self.mid) / self.half,
                             self.moments.shape[0])
        sums = series_sums(self.moments, T)
        return (sums, series_sums(self.moments, dT) / self.half) if slope else sums


def _former_minimise_b_many(hist, load_N, objective, b_bounds, n_grid, xtol, censored):
    """:func:`_minimise_b` reading the histograms twice, whatever the number of rounds.

    The same rounds as :func:`_minimise_b`: the first grid over ``b_bounds`` with
    ``hist @ LEVELS**b``; every later exponent lies in that grid's bracket, where
    :class:`_Sums` gives ``S_T(b)`` from one more product. l1 medians are selected, not
    sorted (:mod:`tactilecal._powerfit_kernels`). Same results as the direct sums to
    round-off (``tests/test_powerfit_many.py``).
    """
    lo, hi = (float(v) for v in b_bounds)
    grid = np.linspace(lo, hi, n_grid)
    cost, A = _costs_many((LEVELS[:, None] ** grid).T @ hist.T, load_N, objective, censored)
    k = int(np.nanargmin(cost))
    _check_interior(k, grid, b_bounds)
    lo, hi, n_eval = grid[k - 1], grid[k + 1], n_grid
    sums_at = _Sums(hist, lo, hi)
    if objective == "l1":
        while hi - lo > xtol:
            last, last_A, grid = grid, A, np.linspace(lo, hi, n_grid)
            cost, A = _costs_many(sums_at(grid), load_N, objective, censored,
                                  _median_window(grid, last, last_A))
            k, n_eval = int(np.nanargmin(cost)), n_eval + n_grid
            lo, hi = grid[max(k - 1, 0)], grid[min(k + 1, n_grid - 1)]
        b = float(grid[k])
    else:
        w2 = objective_weights(load_N, objective) ** 2

        def slope(x):  # _cost_slope on the bracket's sums
            (S,), (dS,) = sums_at([x], slope=True)
            p, q = np.sum(w2 * S * load_N), np.sum(w2 * S * S)
            dp, dq = np.sum(w2 * dS * load_N), 2.0 * np.sum(w2 * dS * S)
            return -(2.0 * p * dp * q - p * p * dq) / (q * q)

        if slope(lo) < 0 < slope(hi):
            b, info = optimize.brentq(slope, lo, hi, xtol=xtol, full_output=True)
            n_eval += 2 + info.function_calls
        else:
            b = float(grid[k])
    window = _median_window([b], grid, A) if objective == "l1" else None
    cost, A = _costs_many(sums_at([b]), load_N, objective, censored, window)
    return float(b), float(A[0]), float(cost[0]), n_eval + 1


