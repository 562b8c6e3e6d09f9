"""Per-sensel calibration laws: raw reading -> force on one sensel in newtons.

Every model is a function ``f(raw, params)`` with ``f(0) = 0``. A frame's total force is
``sum_k f(X_k)``, i.e. ``histogram @ f(arange(256))`` for its 256-bin histogram (Zvyagin
2022, eq. 2). The model names are the ``model`` key of the calibration JSON.
"""

import numpy as np

from tactilecal._errors import TactilecalError

__all__ = ["MODELS", "check_law", "sensel_force", "force_table"]

LEVELS = np.arange(256, dtype=float)


def _power(raw, params):
    """Manufacturer's law f = A * raw**b (Zvyagin 2022, eq. 1; thesis sec. 3.5)."""
    positive = raw > 0
    # zero and negative readings carry no force; they are not raised to b (which may be < 0)
    return np.where(positive, params["A"] * np.where(positive, raw, 1.0) ** params["b"], 0.0)


def _linear_offset(raw, params):
    """Paikowsky & Hajduk (1997) f = K * (raw - offset) on loaded sensels (thesis sec. 3.5).

    Clipped at 0: a reading at or below the offset carries no force (the published formula
    would give it a negative one).
    """
    return np.where(raw > 0, params["K"] * np.maximum(raw - params["offset"], 0.0), 0.0)


def _piecewise_power(raw, params):
    """Continuous piecewise power law: straight lines between knots in log-log coordinates.

    Each segment between two knots is a power law ``A_r * raw**b_r`` (Stith's separate
    low/medium/high-pressure curves, made continuous at the knots).
    """
    log_knots = np.log(np.asarray(params["knots"], dtype=float))
    log_force = np.log(np.asarray(params["force_N"], dtype=float))
    slope0 = (log_force[1] - log_force[0]) / (log_knots[1] - log_knots[0])
    with np.errstate(divide="ignore", invalid="ignore"):
        log_raw = np.log(np.where(raw > 0, raw, 1.0))
        inside = np.interp(log_raw, log_knots, log_force)
        below = log_force[0] + slope0 * (log_raw - log_knots[0])
        value = np.exp(np.where(log_raw < log_knots[0], below, inside))
    return np.where(raw > 0, value, 0.0)


def _table(raw, params):
    """Monotone lookup table: ``force_N`` at ``knots``, linear in ``raw**exponent`` between.

    ``exponent`` (default 1: linear in raw, as tables saved before it existed) is the power
    method's b on the calibration patches (``fit_lut``).
    """
    e = float(params.get("exponent", 1.0))
    knots = np.asarray(params["knots"], dtype=float)
    with np.errstate(invalid="ignore"):  # negative readings carry no force either way
        value = np.interp(np.where(raw > 0, raw, 0.0) ** e, knots ** e, params["force_N"])
    return np.where(raw > 0, value, 0.0)


def _polynomial(raw, params):
    """Polynomial through the origin f = sum_j c_j * raw**j, j = 1..degree."""
    coef = np.asarray(params["coefficients"], dtype=float)
    return np.where(raw > 0, np.polynomial.polynomial.polyval(raw, np.r_[0.0, coef]), 0.0)


MODELS = {
    "power": _power,
    "linear-offset": _linear_offset,
    "piecewise-power": _piecewise_power,
    "table": _table,
    "polynomial": _polynomial,
}


def sensel_force(model, params, raw):
    """Force per sensel in newtons for raw readings (NaN stays NaN).

    Parameters
    ----------
    model : str
        One of :data:`MODELS`.
    params : dict
        The model's parameters.
    raw : array_like
        Raw readings (any shape, floats allowed).

    Returns
    -------
    numpy.ndarray

    Raises
    ------
    ValueError
        For an unknown model name.

    Examples
    --------
    >>> sensel_force("power", {"A": 0.5, "b": 2.0}, [0.0, 2.0, np.nan]).tolist()
    [0.0, 2.0, nan]
    """
    if model not in MODELS:
        raise TactilecalError(f"model {model!r} is unknown; expected one of {sorted(MODELS)}")
    out = MODELS[model](np.nan_to_num(raw, nan=0.0), params)
    return np.where(np.isnan(raw), np.nan, out)


def force_table(model, params):
    """Return the force per sensel at raw = 0..255 (float64[256])."""
    return sensel_force(model, params, LEVELS)


def check_law(model, params, where):
    """Refuse a law that is not a force per sensel: non-finite, negative or decreasing.

    A calibrated law must give finite forces on raw 0..255 that never decrease (a higher
    reading never means a smaller force), are never negative, and are positive at 255 (so
    the saturation pressure is positive).

    Raises
    ------
    TactilecalError
        Naming ``where`` (e.g. ``"key 'params' of cal.json"``), the model and what is wrong.

    Examples
    --------
    >>> check_law("polynomial", {"coefficients": [0.01, -1e-4]}, "the fit")
    Traceback (most recent call last):
    ...
    tactilecal.TactilecalError: the fit: the polynomial law decreases from raw 50 ...
    """
    with np.errstate(all="ignore"):  # overflow shows as a non-finite force below
        table = force_table(model, params)
    if not np.all(np.isfinite(table)):
        bad = int(np.flatnonzero(~np.isfinite(table))[0])
        raise TactilecalError(f"{where}: the {model} law gives a non-finite force at raw {bad}; "
                              "expected finite forces on raw 0..255")
    drops = np.flatnonzero(np.diff(table) < -1e-12 * max(float(table.max()), 1e-300))
    if drops.size:
        raise TactilecalError(f"{where}: the {model} law decreases from raw {drops[0]} "
                              f"({table[drops[0]]:.4g} N) to {drops[0] + 1} "
                              f"({table[drops[0] + 1]:.4g} N); expected a force that never "
                              "decreases as the reading grows (choose a method that "
                              "keeps it monotone, such as lut, or a lower degree)")
    if table.min() < 0:
        bad = int(np.argmin(table))
        raise TactilecalError(f"{where}: the {model} law gives {table[bad]:.4g} N at raw {bad}; "
                              "expected forces >= 0 on raw 0..255")
    if not table[255] > 0:
        raise TactilecalError(f"{where}: the {model} law gives {table[255]:.4g} N at raw 255; "
                              "expected a positive force (and saturation pressure)")
