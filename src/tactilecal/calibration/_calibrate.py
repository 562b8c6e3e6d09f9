"""``calibrate``: the one door to every static method; ``validate``.

:func:`calibrate` checks the options once (those of :class:`CommonOptions` and of the
method's ``Options``), reads a manifest with its preprocessing, chooses the points a fit may
use (:func:`select_points`), resolves saturation and the sensel area, runs the method's
``fit`` (:mod:`tactilecal.calibration.methods`) and assembles the
:class:`CalibrationResult`. Movie calibration (:func:`calibrate_movie`) enters at
:func:`fit_arrays`, after the same option check.
"""

import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from tactilecal._errors import TactilecalError
from tactilecal._provenance import provenance
from tactilecal._units import N_PER_MM2_TO_KPA
from tactilecal.calibration._fit import FitData, MethodOptions, check_positive_number, option
from tactilecal.calibration._gains import learn_gains
from tactilecal.calibration._lack_of_fit import lack_of_fit, law_parameters
from tactilecal.calibration._manifest import load_points
from tactilecal.calibration._metrics import fit_metrics
from tactilecal.calibration._models import check_law, force_table
from tactilecal.calibration._pipeline import chain, is_path, manifest_points, reading_options
from tactilecal.calibration._points import frame_histograms, points_to_arrays, take_rows
from tactilecal.calibration._powerfit import check_unsaturated, hist_products
from tactilecal.calibration._result import CalibrationResult
from tactilecal.calibration._saturation import SATURATED_CHOICES, SATURATED_DEFAULT
from tactilecal.calibration._uncertainty import bootstrap_refits
from tactilecal.calibration._validation import ValidationResult
from tactilecal.calibration.methods import MODULES, auto

__all__ = ["METHODS", "DEFAULT_METHOD", "META_COLUMNS", "CommonOptions", "calibrate",
           "fit_arrays", "law_result", "method_options", "point_meta", "select_points",
           "validate"]

METHODS = (auto.NAME, *MODULES)
"""``"auto"`` (choose by held-out error) and the static methods, in the order of
:mod:`tactilecal.calibration.methods`."""

DEFAULT_METHOD = auto.NAME
"""The method of :func:`calibrate` and ``tactilecal calibrate`` when none is given: on the
family of simulated sensors, choosing by held-out error held every session within 10 % of
the best method's error, where any one method was up to 1.5x worse on some member."""

INTERVAL_LEVEL = 0.95
"""Probability of the prediction interval of a new patch's load."""


@dataclass(frozen=True)
class CommonOptions(MethodOptions):
    """The options of :func:`calibrate` that every method takes.

    ``saturated``: how patches with a sensel at 255 enter the fit (the one default of every
    method, :data:`tactilecal.calibration._saturation.SATURATED_DEFAULT`). ``sensel_area_mm2``:
    the sensel area (default: the points', which must agree). ``n_interval_resamples``:
    refits of the whole method on patches resampled with replacement, giving the 95 %
    prediction interval of a new patch's load (0: none). ``seed``: of that resampling.
    ``gains="learn"``: per-sensel gains learned with the law
    (:mod:`tactilecal.calibration._gains`), applied to the frames before the method's fit
    and kept as the result's ``equilibration``; the points need their frames
    (``CalibrationPoint.readings``).

    Examples
    --------
    >>> from tactilecal.calibration import calibrate, points_from_frames
    >>> CommonOptions.names()
    ('saturated', 'sensel_area_mm2', 'n_interval_resamples', 'seed', 'gains')
    >>> raw = np.zeros((3, 4, 4)); raw[:, 1:3, 1:3] = np.array([10, 20, 40])[:, None, None]
    >>> points = points_from_frames(raw, 0.04 * np.array([10, 20, 40]) ** 1.2)  # 4 sensels
    >>> cal = calibrate(points, method="power", objective="l2", sensel_area_mm2=2.0)
    >>> cal.options["saturated"], cal.options["sensel_area_mm2"], round(cal.saturation_pressure_kPa)
    ('drop', 2.0, 3862)
    """

    saturated: str = option(SATURATED_DEFAULT, "patches with a sensel at 255: drop them from "
                                               "the fit, keep them as if 255 were their "
                                               "reading, or fit them as lower bounds "
                                               "(censored)", choices=SATURATED_CHOICES)
    sensel_area_mm2: float | None = option(None, "sensel area in mm2 (default: the "
                                                 "recordings')")
    n_interval_resamples: int = option(0, "bootstrap refits for the 95 % prediction interval "
                                          "of a new patch's load (0: none)", metavar="N")
    seed: int = option(0, "seed of the bootstrap refits")
    gains: str = option("none", "learn each sensel's gain with the law from the patches: a "
                                "smooth surface plus a shrunk per-sensel residual, its "
                                "strength chosen by held-out patches (no gains among the "
                                "choices); kept as the calibration's equilibration",
                        choices=("none", "learn"), flag=("--learn-gains", "learn"))

    @classmethod
    def method_name(cls):
        return "every method"

    def _check(self):
        if self.sensel_area_mm2 is not None:
            check_positive_number(self.sensel_area_mm2, "sensel_area_mm2", "calibrate")
        for name in ("n_interval_resamples", "seed"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, int | np.integer) or value < 0:
                raise TactilecalError(f"{name}={value!r}; expected a whole number >= 0")


def method_options(method, keywords):
    """Split ``keywords`` into the :class:`CommonOptions` and the method's ``Options``.

    Returns
    -------
    module, CommonOptions, Options

    Raises
    ------
    TactilecalError
        An unknown method or a bad option value.
    TactilecalTypeError
        An option that neither the method nor :class:`CommonOptions` takes, naming it and
        the accepted ones.
    """
    if method not in METHODS:
        raise TactilecalError(f"method={method!r} is unknown; expected one of {list(METHODS)}")
    module = auto if method == auto.NAME else MODULES[method]
    keywords = dict(keywords)
    common = CommonOptions(**{k: keywords.pop(k) for k in CommonOptions.names()
                              if k in keywords})
    return module, common, module.Options.from_keywords(keywords,
                                                         accepted_too=CommonOptions.names())


def select_points(load, meta, saturated):
    """Decide which points a fit may use and why the others may not.

    Parameters
    ----------
    load : numpy.ndarray
        Applied loads (n,).
    meta : dict
        Per-point columns (:data:`META_COLUMNS`).
    saturated : str
        The saturation treatment: ``"drop"`` leaves out points with a sensel at 255.

    Returns
    -------
    used : numpy.ndarray of bool
    reasons : numpy.ndarray of str (object)
        ``""`` for a used point, else why it was left out.
    """
    reasons = np.full(len(load), "", dtype=object)
    sat = meta["saturated_cells"]
    if saturated == "drop":
        bad = sat > 0
        reasons[bad] = [f"saturated: {k} sensels at 255, left out (saturated='censored' or "
                        "'keep' uses it)" for k in sat[bad]]
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


def calibrate(points, method=DEFAULT_METHOD, *, equilibration=None, mask=None, progress=None,
              **options):
    """Fit a static calibration to calibration points, or to a manifest's frames.

    Parameters
    ----------
    points : sequence of CalibrationPoint, str or os.PathLike
        From :func:`load_points` or :func:`points_from_frames`; or the path of a manifest
        CSV, whose frames are then read with ``equilibration`` and ``mask`` applied (what
        ``tactilecal calibrate MANIFEST`` does).
    method : str
        One of :data:`METHODS` (:mod:`tactilecal.calibration.methods` describes each):
        ``"linear"`` (I-Scan 1-point / through zero), ``"power-2pt"`` (I-Scan 2-point power
        law on the mean raw reading), ``"power"`` (multi-point power law over every sensel),
        ``"linear-offset"`` (Paikowsky & Hajduk), ``"piecewise"`` (power law per raw
        range), ``"lut"`` (monotone lookup table), ``"polynomial"``, ``"zvyagin"``
        (Zvyagin 2022; the result's ``method_result`` is its
        :class:`tactilecal.calibration.ZvyaginResult`).
    equilibration : Equilibration, str or os.PathLike, optional
        Manifest only: per-sensel gains (or the path of their JSON) applied to every frame
        before it is counted (Gillis 2013, sec. 3.5); kept as the result's
        ``equilibration`` so that :meth:`CalibrationResult.apply` applies them to a
        recording too.
    mask : {"detect"}, NonWorkingSensels or array_like of bool, optional
        Manifest only: non-working sensels to leave out; ``"detect"`` finds them over the
        manifest's frames (:func:`find_dead_sensels`, ``--mask-dead`` of the CLI). Kept as
        the result's ``non_working`` and masked by ``apply``.
    progress : callable, optional
        Manifest only: ``progress(iterable, total=, desc=)`` wrapping the reading of long
        manifests, e.g. a progress bar (default None: none).
    **options
        The fields of :class:`CommonOptions` (``saturated``, ``sensel_area_mm2``,
        ``n_interval_resamples``, ``seed``) and of the method's ``Options``
        (``tactilecal.calibration.METHOD_OPTIONS[method]``), e.g. ``objective`` of
        ``power``, ``degree`` of ``polynomial``, ``mode`` of ``zvyagin``.

    Returns
    -------
    CalibrationResult

    Raises
    ------
    TactilecalError
        For an unknown method, a bad option value, too few usable points (the message names
        a manifest given by path), a law that is negative or decreasing on raw 0..255, or
        ``equilibration``/``mask`` given with points (they act on frames: give the
        manifest's path, or apply them when making the points).
    TactilecalTypeError
        For an option the method does not take (naming it and the accepted ones).
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
    module, common, method_opts = method_options(method, options)  # before reading files
    if not is_path(points):
        if equilibration is not None or mask is not None:
            raise TactilecalError("equilibration= and mask= act on frames, and points are "
                                  "histograms; expected the manifest's path as points, or "
                                  "load_points(..., equilibration=, mask=)")
        return _calibrate_points(list(points), module, common, method_opts)
    manifest = points
    points, dead, eq = manifest_points(manifest, equilibration=equilibration, mask=mask,
                                       progress=progress)
    try:
        result = _calibrate_points(points, module, common, method_opts)
    except TactilecalError as err:  # name the manifest: the points' names are in the text
        raise TactilecalError(f"{Path(manifest)}: {err}") from None
    result.equilibration, result.non_working = chain(eq, result.equilibration), dead
    return result


def _calibrate_points(points, module, common, options):
    """:func:`calibrate` on calibration points (no preprocessing left to do)."""
    hist, load = points_to_arrays(points)
    readings = None
    if common.gains == "learn":
        if any(p.readings is None for p in points):
            raise TactilecalError("gains='learn' needs the frames of the points (where each "
                                  "reading lies); these points carry only histograms")
        readings = np.stack([p.readings for p in points])
    result = fit_arrays(hist, load, point_meta(points), module=module, common=common,
                        options=options, readings=readings)
    result.provenance = points_provenance(points)
    return result


def points_provenance(points):
    """Provenance of a result computed from points: their manifests, files and sensors."""
    files = []
    for p in points:
        if p.manifest:
            files.append(Path(p.manifest))
            files.append(Path(p.manifest).parent / p.source)
        elif p.source:
            files.append(Path(p.source))
    return provenance(files, [p.sensor for p in points])


def fit_arrays(hist, load, meta, *, module, common, options, readings=None, diagnose=True):
    """Fit a calibration to points given as arrays (the core of :func:`calibrate`).

    ``hist`` (n, 256), ``load`` (n,) and ``meta`` (dict of per-point arrays, keys
    :data:`META_COLUMNS`): what movie calibration uses for tens of thousands of frames
    without making a Python object per frame. ``module``, ``common`` and ``options`` come
    from :func:`method_options`; ``readings`` (n, rows, cols), the frames, are needed for
    ``gains="learn"``: the gains learned on the used points correct every frame before
    ``hist`` is counted again and the method fitted. ``diagnose=False`` leaves out the
    lack-of-fit checks (``lack_of_fit`` None): the prediction interval's refits, of which
    only the law is used.
    """
    area = _sensel_area(meta["sensel_area_mm2"], common.sensel_area_mm2)
    used, reasons = select_points(load, meta, common.saturated)
    if not used.any():
        kinds = sorted({str(r).split(":")[0] for r in reasons})
        names = [_point_name(meta, k) for k in range(min(len(load), 8))]
        raise TactilecalError(f"no usable calibration points among {len(load)} "
                              f"({', '.join(kinds)}: {', '.join(names)}"
                              f"{' ...' if len(load) > 8 else ''}); expected at least one "
                              "unsaturated point with a positive load")
    rows = np.flatnonzero(used)
    _check_two_loads(module.NAME, load[used])
    gains, gains_record = None, None
    if common.gains == "learn":
        exact = (meta["saturated_cells"][used] == 0) | (common.saturated != "censored")
        gains, gains_record = learn_gains(readings[used], load[used], exact)
        if gains is not None:
            hist = frame_histograms(gains.apply(readings))
    if common.saturated == "censored":  # lower bounds need two exact loads to start from
        check_unsaturated(meta["saturated_cells"][used] > 0,
                          lambda k: _point_name(meta, rows[k]), kind="usable point(s)")
    scale = _working_fraction(meta) if getattr(options, "scale_by_working", False) else None
    data = FitData(hist=take_rows(hist, used), load_N=(load if scale is None
                                                       else load * scale)[used],
                   censored=(meta["saturated_cells"][used] > 0
                             if common.saturated == "censored" else None),
                   sensel_area_mm2=area,
                   labels=tuple(_point_name(meta, k) for k in rows)
                   if getattr(module, "NAMES_POINTS", False) else ())
    selection = None
    if module is auto:
        module, options, selection = auto.select(
            data, options, auto.groups_of(meta["file"][rows], options.folds))
    fit = module.fit(data, options)
    check_law(fit.model, fit.params, f"the {module.NAME} fit")
    if fit.chosen is not None:  # I-Scan's 1- and 2-point calibrations: the rest not used
        others = used.copy()
        others[rows[list(fit.chosen)]] = False
        used[others] = False
        reasons[others] = f"not one of the points of I-Scan's {module.NAME} calibration"
    if scale is not None:
        fit.diagnostics["working_fraction"] = scale[used].tolist()
    if gains_record is not None:
        fit.diagnostics["gains"] = gains_record
    result = law_result(hist, load, meta, module.NAME, fit, used, reasons, area, common,
                        options)
    result.selection = selection
    result.equilibration = gains
    if diagnose:
        exact = used & ((meta["saturated_cells"] == 0) | (common.saturated != "censored"))
        mean_raw = meta["raw_sum"][exact] / np.maximum(meta["loaded_cells"][exact], 1)
        power_law = fit.model == "power" and module.NAME != "linear" or selection is not None
        result.lack_of_fit = lack_of_fit(
            load[exact], result.points["predicted_N"].to_numpy()[exact], mean_raw,
            n_parameters=law_parameters(module.NAME, fit.model, fit.params),
            selection=selection, hist=take_rows(hist, exact) if power_law else None)
        for message in result.lack_of_fit.messages:
            warnings.warn(f"{module.NAME} calibration: {message}", UserWarning, stacklevel=3)
    if common.n_interval_resamples:
        result.prediction_interval = _interval(hist, load, meta, module, common, options)
    return result


def _check_two_loads(method, load_N):
    """Refuse one load for a law of two parameters: any exponent fits a single load."""
    if method != "linear" and np.unique(load_N).size < 2:
        raise TactilecalError(f"method {method!r} needs at least two different loads (a power "
                              "law has two parameters: one load is met by any exponent); the "
                              f"{load_N.size} usable points all have load_N = "
                              f"{float(load_N[0]):.6g}; expected points at two or more loads, "
                              "or method 'linear' (I-Scan's 1-point calibration)")


def _interval(hist, load, meta, module, common, options):
    """Return the bootstrap prediction interval of a new patch's load (whole-method refits)."""
    if len(load) < 3:
        raise TactilecalError(f"{len(load)} patches; a prediction interval needs at least 3")
    once = CommonOptions(saturated=common.saturated, sensel_area_mm2=common.sensel_area_mm2)
    # the gains learned once stay: the interval is that of the law on corrected frames;
    # of a refit only its law is used, so its lack-of-fit checks are not made
    boot = bootstrap_refits(lambda idx: fit_arrays(
        hist[idx], load[idx], {k: np.asarray(v)[idx] for k, v in meta.items()},
        module=module, common=once, options=options, diagnose=False), hist, load,
        n_resamples=common.n_interval_resamples, seed=common.seed)
    return boot.prediction_interval(INTERVAL_LEVEL)


def law_result(hist, load, meta, method, fit, used, reasons, area, common, options=None):
    """Assemble the :class:`CalibrationResult` of a law: per-point table, metrics, p_s.

    Also used for a law that was not fitted here (a Tekscan header's calibration).
    """
    table_N = force_table(fit.model, fit.params)
    predicted = hist_products(hist, table_N)[0]  # counts in any dtype
    saturation = table_N[255] / area * N_PER_MM2_TO_KPA if np.isfinite(area) else float("nan")
    # a saturated point's load is only a lower bound of the law's prediction: not scored
    scored = used & ((meta["saturated_cells"] == 0) | (common.saturated != "censored"))
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
        method=method, model=fit.model, params=fit.params, sensel_area_mm2=area,
        saturation_pressure_kPa=float(saturation), points=table,
        metrics={"n_points": len(load), **fit_metrics(load[scored], predicted[scored])},
        options={**common.to_dict(), **({} if options is None else options.to_dict())},
        diagnostics=fit.diagnostics,
        method_result=fit.method_result)


def _point_name(meta, k):
    """Return a point's name for messages: its label, else file#frame, else frame N."""
    if meta["label"][k]:
        return str(meta["label"][k])
    return f"{meta['file'][k]}#{meta['frame'][k]}" if meta["file"][k] else \
        f"frame {meta['frame'][k]}"


def _working_fraction(meta):
    """Working / all sensels per point (1 where the total is unknown)."""
    total = meta["total_cells"].astype(float)
    return np.where(total > 0, meta["working_cells"] / np.where(total > 0, total, 1.0), 1.0)


def _sensel_area(areas, area):
    """Return the one sensel area: ``area`` if given, else the points' (which must agree)."""
    if area is not None:
        return float(area)
    areas = np.asarray(areas, dtype=float)
    areas = np.unique(areas[np.isfinite(areas)])
    if len(areas) > 1 and not np.allclose(areas, areas[0], rtol=1e-6):
        raise TactilecalError(f"points have different sensel areas {areas.tolist()} mm2; "
                              "expected one sensor model per calibration")
    return float(areas[0]) if len(areas) else float("nan")


def validate(result, points, *, include_saturated=False, progress=None):
    """Compare a calibration's predicted loads with the applied loads of (held-out) points.

    Parameters
    ----------
    result : CalibrationResult
    points : sequence of CalibrationPoint, str or os.PathLike
        Points, or the path of a manifest CSV whose frames are read with the calibration's
        equilibration gains applied, as they were for the fit. Its non-working-sensel mask
        is not needed: a masked sensel reads 0 and ``f(0)`` adds nothing to a frame's force.
    include_saturated : bool
        Whether points with saturated sensels count in the summary (default False: they
        are listed with ``saturated: true`` and left out of the summary, which says so).
    progress : callable, optional
        Manifest only: as in :func:`calibrate`.

    Returns
    -------
    ValidationResult
        ``points`` (file, frame, load_N, predicted_N, error_pct, saturated...) and
        ``metrics`` (those of :func:`tactilecal.calibration._metrics.fit_metrics`, plus
        n_saturated_excluded, calibration_method, calibration_sha256 (the calibration's
        :meth:`~tactilecal._result.SavedResult.fingerprint`) and, for a calibration with a
        prediction interval, interval_coverage).

    Raises
    ------
    TactilecalError
        If no point can be summarised.

    Examples
    --------
    >>> from tactilecal.calibration import points_from_frames
    >>> raw = np.zeros((4, 3, 3)); raw[:, 1, 1] = [10, 20, 40, 80]
    >>> points = points_from_frames(raw, 0.01 * raw[:, 1, 1] ** 1.1)
    >>> check = validate(calibrate(points[:3], "power", objective="l2"), points[3:])
    >>> check.metrics["n"], round(check.metrics["max_abs_error_pct"], 6)
    (1, 0.0)
    """
    manifest = points if is_path(points) else None
    if manifest is not None:
        points = load_points(manifest, **reading_options(progress),
                             equilibration=result.equilibration)
    points = list(points)
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
        raise TactilecalError(f"none of the {len(points)} validation points has a positive "
                              "load and no saturated sensels; expected at least one")
    metrics = {**fit_metrics(load[keep], predicted[keep]),
               "n_saturated_excluded": int((saturated & ~keep).sum()),
               "calibration_method": result.method,
               "calibration_sha256": result.fingerprint()}
    if inside is not None:
        metrics["interval_coverage"] = float(np.mean(inside[keep & ~saturated])) \
            if (keep & ~saturated).any() else float("nan")
    checked = ValidationResult(points=rows, metrics=metrics)
    checked.provenance = points_provenance(points)
    return checked


def _interval_columns(result, rows, predicted, load):
    """Add each point's prediction interval (if the calibration has one); return inside."""
    if result.prediction_interval is None:
        return None
    low, high = result.prediction_interval.bounds_N(predicted)
    for row, lo, hi, sat in zip(rows, low, high, [r["saturated"] for r in rows], strict=True):
        row["predicted_low_N"] = float(lo)
        # a saturated patch's load is only bounded below
        row["predicted_high_N"] = float("inf") if sat else float(hi)
    return (low <= load) & (load <= high)
