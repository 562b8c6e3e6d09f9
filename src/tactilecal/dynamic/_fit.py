"""Fit of the transfer-function models (Gillis 2013, eq. 4.1) and its result object.

Models (``Y`` is ``|reference(f)| / |sensor(f)|``, ``f`` in Hz):

``"log"``
    ``Y = A ln(f + 1) + 1`` (eq. 4.1 with the natural log; ``log_base = "e"``).
``"log10"``
    ``Y = A log10(f + 1) + 1`` (eq. 4.1 with the decimal log; ``log_base = "10"``).
    The thesis gives A = 0.11 without a base; the two readings differ by a factor
    ln(10) = 2.30 in A, so the base is always stored with the fit.
``"log-quadratic"``
    ``Y = A L + B L^2 + 1`` with ``L = ln(f + 1)``: a more flexible curve, still 1 at DC.

All models equal 1 at 0 Hz, so the correction never changes a static calibration.
"""

from dataclasses import dataclass, field

import numpy as np
from scipy import optimize

from tactilecal._errors import TactilecalError

__all__ = ["MODELS", "TransferFit", "complex_r2", "fit_transfer", "model_gain"]

#: name -> (log base, parameter names)
MODELS = {"log": ("e", ("A",)), "log10": ("10", ("A",)), "log-quadratic": ("e", ("A", "B"))}


def _check_model(model):
    if model not in MODELS:
        raise TactilecalError(f"model={model!r}; expected one of {', '.join(MODELS)}")


def model_gain(model, params, f_hz):
    """Evaluate a transfer-function model.

    Parameters
    ----------
    model : {"log", "log10", "log-quadratic"}
    params : dict
        ``{"A": ...}`` (and ``"B"`` for ``"log-quadratic"``).
    f_hz : array_like
        Frequencies in Hz (>= 0).

    Returns
    -------
    numpy.ndarray
        ``Y(f)`` of eq. 4.1 (or its quadratic extension).

    Examples
    --------
    >>> round(float(model_gain("log10", {"A": 0.11}, 99.0)), 6)
    1.22
    >>> round(float(model_gain("log", {"A": 0.11}, 99.0)), 4)
    1.5066
    """
    _check_model(model)
    f_hz = np.asarray(f_hz, dtype=float)
    log = np.log10(f_hz + 1.0) if model == "log10" else np.log(f_hz + 1.0)
    return 1.0 + params["A"] * log + params.get("B", 0.0) * log**2


@dataclass
class TransferFit:
    """Result of fitting a model to a measured transfer function.

    Attributes
    ----------
    model, log_base : str
        Model name and the base of its logarithm (``"e"`` or ``"10"``).
    params, stderr : dict
        Fitted parameters and their standard errors (from the covariance of
        :func:`scipy.optimize.curve_fit`).
    f_hz, measured, fitted, residuals : numpy.ndarray
        The bins used, their measured ``Y``, the model and ``measured - fitted``.
    r2, rmse : float
        Coefficient of determination and root-mean-square residual over the used bins.
    method : str
        Transfer-function estimator (``"h2"``, ``"h1"``, ``"ratio"``).
    excluded : dict
        Bins left out and why (``low_coherence``, ``outside_band``, ``zero_frequency``).
    r2_complex : float or None
        Share of the *complex* correction (magnitude and phase) the model explains over the
        used bins (:func:`complex_r2`); the models here have no phase, so a sensor that lags
        scores low. None when the transfer function carried no complex response.
    """

    model: str
    log_base: str
    params: dict
    stderr: dict
    f_hz: np.ndarray
    measured: np.ndarray
    fitted: np.ndarray
    residuals: np.ndarray
    r2: float
    rmse: float
    method: str = "h2"
    excluded: dict = field(default_factory=dict)
    r2_complex: float | None = None

    @property
    def A(self):
        """The slope ``A`` of eq. 4.1."""
        return self.params["A"]

    def gain(self, f_hz):
        """Return the fitted ``Y(f)``."""
        return model_gain(self.model, self.params, f_hz)

    def summary(self):
        """Return a short human-readable description of the fit."""
        pars = ", ".join(f"{k} = {v:.5g} +- {self.stderr[k]:.2g}" for k, v in self.params.items())
        return (f"model {self.model} (log base {self.log_base}): {pars}; R2 = {self.r2:.4f}, "
                f"RMS residual = {self.rmse:.3g} over {self.f_hz.size} bins "
                f"{self.f_hz.min():g}..{self.f_hz.max():g} Hz ({self.method}); "
                f"left out: {self.excluded}")

    def to_dict(self):
        """Return a JSON-ready dict (the ``fit`` entry of FILTER.json)."""
        return {"model": self.model, "log_base": self.log_base, "params": self.params,
                "stderr": self.stderr, "r2": self.r2, "r2_complex": self.r2_complex,
                "rmse": self.rmse,
                "method": self.method, "excluded": self.excluded, "f_hz": self.f_hz,
                "measured": self.measured, "fitted": self.fitted, "residuals": self.residuals}

    @classmethod
    def from_dict(cls, d):
        """Rebuild from :meth:`to_dict` output."""
        arrays = {k: np.asarray(d[k], dtype=float)
                  for k in ("f_hz", "measured", "fitted", "residuals")}
        return cls(model=d["model"], log_base=d["log_base"], params=dict(d["params"]),
                   stderr=dict(d["stderr"]), r2=float(d["r2"]), rmse=float(d["rmse"]),
                   method=d.get("method", "h2"), excluded=dict(d.get("excluded", {})),
                   r2_complex=d.get("r2_complex"), **arrays)


def fit_transfer(tf, *, model="log10"):
    """Fit eq. 4.1 (or the quadratic extension) to the used bins of a transfer function.

    Parameters
    ----------
    tf : TransferFunction
        From :func:`transfer_function`; only ``tf.used`` bins enter the fit.
    model : {"log10", "log", "log-quadratic"}

    Returns
    -------
    TransferFit

    Raises
    ------
    ValueError
        Unknown model, or fewer used bins than parameters + 2.

    Notes
    -----
    Least squares on ``Y`` (unweighted) with :func:`scipy.optimize.curve_fit`; the
    standard errors assume independent bins (Welch bins of a Hann window overlap by
    about one neighbour, so they are somewhat optimistic).

    Examples
    --------
    >>> from tactilecal.dynamic._transfer import TransferFunction
    >>> f = np.arange(0.0, 200.0)
    >>> y = 1 + 0.11 * np.log10(f + 1)
    >>> tf = TransferFunction(f, y, np.ones_like(f), f > 0, "h2", 400.0, 400, 0.9)
    >>> fit = fit_transfer(tf, model="log10")
    >>> round(fit.A, 6), fit.log_base, round(fit.r2, 6)
    (0.11, '10', 1.0)
    """
    _check_model(model)
    base, names = MODELS[model]
    f_hz, y = tf.f_hz[tf.used], tf.gain[tf.used]
    if f_hz.size < len(names) + 2:
        raise TactilecalError(f"only {f_hz.size} frequency bins have coherence >= "
                              f"{tf.min_coherence} inside the band; expected at least "
                              f"{len(names) + 2} (check the records overlap and carry a sweep, "
                              "or lower min_coherence)")

    def curve(f, *p):
        return model_gain(model, dict(zip(names, p, strict=True)), f)

    popt, pcov = optimize.curve_fit(curve, f_hz, y, p0=[0.1] * len(names))
    params = dict(zip(names, (float(v) for v in popt), strict=True))
    stderr = dict(zip(names, (float(v) for v in np.sqrt(np.diag(pcov))), strict=True))
    fitted = curve(f_hz, *popt)
    residuals = y - fitted
    r2 = 1.0 - np.sum(residuals**2) / np.sum((y - y.mean()) ** 2)
    r2c = None if tf.response is None else complex_r2(tf.response[tf.used], fitted)
    return TransferFit(model, base, params, stderr, f_hz, y, fitted, residuals, float(r2),
                       float(np.sqrt(np.mean(residuals**2))), tf.method, dict(tf.excluded),
                       r2c)


def complex_r2(measured, model):
    """Share of a complex correction that a model explains (1 = all; can be negative).

    ``1 - sum |C - Y|**2 / sum |C - 1|**2`` over the bins, with ``C`` the measured complex
    ``reference / sensor`` and ``Y`` the model: the part of the correction ``C - 1`` (what a
    filter must do) that the model does, magnitude and phase alike. Referred to the
    identity rather than to the mean of ``C``, it does not punish a sensor whose gain
    barely varies for its noise (on the thesis' full sweep: 0.998; a zero-phase model of a
    sensor with a first-order lag, gain 1 -> 0.25 over 10-40 Hz: 0.56).

    Examples
    --------
    >>> f = np.linspace(1, 100, 50)
    >>> gain = 1 + 0.1 * np.log(f)
    >>> round(complex_r2(gain * np.exp(0j), gain), 6)
    1.0
    >>> complex_r2(gain * np.exp(-1j * f / 40), gain) < 0.9  # a lag the model cannot show
    True
    """
    measured = np.asarray(measured, dtype=complex)
    correction = np.sum(np.abs(measured - 1.0) ** 2)
    return float(1.0 - np.sum(np.abs(measured - model) ** 2) / correction) if correction > 0 \
        else float("nan")
