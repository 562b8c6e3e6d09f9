"""``calibrate(points, method="zvyagin")``: Zvyagin (2022) from calibration points.

The adapter between the two subpackages lives here, on the calibration side: it imports
:mod:`tactilecal.zvyagin` by its public names (Zvyagin's procedure knows nothing of
calibration points or results), so the import runs one way, calibration -> zvyagin.
"""

import warnings

import numpy as np

from tactilecal._errors import TactilecalError
from tactilecal._jsonutil import to_jsonable
from tactilecal._saturation import resolve_saturated
from tactilecal.calibration._calibrate import make_result
from tactilecal.calibration._points import points_to_arrays
from tactilecal.zvyagin import OPTIONS, energy, zvyagin_fit

__all__ = ["calibrate_zvyagin", "conditional_stderr"]


def _point_labels(points):
    out = []
    for k, p in enumerate(points):
        name = p.label or (f"{p.source}#{p.frame}" if p.source else f"point {k}")
        out.append(f"{k}:{name}")
    return out


def _sensel_area(points, area):
    if area is not None:
        return float(area)
    areas = np.array([p.sensel_area_mm2 for p in points], dtype=float)
    areas = areas[np.isfinite(areas)]
    if areas.size == 0:
        warnings.warn("the points carry no sensel area and sensel_area_mm2 was not given: "
                      "p_s (eq. 16) is unknown; pass sensel_area_mm2 (5051: 1.6129)",
                      UserWarning, stacklevel=3)
        return float("nan")
    return float(areas[0])


def conditional_stderr(res, histograms_used):
    """Estimate standard errors of (A0, b0) from the curvature of E along the power-law curve.

    var(b0) = 2 s^2 / E''(b0) with s^2 = E(b0) / (n - 1), and se(A0) = |dA0/db0| se(b0):
    conditional on alpha and beta (their own uncertainty is not propagated). With
    ``final="free"`` it is taken at the curve's own optimum (``curve_b0``).

    Parameters
    ----------
    res : tactilecal.zvyagin.ZvyaginResult
    histograms_used : numpy.ndarray
        (n_usable, 256) histograms of the patches ``res.usable`` marks.
    """
    h = histograms_used
    f = res.load_N[res.usable]
    b0, step = res.final.get("curve_b0", res.b0), 1e-4
    e = energy(np.array([b0 - step, b0, b0 + step]), h, f, res.alpha, res.beta)
    curvature = (e[0] - 2 * e[1] + e[2]) / step ** 2
    n = f.size
    if curvature <= 0 or n < 2:
        return {"A": None, "b": None}
    se_b = float(np.sqrt(2 * e[1] / (n - 1) / curvature))
    se_a = float(abs(res.alpha * res.beta * b0 ** (res.beta - 1)) * se_b)
    return {"A": se_a, "b": se_b}


def calibrate_zvyagin(points, **options):
    """Calibrate with Zvyagin's (2022) multi-patch method; return a CalibrationResult.

    ``tactilecal.calibrate(points, method="zvyagin", **options)`` calls this (and adds the
    bootstrap options).

    Parameters
    ----------
    points : sequence of tactilecal.calibration.CalibrationPoint
        One per loaded patch (histogram of raw values and applied load).
    **options
        ``mode`` ("robust", the default, or "faithful"), ``domain``, ``root_choice``,
        ``outliers``, ``b_range``, ``saturated``, ``final``, ``pair_b_min``, ``objective``,
        ``trim``, ``max_relerr``, ``grey_share``, ``group_tolerance``, ``sensel_area_mm2``:
        see :func:`zvyagin_fit`. ``keep_saturated`` (the static methods' spelling) sets
        ``saturated`` to "keep" (True) or "drop" (False); without
        either, ``saturated`` is the one default of every static method,
        :data:`tactilecal._saturation.SATURATED_DEFAULT` ("drop").

    Returns
    -------
    tactilecal.calibration.CalibrationResult
        Method ``"zvyagin"``, model ``"power"``, params ``{"A": A0, "b": b0}`` (force per
        sensel in N = A * raw**b), and every intermediate of the procedure in ``details``
        (:meth:`ZvyaginResult.to_details`); the :class:`ZvyaginResult` itself is
        ``method_result`` (rebuilt from ``details`` when the JSON is loaded).

    Raises
    ------
    ValueError
        Unknown option, or any error of :func:`zvyagin_fit`.

    Examples
    --------
    >>> from tactilecal.calibration import points_from_frames
    >>> from tactilecal.simulate import make_sensor, deadweight_session
    >>> s = deadweight_session(make_sensor("5051", seed=1), n_patches=40, seed=2)
    >>> cal = calibrate_zvyagin(points_from_frames(s.raw, s.load_N))
    >>> cal.method, cal.model, sorted(cal.params)
    ('zvyagin', 'power', ['A', 'b'])
    """
    unknown = sorted(set(options) - set(OPTIONS))
    if unknown:
        raise TactilecalError(f"calibrate_zvyagin: unknown options {unknown}; expected some of "
                              f"{list(OPTIONS)}")
    opts = dict(options)
    opts["saturated"] = resolve_saturated(opts.get("saturated"), opts.pop("keep_saturated", None))
    points = list(points)
    if len(points) < 2:
        raise TactilecalError(f"{len(points)} calibration point(s); expected at least 2 patches")
    area = _sensel_area(points, opts.pop("sensel_area_mm2", None))
    hist, load = points_to_arrays(points)
    res = zvyagin_fit(hist, load, labels=_point_labels(points), sensel_area_mm2=area, **opts)
    reasons = [res.excluded.get(k, "") for k in range(len(points))]
    details = to_jsonable(res.to_details())
    # The curvature of E(b0) along the fitted curve ignores the uncertainty of alpha and
    # beta: on an independent simulator it was ~100x too small (b = 1.22069 +- 0.00037 for
    # a truth of 1.16, issue 12), so it is kept only as a diagnostic, not as an error.
    used_hist = np.asarray(hist)[res.usable]
    details["conditional_stderr"] = to_jsonable(conditional_stderr(res, used_hist))
    details["stderr_note"] = ("no parameter errors: the curvature of E(b0) along the power "
                              "law (details.conditional_stderr) is conditional on alpha and "
                              "beta and far too small to quote")
    return make_result(points, method="zvyagin", model="power",
                       params={"A": res.A0, "b": res.b0}, params_stderr={"A": None, "b": None},
                       used=res.usable, reasons=reasons, details=details,
                       options={"mode": res.mode, **res.options}, sensel_area_mm2=area,
                       method_result=res)
