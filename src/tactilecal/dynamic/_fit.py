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
from tactilecal._jsonutil import to_jsonable
from tactilecal._validate import check_number, check_numbers, check_type, require_keys
from tactilecal.dynamic._fitparts import AmplitudeCheck, ModelChoice, _ByValue

__all__ = ["MODELS", "MODEL_TEXT", "TransferFit", "complex_r2", "fit_transfer", "model_gain",
           "fit_delay", "MAX_PARAM"]

#: name -> (log base, parameter names)
MODELS = {"log": ("e", ("A",)), "log10": ("10", ("A",)), "log-quadratic": ("e", ("A", "B"))}
#: Each model's law in words.
MODEL_TEXT = {"log": "Y = 1 + A ln(f + 1)", "log10": "Y = 1 + A log10(f + 1)",
              "log-quadratic": "Y = 1 + A L + B L^2, L = ln(f + 1)"}
#: Largest magnitude of a model parameter a file may hold (A = 1e3 is a gain of 3000 at
#: 1 kHz: no sensor; larger values are a damaged file, refused by name).
MAX_PARAM = 1e3
#: Bounds (ms) and grid step (share of the top bin's period) of :func:`fit_delay`.
MAX_DELAY_MS = 20.0
_DELAY_STEP = 0.02


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


@dataclass(eq=False)
class TransferFit(_ByValue):
    """Result of fitting the thesis' model to a measured transfer function, and of the choice.

    Equal to another fit when every value is (arrays element by element, NaN equal to NaN).

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
        Bins left out, by reason (``low_coherence``, ``low_power``, ``outside_band``,
        ``zero_frequency``): counts, nothing else.
    r2_complex : float
        Share of the *complex* correction (magnitude and phase) the model, with its
        delay, explains over the used bins (:func:`complex_r2`); a zero-phase model of a
        sensor that lags scores low. NaN when the transfer function carried no phase.
    delay_s : float
        The model's delay ``tau``, fitted to the phase with the model's gain
        (:func:`fit_delay`): ``C ~ Y(f) exp(-j 2 pi f tau)``.
    static_factor : float
        ``mean(reference) / mean(sensor)`` the sweep was scaled by (:func:`fit_filter`;
        NaN when unknown).
    band_note : str
        Where the band of coherent energy ends, and why (:func:`fit_filter`).
    model_choice : ModelChoice or None
        How :func:`fit_filter` chose the filter's model.
    amplitude : AmplitudeCheck or None
        The comparison of sweeps at different amplitudes, when several were fitted.
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
    r2_complex: float = float("nan")
    delay_s: float = 0.0
    static_factor: float = float("nan")
    band_note: str = ""
    model_choice: ModelChoice | None = None
    amplitude: AmplitudeCheck | None = None

    @property
    def A(self):
        """The slope ``A`` of eq. 4.1 in the model's own log base."""
        return self.params["A"]

    @property
    def A_log10(self):
        """``A`` in the thesis' decimal-log base (``A ln 10`` for a natural-log model)."""
        return self.params["A"] * (np.log(10.0) if self.log_base == "e" else 1.0)

    def gain(self, f_hz):
        """Return the fitted ``Y(f)``."""
        return model_gain(self.model, self.params, f_hz)

    def summary(self):
        """Return the fit in one readable line (``A`` in log10 base, the thesis' reading)."""
        pars = ", ".join(f"{k} = {v:.5g} +- {self.stderr[k]:.2g}" for k, v in self.params.items())
        if self.model in ("log", "log-quadratic"):
            pars += f" (natural log; A in log10 base {self.A_log10:.5g})"
        elif self.model == "log10":
            pars += f" (natural-log A {self.A / np.log(10.0):.5g})"
        return (f"{MODEL_TEXT[self.model]}: {pars}; R2 {self.r2:.4f}, complex R2 "
                f"{self.r2_complex:.4f} over {self.f_hz.size} bins "
                f"{self.f_hz.min():g}..{self.f_hz.max():g} Hz ({self.method})")

    def to_dict(self):
        """Return a JSON-ready dict (the ``fit`` entry of FILTER.json)."""
        return to_jsonable({
            "model": self.model, "log_base": self.log_base, "params": self.params,
            "stderr": self.stderr, "r2": self.r2, "r2_complex": self.r2_complex,
            "rmse": self.rmse, "method": self.method, "excluded": self.excluded,
            "delay_s": self.delay_s, "static_factor": self.static_factor,
            "band_note": self.band_note,
            "model_choice": None if self.model_choice is None else self.model_choice.to_dict(),
            "amplitude": None if self.amplitude is None else self.amplitude.to_dict(),
            "f_hz": self.f_hz, "measured": self.measured, "fitted": self.fitted,
            "residuals": self.residuals})

    @classmethod
    def from_dict(cls, d, where="fit"):
        """Rebuild from :meth:`to_dict` output, checking every key (messages name ``where``)."""
        key = f"key '{{}}' of {where}".format
        require_keys(d, ("model", "log_base", "params", "stderr", "r2", "rmse", "f_hz",
                         "measured", "fitted", "residuals"), where,
                     expected="a transfer-function fit")
        if d["model"] not in MODELS:
            raise TactilecalError(f"{key('model')} is {d['model']!r}; expected one of "
                                  f"{', '.join(MODELS)}")
        arrays = {k: np.asarray(check_numbers(d[k], key(k)), dtype=float)
                  for k in ("f_hz", "measured", "fitted", "residuals")}
        if len({a.size for a in arrays.values()}) != 1:
            raise TactilecalError(f"{key('f_hz')}: f_hz, measured, fitted and residuals of "
                                  f"lengths {[a.size for a in arrays.values()]}; expected one")
        params = {k: check_number(v, key(f"params.{k}"), minimum=-MAX_PARAM, maximum=MAX_PARAM)
                  for k, v in check_type(d["params"], dict, key("params"),
                                         expected="an object of numbers").items()}
        stderr = {k: _number(v, key(f"stderr.{k}")) for k, v in check_type(
            d["stderr"], dict, key("stderr"), expected="an object of numbers").items()}
        excluded = {k: check_number(v, key(f"excluded.{k}"), minimum=0, integer=True)
                    for k, v in check_type(d.get("excluded", {}), dict, key("excluded"),
                                           expected="an object of bin counts").items()}
        choice, amplitude = d.get("model_choice"), d.get("amplitude")
        return cls(model=d["model"], log_base=MODELS[d["model"]][0], params=params,
                   stderr=stderr, r2=_number(d["r2"], key("r2")),
                   rmse=_number(d["rmse"], key("rmse"), minimum=0.0),
                   method=str(d.get("method", "h2")), excluded=excluded,
                   r2_complex=_number(d.get("r2_complex"), key("r2_complex")),
                   delay_s=_number(d.get("delay_s", 0.0), key("delay_s"), minimum=-1.0,
                                   maximum=1.0),
                   static_factor=_number(d.get("static_factor"), key("static_factor")),
                   band_note=str(d.get("band_note") or ""),
                   model_choice=None if choice is None else ModelChoice.from_dict(
                       choice, key("model_choice")),
                   amplitude=None if amplitude is None else AmplitudeCheck.from_dict(
                       amplitude, key("amplitude")), **arrays)


def _number(value, where, **bounds):
    """Return a JSON number (NaN for null) checked finite and, with ``bounds``, in range."""
    value = check_number(value, where, allow_none=True, **bounds)
    return float("nan") if value is None else float(value)


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
    spread = np.sum((y - y.mean()) ** 2)
    r2 = 1.0 - np.sum(residuals**2) / spread if spread > 0 else float("nan")
    delay_s, r2c = 0.0, float("nan")
    if tf.response is not None:
        measured = tf.response[tf.used]
        error = np.ones(f_hz.size) if tf.gain_error is None else tf.gain_error[tf.used]
        delay_s = fit_delay(f_hz, measured, fitted, error)
        r2c = complex_r2(measured, fitted * np.exp(-2j * np.pi * f_hz * delay_s))
    return TransferFit(model, base, params, stderr, f_hz, y, fitted, residuals, float(r2),
                       float(np.sqrt(np.mean(residuals**2))), tf.method, dict(tf.excluded),
                       r2c, delay_s)


def fit_delay(f_hz, measured, model, gain_error, *, max_delay_ms=MAX_DELAY_MS):
    """Fit the delay ``tau`` of ``measured ~ model exp(-j 2 pi f tau)`` (s).

    Weighted least squares of the complex relative residual (weights ``1 / e^2``, ``e``
    each bin's normalised random error, Bendat & Piersol eq. 9.90) over
    ``|tau| <= max_delay_ms``: a grid fine enough for the top bin's phase (steps of
    ``_DELAY_STEP`` of its period), refined by a bounded scalar search around the best
    point. The measured correction of records aligned at lag ``L`` is that of records at
    the clock offset ``L - tau`` times ``exp(-j 2 pi f tau)``.

    Examples
    --------
    >>> f = np.arange(1.0, 150.0)
    >>> y = 1 + 0.11 * np.log10(f + 1)
    >>> round(1e3 * fit_delay(f, y * np.exp(-2j * np.pi * f * 0.0021), y, np.ones(f.size)), 6)
    2.1
    """
    f_hz = np.asarray(f_hz, float)
    measured, model = np.asarray(measured, complex), np.asarray(model, complex)
    weight = 1.0 / np.maximum(np.asarray(gain_error, float), 1e-9) ** 2 / np.abs(measured) ** 2

    def cost(tau_s):
        rotated = model * np.exp(-2j * np.pi * np.multiply.outer(np.atleast_1d(tau_s), f_hz))
        return np.sum(weight * np.abs(measured - rotated) ** 2, axis=-1)

    step_s = _DELAY_STEP / max(float(f_hz.max()), 1e-9)
    grid = np.arange(-max_delay_ms * 1e-3, max_delay_ms * 1e-3 + step_s / 2, step_s)
    best = grid[int(np.argmin(np.concatenate([cost(c) for c in np.array_split(
        grid, max(1, grid.size // 256))])))]
    found = optimize.minimize_scalar(lambda t: float(cost(t)[0]), method="bounded",
                                     bounds=(best - step_s, best + step_s),
                                     options={"xatol": 1e-9})
    return float(found.x)


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
    if not correction > 0:  # the identity: nothing to explain
        return float("nan")
    return float(1.0 - np.sum(np.abs(measured - model) ** 2) / correction)
