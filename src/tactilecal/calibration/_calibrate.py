"""``calibrate``: choose the points, run a method, build the result; ``validate``."""

import os
from pathlib import Path

import numpy as np
import pandas as pd

from tactilecal._errors import TactilecalError
from tactilecal._powerfit import NO_STDERR, hist_products
from tactilecal._provenance import provenance
from tactilecal._saturation import resolve_saturated
from tactilecal._units import N_PER_MM2_TO_KPA
from tactilecal.calibration._manifest import load_points
from tactilecal.calibration._methods import FITTERS, check_unsaturated, fit_censored
from tactilecal.calibration._models import force_table
from tactilecal.calibration._pipeline import (
    is_path,
    manifest_points,
    reading_options,
    record_preprocessing,
)
from tactilecal.calibration._points import points_to_arrays, take_rows
from tactilecal.calibration._result import CalibrationResult
from tactilecal.calibration._sensels import Equilibration
from tactilecal.calibration._uncertainty import PredictionInterval, bootstrap_refits
from tactilecal.calibration._validation import ValidationResult

__all__ = ["METHODS", "META_COLUMNS", "calibrate", "calibrate_arrays", "make_result",
           "point_meta", "result_from_arrays", "select_points", "validate"]

METHODS = (*FITTERS, "zvyagin")
SCALABLE = ("linear", "power-2pt")  # I-Scan-style methods offering the working/all scaling


def select_points(points, *, keep_saturated=False):
    """Decide which points a fit may use and why the others may not.

    Returns
    -------
    used : numpy.ndarray of bool
    reasons : list of str
        ``""`` for a used point, else why it was left out.
    """
    meta = point_meta(points)
    used, reasons = _select(np.array([p.load_N for p in points], dtype=float), meta,
                            keep_saturated)
    return used, list(reasons)


def _select(load, meta, keep_saturated):
    """Vectorised point selection: (used, reasons as an object array)."""
    reasons = np.full(len(load), "", dtype=object)
    sat = meta["saturated_cells"]
    if not keep_saturated:
        bad = sat > 0
        reasons[bad] = [f"saturated: {k} sensels at 255, left out (the saturated option "
                        "'censored' or 'keep' uses it)" for k in sat[bad]]
    empty = meta["loaded_cells"] == 0
    reasons[empty] = "no loaded sensels (raw > 0)"
    bad_load = ~(np.isfinite(load) & (load > 0))
    reasons[bad_load] = [f"load_N = {v} is not a positive load" for v in load[bad_load]]
    return reasons == "", reasons


META_COLUMNS = ("file", "frame", "raw_sum", "loaded_cells", "saturated_cells", "label", "note",
                "sensel_area_mm2", "working_cells", "total_cells")


def point_meta(points):
    """Per-point columns of a list of points as arrays (see :data:`META_COLUMNS`)."""
    attrs = {"file": "source"}
    return {c: np.array([getattr(p, attrs.get(c, c)) for p in points]) for c in META_COLUMNS}


def calibrate(points, method="power", *, equilibration=None, mask=None, progress=None,
              **options):
    """Fit a static calibration to calibration points, or to a manifest's frames.

    Parameters
    ----------
    points : sequence of CalibrationPoint, str or os.PathLike
        From :func:`load_points`, :func:`points_from_frames` or :func:`calibrate_movie`;
        or the path of a manifest CSV, whose frames are then read with ``equilibration``
        and ``mask`` applied (what ``tactilecal calibrate MANIFEST`` does).
    method : str
        ``"linear"`` (I-Scan 1-point / through zero), ``"power-2pt"`` (I-Scan 2-point power
        law on the mean raw reading), ``"power"`` (multi-point power law over every sensel,
        option ``objective`` in ``"l2"``, ``"l1"``, ``"relative"``), ``"linear-offset"``
        (Paikowsky & Hajduk), ``"piecewise"`` (power law per raw range, option ``knots``),
        ``"lut"`` (monotone lookup table, option ``knots``), ``"polynomial"`` (option
        ``degree``), ``"zvyagin"`` (Zvyagin 2022, :func:`tactilecal.zvyagin.zvyagin_fit` on
        the points; the result's ``method_result`` is its
        :class:`tactilecal.zvyagin.ZvyaginResult`).
    equilibration : Equilibration, str or os.PathLike, optional
        Manifest only: per-sensel gains (or the path of their JSON) applied to every frame
        before it is counted (Gillis 2013, sec. 3.5); stored in
        ``details["equilibration"]`` so that :meth:`CalibrationResult.apply` applies them
        to a recording too.
    mask : {"detect"}, NonWorkingSensels or array_like of bool, optional
        Manifest only: non-working sensels to leave out; ``"detect"`` finds them over the
        manifest's frames (:func:`find_dead_sensels`, ``--mask-dead`` of the CLI). Stored
        in ``details["non_working_sensels"]`` and masked by ``apply``.
    progress : callable, optional
        Manifest only: ``progress(iterable, total=, desc=)`` wrapping the reading of long
        manifests, e.g. a progress bar (default None: none).
    **options
        ``saturated`` (``"drop"``, the default of :mod:`tactilecal._saturation`: points
        with sensels at 255 are left out and reported; ``"keep"``; ``keep_saturated`` is
        the older spelling), ``scale_by_working`` (``linear``/``power-2pt``: multiply each load by
        working / all sensels, thesis sec. 3.5), ``sensel_area_mm2`` (default: from the
        points), ``n_interval_resamples`` (default 0: none; else refits of the whole
        method on resampled patches giving the 95 % prediction interval of a new patch's
        load, ``details["prediction_interval"]``, used by :func:`validate`), ``seed`` (of
        the resampling), ``n_bootstrap`` (accepted and recorded, but no parameter interval
        is reported: ``params_stderr`` and ``details["params_interval"]`` are None and
        ``details["stderr_method"]`` says why, :func:`add_uncertainty`), and the method's
        own options.

    Returns
    -------
    CalibrationResult

    Raises
    ------
    ValueError
        For an unknown method, an option the method does not take, too few usable points
        (the message names a manifest given by path), or ``equilibration``/``mask`` given
        with points (they act on frames: give the manifest's path, or apply them when
        making the points).
    TypeError
        For an ``equilibration`` or ``mask`` of the wrong kind.

    Examples
    --------
    >>> from tactilecal.calibration import points_from_frames
    >>> rng = np.random.default_rng(0)
    >>> raw = rng.integers(3, 200, size=(6, 5, 5)).astype(float)
    >>> load = 0.004 * (raw ** 1.2).sum(axis=(1, 2))
    >>> res = calibrate(points_from_frames(raw, load), method="power", objective="l2")
    >>> round(res.params["b"], 6), round(res.params["A"], 6)
    (1.2, 0.004)
    """
    if method not in METHODS:  # before any manifest file is read
        raise TactilecalError(f"method={method!r} is unknown; expected one of {list(METHODS)}")
    if is_path(points):
        manifest = points
        points, dead, eq = manifest_points(manifest, equilibration=equilibration, mask=mask,
                                           progress=progress)
        try:
            result = _calibrate_points(points, method, options)
        except ValueError as err:  # name the manifest: the points' names are in the text
            raise TactilecalError(f"{os.fspath(manifest)}: {err}") from None
        result.provenance = _manifest_provenance(manifest, points)
        return record_preprocessing(result, dead, eq)
    if equilibration is not None or mask is not None:
        raise TactilecalError("equilibration= and mask= act on frames, and points are "
                              "histograms; expected the manifest's path as points, or "
                              "load_points(..., equilibration=, mask=)")
    return _calibrate_points(points, method, options)


def _calibrate_points(points, method, options):
    """:func:`calibrate` on calibration points (no preprocessing left to do)."""
    points = list(points)
    if method != "zvyagin":  # resampled, if asked, by calibrate_arrays on the arrays
        if method not in FITTERS:
            raise TactilecalError(f"method={method!r} is unknown; expected one of {list(METHODS)}")
        hist, load = points_to_arrays(points)
        return calibrate_arrays(hist, load, point_meta(points), method=method, **options)
    from tactilecal.calibration._zvyagin import calibrate_zvyagin as zvyagin  # imports us
    n_params, n_interval, seed = _pop_uncertainty(options)
    result = no_parameter_interval(zvyagin(points, **options))
    if n_params or n_interval:
        hist, load = points_to_arrays(points)
        add_uncertainty(result, lambda idx: zvyagin([points[k] for k in idx], **options),
                        hist, load, n_params=n_params, n_interval=n_interval, seed=seed)
    return result


def _pop_uncertainty(options):
    """Take ``n_bootstrap``, ``n_interval_resamples`` and ``seed`` out of ``options``."""
    counts = {k: options.pop(k, 0) for k in ("n_bootstrap", "n_interval_resamples")}
    for key, count in counts.items():
        if isinstance(count, bool) or not isinstance(count, (int, np.integer)) or count < 0:
            raise TactilecalError(f"{key}={count!r}; expected a whole number >= 0")
    seed = options.pop("seed", 0)
    return int(counts["n_bootstrap"]), int(counts["n_interval_resamples"]), seed


def add_uncertainty(result, refit, hist, load, *, n_params, n_interval, seed, level=0.95):
    """Store the bootstrap prediction interval on ``result`` (in place), and no parameter one.

    ``n_interval`` refits (:func:`bootstrap_refits`) give ``details["prediction_interval"]``.
    ``n_params`` (``n_bootstrap``) is recorded in the options but refits nothing: no
    parameter interval held 90-99 % on every simulated family member (issue 12), so
    ``params_stderr`` stays None and ``details["stderr_method"]`` says why
    (:func:`no_parameter_interval`).
    """
    if n_params:
        result.options["n_bootstrap"] = n_params
    if n_interval:
        boot = bootstrap_refits(refit, hist, load, n_resamples=n_interval, seed=seed)
        result.details["prediction_interval"] = boot.prediction_interval(level).to_dict()
        result.options["n_interval_resamples"] = n_interval
    return result


def no_parameter_interval(result):
    """Mark ``result`` as carrying no parameter interval, and say why (in place).

    Every result of :func:`calibrate` has ``details["params_interval"] = None`` (null in
    its JSON; ``params_stderr`` is None per parameter, as every method returns it) and
    ``details["stderr_method"]`` = :data:`tactilecal._powerfit.NO_STDERR`, unless the
    method gave its own reason (``power-2pt``: two points define the curve exactly).
    """
    result.details["params_interval"] = None
    result.details.setdefault("stderr_method", NO_STDERR)
    return result


def calibrate_arrays(hist, load, meta, *, method="power", **options):
    """Fit a calibration to points given as arrays (the core of :func:`calibrate`).

    ``hist`` (n, 256), ``load`` (n,) and ``meta`` (dict of per-point arrays, keys
    :data:`META_COLUMNS`): what movie calibration uses for tens of thousands of frames
    without making a Python object per frame.
    """
    if method not in FITTERS:
        raise TactilecalError(f"method={method!r} is unknown; expected one of {list(METHODS)}")
    saturated = resolve_saturated(options.pop("saturated", None),
                                  options.pop("keep_saturated", None))
    keep_saturated = saturated == "keep"
    scale_by_working = bool(options.pop("scale_by_working", False))
    area = options.pop("sensel_area_mm2", None)
    n_params, n_interval, seed = _pop_uncertainty(options)
    _check_options(method, options)
    if scale_by_working and method not in SCALABLE:
        raise TactilecalError(f"scale_by_working is offered for {SCALABLE}; method={method!r}")
    used, reasons = _select(load, meta, keep_saturated or saturated == "censored")
    if not used.any():
        kinds = sorted({str(r).split(":")[0] for r in reasons})
        names = [_point_name(meta, k) for k in range(min(len(load), 8))]
        raise TactilecalError(f"no usable calibration points among {len(load)} "
                              f"({', '.join(kinds)}: {', '.join(names)}"
                              f"{' ...' if len(load) > 8 else ''}); expected at least one "
                              "unsaturated point with a positive load")
    if saturated == "censored":
        check_unsaturated(meta["saturated_cells"][used] > 0,
                          lambda k: _point_name(meta, np.flatnonzero(used)[k]),
                          kind="usable point(s)")
    fraction = _working_fraction(meta)
    fit_load = load * fraction if scale_by_working else load
    censored = (meta["saturated_cells"][used] > 0) if saturated == "censored" else None
    fit = _fit(method, take_rows(hist, used), fit_load[used], censored, options)
    if method == "linear" and "point" in fit.details:
        others = used.copy()
        others[np.flatnonzero(used)[fit.details["point"]]] = False
        used[others], reasons[others] = False, "not the I-Scan 1-point calibration point"
    if method == "power-2pt":
        pair = np.flatnonzero(used)[fit.details["pair"]]
        others = used.copy()
        others[pair] = False
        used[others], reasons[others] = False, "not one of the two I-Scan 2-point points"
    if scale_by_working:
        fit.details["working_fraction"] = fraction[used].tolist()
    all_options = {**options, "saturated": saturated, "keep_saturated": keep_saturated,
                   "scale_by_working": scale_by_working, "n_bootstrap": n_params}
    result = result_from_arrays(hist, load, meta, method=method, model=fit.model,
                                params=fit.params, params_stderr=fit.params_stderr, used=used,
                                reasons=reasons, details=fit.details, options=all_options,
                                sensel_area_mm2=area)
    no_parameter_interval(result)
    if n_params or n_interval:
        refit_options = {**options, "saturated": saturated,
                         "scale_by_working": scale_by_working, "sensel_area_mm2": area}
        add_uncertainty(result, lambda idx: calibrate_arrays(
            hist[idx], load[idx], {k: np.asarray(v)[idx] for k, v in meta.items()},
            method=method, **refit_options), hist, load, n_params=n_params,
            n_interval=n_interval, seed=seed)
    return result


def _point_name(meta, k):
    """Return a point's name for messages: its label, else file#frame, else frame N."""
    if meta["label"][k]:
        return str(meta["label"][k])
    return f"{meta['file'][k]}#{meta['frame'][k]}" if meta["file"][k] else \
        f"frame {meta['frame'][k]}"


def _fit(method, hist, load, censored, options):
    """One fit: censored patches (bool mask or None) as lower bounds, else all as equal."""
    if censored is None:
        return FITTERS[method](hist, load, **options)
    return fit_censored(method, hist, load, censored, **options)


def _check_options(method, options):
    import inspect

    accepted = [p.name for p in inspect.signature(FITTERS[method]).parameters.values()
                if p.kind is p.KEYWORD_ONLY]
    unknown = sorted(set(options) - set(accepted))
    if unknown:
        generic = ["saturated", "keep_saturated", "sensel_area_mm2", "scale_by_working",
                   "n_bootstrap", "n_interval_resamples", "seed"]
        raise TactilecalError(f"method={method!r} does not take the options {unknown}; expected "
                              f"{accepted + generic}")


def _working_fraction(meta):
    """Working / all sensels per point (1 where the total is unknown)."""
    total = meta["total_cells"].astype(float)
    return np.where(total > 0, meta["working_cells"] / np.where(total > 0, total, 1.0), 1.0)


def make_result(points, *, method, model, params, params_stderr, used, reasons, details=None,
                options=None, sensel_area_mm2=None, method_result=None):
    """Assemble a :class:`CalibrationResult` with its per-point table and metrics.

    Other calibration methods (e.g. :mod:`tactilecal.zvyagin`) use it so that every
    result has the same table, metrics and saturation pressure; ``method_result`` is the
    method's own result object (:attr:`CalibrationResult.method_result`).
    """
    hist, load = points_to_arrays(points)
    return result_from_arrays(hist, load, point_meta(points), method=method, model=model,
                              params=params, params_stderr=params_stderr, used=used,
                              reasons=reasons, details=details, options=options,
                              sensel_area_mm2=sensel_area_mm2, method_result=method_result)


def result_from_arrays(hist, load, meta, *, method, model, params, params_stderr, used,
                       reasons, details=None, options=None, sensel_area_mm2=None,
                       method_result=None):
    """Assemble a :class:`CalibrationResult` from arrays (see :func:`calibrate_arrays`)."""
    table_N = force_table(model, params)
    predicted = hist_products(hist, table_N)[0]  # counts in any dtype
    area = _sensel_area(meta["sensel_area_mm2"], sensel_area_mm2)
    saturation = table_N[255] / area * N_PER_MM2_TO_KPA if np.isfinite(area) else float("nan")
    used = np.asarray(used, dtype=bool)
    # a saturated point's load is only a lower bound of the law's prediction: not scored
    scored = used & ((meta["saturated_cells"] == 0) | ((options or {}).get("saturated")
                                                        != "censored"))
    with np.errstate(divide="ignore", invalid="ignore"):
        error_pct = 100.0 * (predicted - load) / load
    table = pd.DataFrame({
        "file": meta["file"], "frame": meta["frame"], "load_N": load,
        "raw_sum": meta["raw_sum"], "loaded_cells": meta["loaded_cells"],
        "saturated_cells": meta["saturated_cells"], "used": used,
        "reason": np.asarray(reasons, dtype=object), "predicted_N": predicted,
        "error_pct": error_pct, "label": meta["label"], "note": meta["note"],
    })
    return CalibrationResult(
        method=method, model=model, params=params, params_stderr=params_stderr,
        sensel_area_mm2=area, saturation_pressure_kPa=float(saturation), points=table,
        metrics=_metrics(load[scored], predicted[scored], len(load)), details=details or {},
        options=options or {}, method_result=method_result,
    )


def _sensel_area(areas, area):
    if area is not None:
        return float(area)
    areas = np.asarray(areas, dtype=float)
    areas = np.unique(areas[np.isfinite(areas)])
    if len(areas) > 1 and not np.allclose(areas, areas[0], rtol=1e-6):
        raise TactilecalError(f"points have different sensel areas {areas.tolist()} mm2; "
                              "expected one sensor model per calibration")
    return float(areas[0]) if len(areas) else float("nan")


def _metrics(load, predicted, n_points):
    """Fit quality over the used points: errors in N and in percent of the applied load."""
    if len(load) == 0:  # e.g. a header's power law, which carries no points to score
        return {"n_points": int(n_points), "n_used": 0,
                **dict.fromkeys(("rmse_N", "mean_error_pct", "median_abs_error_pct",
                                 "max_abs_error_pct", "within_5pct", "within_10pct", "r2"),
                                float("nan"))}
    err = predicted - load
    pct = np.abs(100.0 * err / load)
    ss_tot = float(((load - load.mean()) ** 2).sum())
    return {
        "n_points": int(n_points), "n_used": int(len(load)),
        "rmse_N": float(np.sqrt(np.mean(err ** 2))),
        "mean_error_pct": float(np.mean(100.0 * err / load)),
        "median_abs_error_pct": float(np.median(pct)),
        "max_abs_error_pct": float(pct.max()),
        "within_5pct": float(np.mean(pct <= 5.0)), "within_10pct": float(np.mean(pct <= 10.0)),
        "r2": float(1.0 - np.sum(err * err) / ss_tot) if ss_tot > 0 else float("nan"),
    }


def validate(result, points, *, include_saturated=False, progress=None):
    """Compare a calibration's predicted loads with the applied loads of (held-out) points.

    Parameters
    ----------
    result : CalibrationResult
    points : sequence of CalibrationPoint, str or os.PathLike
        Points, or the path of a manifest CSV whose frames are read with the calibration's
        equilibration gains (``details["equilibration"]``) applied, as they were for the
        fit. Its non-working-sensel mask is not needed: a masked sensel reads 0 and
        ``f(0)`` adds nothing to a frame's force.
    include_saturated : bool
        Whether points with saturated sensels count in the summary (default False: they
        are listed with ``saturated: true`` and left out of the summary, which says so).
    progress : callable, optional
        Manifest only: as in :func:`calibrate`.

    Returns
    -------
    ValidationResult
        Read as a dict: ``points`` (file, frame, load_N, predicted_N, error_pct, saturated)
        and ``summary`` (n, within_5pct, within_10pct, median_abs_error_pct,
        max_abs_error_pct, as fractions in 0..1 for the ``within`` keys, plus
        n_saturated_excluded); plain Python numbers, ``to_json`` saves it.

    Raises
    ------
    ValueError
        If no point can be summarised.
    """
    manifest = points if is_path(points) else None
    if manifest is not None:
        stored = result.details.get("equilibration")
        points = load_points(manifest, **reading_options(progress),
                             equilibration=None if stored is None
                             else Equilibration.from_dict(stored))
    hist, load = points_to_arrays(points)
    predicted = result.predict_histograms(hist)
    saturated = np.array([p.saturated_cells > 0 for p in points])
    with np.errstate(divide="ignore", invalid="ignore"):
        error_pct = 100.0 * (predicted - load) / load
    rows = [{"file": p.source, "frame": p.frame, "load_N": p.load_N, "predicted_N": pr,
             "error_pct": e, "saturated": bool(s), "predicted_is_lower_bound": bool(s),
             "label": p.label}
            for p, pr, e, s in zip(points, predicted, error_pct, saturated, strict=True)]
    keep = np.isfinite(error_pct) & (include_saturated | ~saturated)
    inside = _interval_columns(result, rows, predicted, load)
    if not keep.any():
        raise TactilecalError(f"none of the {len(points)} validation points has a positive load "
                              "and no saturated sensels; expected at least one")
    pct = np.abs(error_pct[keep])
    summary = {"n": int(keep.sum()), "within_5pct": float(np.mean(pct <= 5.0)),
               "within_10pct": float(np.mean(pct <= 10.0)),
               "within_3pct": float(np.mean(pct <= 3.0)),
               "median_abs_error_pct": float(np.median(pct)),
               "max_abs_error_pct": float(pct.max()),
               "n_saturated_excluded": int((saturated & ~keep).sum()),
               "calibration_method": result.method}
    if inside is not None:
        summary["interval_coverage"] = float(np.mean(inside[keep & ~saturated])) \
            if (keep & ~saturated).any() else float("nan")
    checked = ValidationResult(points=rows, metrics=summary)
    checked.provenance = (provenance([]) if manifest is None
                          else _manifest_provenance(manifest, points))
    return checked


def _manifest_provenance(manifest, points):
    """Provenance of a result computed from a manifest's points: the manifest, its files."""
    folder = Path(manifest).parent
    return provenance([manifest, *(folder / p.source for p in points)],
                      [p.sensor for p in points])


def _interval_columns(result, rows, predicted, load):
    """Add each point's prediction interval (if the calibration has one); return inside."""
    stored = result.details.get("prediction_interval")
    if not stored:
        return None
    low, high = PredictionInterval(**stored).bounds_N(predicted)
    for row, lo, hi, sat in zip(rows, low, high, [r["saturated"] for r in rows], strict=True):
        row["predicted_low_N"] = float(lo)
        # a saturated patch's load is only bounded below
        row["predicted_high_N"] = float("inf") if sat else float(hi)
    return (low <= load) & (load <= high)
