"""The dynamic-calibration correction filter (Gillis 2013, section 4.3.3, "digital filter").

The filter multiplies a sensor record's spectrum by the correction ``G(f)`` of the fitted
model. For the thesis' models (``log``, ``log10``, ``log-quadratic``) and a measured gain
(``response``) ``G`` is real: the filter has **zero phase**. For the models that carry the
sensor's phase (``rational``: a pole-zero model; ``wiener``: the measured complex correction,
regularised by its coherence) ``G`` is complex and undoes the sensor's lag too. Either way it
is realised as a FIR of ``n_taps`` taps centred on its middle tap (so no delay is
introduced), designed by frequency sampling with a Hamming window
(:func:`scipy.signal.firwin2` for a real ``G``, :func:`centred_fir` for a complex one), with
its DC gain set to exactly 1 (see :attr:`CorrectionFilter.taps`). A rational model also has
a causal form (:meth:`CorrectionFilter.sos`).

Target ``G(f)`` (:meth:`CorrectionFilter.target`):

* from 0 Hz to the top of the calibrated band ``band_hz[1]``: the model (equal to 1 at 0 Hz,
  so static calibrations are untouched) or the measured response;
* above the band, ``outside="taper"`` (default): the deviation from 1 at the band's top,
  ``G(hi) - 1``, falls to 0 with a raised cosine over ``taper_hz`` (for a complex ``G``, its
  log-magnitude and phase do, so the gain never passes through 0 on the way, as a straight
  line from a correction near -2 to 1 would): frequencies the calibration never saw are
  **not amplified** (left as recorded); ``outside="hold"``:
  ``G(hi)`` held to the Nyquist frequency (amplifies noise there by ``|G(hi)|``; only for
  records known to carry signal above the band).
"""

from dataclasses import dataclass, field

import numpy as np
from scipy import fft, signal

from tactilecal._errors import TactilecalError
from tactilecal._jsonutil import to_jsonable
from tactilecal._result import SavedResult
from tactilecal._validate import check_number, check_numbers, check_type, require_keys
from tactilecal.dynamic import _plots
from tactilecal.dynamic._fit import MAX_PARAM, MODELS, TransferFit, model_gain
from tactilecal.dynamic._rational import RationalModel

__all__ = ["CorrectionFilter", "load_filter", "FORMAT", "zero_phase_fir", "centred_fir",
           "centred_spectrum", "PHASE_MODELS"]

#: Floating-point type of the FFT work for each ``precision`` of ``apply_filter``.
PRECISIONS = {"single": np.float32, "double": np.float64}
#: Identifies FILTER.json files (the format tag of :mod:`tactilecal._result`).
FORMAT = "tactilecal-dynamic-filter/1"
_OUTSIDE = ("taper", "hold")
#: Models whose correction is complex (they undo the sensor's phase as well as its gain).
PHASE_MODELS = ("rational", "wiener")
#: Largest gain a filter (file) may apply anywhere: no sensor is a thousandfold out, so a
#: larger one is a damaged file; it would only write absurd or non-finite values.
MAX_GAIN = 1e3
#: Largest sampling rate (Hz) and FIR length (taps) a filter file may hold.
MAX_FS_HZ, MAX_TAPS = 1e7, 1 << 22


def _odd(n):
    n = int(np.ceil(n))
    return n + 1 if n % 2 == 0 else n


def zero_phase_fir(n_taps, grid_hz, gain, fs_hz):
    """Design a symmetric FIR of ``n_taps`` (odd) with ``gain`` on ``grid_hz``, DC ``gain[0]``.

    Frequency sampling (:func:`scipy.signal.firwin2`, Hamming window). A gain law with a
    kink at 0 Hz (the log's slope) is smoothed by the window into a DC gain above
    ``gain[0]`` (about 2 % for A = 0.11, log10, 1 Hz resolution); the excess is removed
    with a Hamming-shaped bump, which acts within 2 fs/n_taps of 0 Hz only (side lobes
    below -43 dB), so a static calibration is kept exactly.
    """
    taps = signal.firwin2(n_taps, grid_hz, gain, fs=fs_hz, window="hamming")
    bump = signal.get_window("hamming", n_taps, fftbins=False)
    return taps - (taps.sum() - gain[0]) * bump / bump.sum()


def centred_fir(n_taps, grid_hz, gain, fs_hz):
    """Design a FIR of ``n_taps`` (odd) centred on its middle tap with a real or complex ``gain``.

    A real ``gain`` gives the symmetric, zero-phase FIR of :func:`zero_phase_fir`. A complex
    one (``grid_hz`` uniform from 0 to ``fs_hz / 2``) is sampled by the inverse real FFT
    (frequency sampling: the impulse response of ``gain`` on the circle of
    ``2 (grid_hz.size - 1)`` samples), cut to ``n_taps`` about time 0 with a Hamming window
    and its DC gain set to ``gain[0]`` (a Hamming-shaped bump, as in :func:`zero_phase_fir`).
    The FIR is then not symmetric: it applies the phase of ``gain``, with no delay.
    """
    gain = np.asarray(gain)
    if not np.iscomplexobj(gain):
        return zero_phase_fir(n_taps, grid_hz, gain, fs_hz)
    impulse = fft.irfft(gain, n=2 * (gain.size - 1))
    half = n_taps // 2
    window = signal.get_window("hamming", n_taps, fftbins=False)
    taps = np.r_[impulse[impulse.size - half:], impulse[:half + 1]] * window
    return taps - (taps.sum() - gain[0].real) * window / window.sum()


def centred_spectrum(taps, n_fft, *, phase=False):
    """Return the half-spectrum of the FIR ``taps`` centred on an ``n_fft`` circle.

    Multiplying a block's ``rfft`` by it convolves the block circularly with the centred
    FIR (no delay); the overlap-save blocks of :mod:`tactilecal.dynamic._apply` use it.
    Real for a symmetric (zero-phase) FIR; complex with ``phase=True`` (:func:`centred_fir`
    of a complex gain).
    """
    half = taps.size // 2
    circ = np.zeros(n_fft)
    circ[:half + 1] = taps[half:]
    circ[n_fft - half:] = taps[:half]
    spectrum = fft.rfft(circ)
    return spectrum if phase else spectrum.real


@dataclass(repr=False, eq=False)
class CorrectionFilter(SavedResult):
    """Zero-phase correction filter; build it with :meth:`from_model` or :meth:`from_response`.

    Saved as FILTER.json, ``"format": "tactilecal-dynamic-filter/1"``
    (:meth:`to_json`, or :meth:`save`).

    Attributes
    ----------
    model : str
        ``"log"``, ``"log10"``, ``"log-quadratic"`` or ``"response"`` (measured gain).
    params : dict
        Model parameters (``{"A": ...}``); empty for ``"response"``.
    fs_hz : float
        Sampling rate the filter is designed for.
    band_hz : tuple of float
        Calibrated band ``(lo, hi)``.
    outside : {"taper", "hold"}
        Gain above ``hi`` (see the module notes).
    taper_hz : float
        Width of the taper above ``hi``.
    n_taps : int
        FIR length (odd); the frequency resolution is about ``fs_hz / n_taps``.
    response_f_hz, response_gain : numpy.ndarray or None
        The measured response of a ``"response"`` filter.
    fit : TransferFit or None
        The fit the filter came from.
    lag_s : float or None
        Lag found between the calibration records (see :func:`estimate_lag`).
    forced : str or None
        Why the fit was refused when the filter was built anyway (``force=True``).
    rational : RationalModel or None
        For ``model="rational"``: the sensor response ``H``; the filter applies ``1 / H``,
        magnitude and phase (offline by the centred FIR, or causally by :meth:`sos`).

    Examples
    --------
    >>> import tempfile, pathlib, tactilecal
    >>> filt = CorrectionFilter.from_model(("log10", {"A": 0.11}), fs_hz=1000.0, band_hz=(1, 100))
    >>> filt.n_taps, [round(float(g), 3) for g in filt.gain([0.0, 99.0, 400.0])]
    (1001, [1.0, 1.22, 1.0])
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "FILTER.json"
    >>> filt.to_json(path)
    >>> tactilecal.load(path) == filt
    True
    """

    FORMAT_KIND = "dynamic-filter"
    DESCRIPTION = "a FILTER.json written by 'tactilecal dynamic fit'"

    model: str
    params: dict
    fs_hz: float
    band_hz: tuple
    outside: str = "taper"
    taper_hz: float = 20.0
    n_taps: int = 4001
    response_f_hz: np.ndarray | None = None
    response_gain: np.ndarray | None = None
    fit: TransferFit | None = None
    lag_s: float | None = None
    forced: str | None = None
    rational: RationalModel | None = None
    _taps: np.ndarray | None = field(default=None, repr=False, compare=False)
    _spectra: dict = field(default_factory=dict, repr=False, compare=False)

    def __post_init__(self):
        lo, hi = (float(v) for v in self.band_hz)
        self.band_hz = (lo, hi)
        if not 0 <= lo < hi:
            raise TactilecalError(f"band_hz=({lo:g}, {hi:g}); expected 0 <= LO < HI")
        if hi > self.fs_hz / 2:
            raise TactilecalError(f"band_hz=({lo:g}, {hi:g}) reaches beyond the Nyquist frequency "
                                  f"{self.fs_hz / 2:g} Hz (fs_hz={self.fs_hz:g}); expected "
                                  f"HI <= {self.fs_hz / 2:g}")
        if self.outside not in _OUTSIDE:
            raise TactilecalError(f"outside={self.outside!r}; expected 'taper' or 'hold'")
        if self.taper_hz <= 0:
            raise TactilecalError(f"taper_hz={self.taper_hz}; expected > 0")
        self.n_taps = _odd(self.n_taps)

    # -- construction -------------------------------------------------------------------
    @classmethod
    def from_model(cls, fit, *, fs_hz, band_hz=None, outside="taper", taper_hz=None,
                   n_taps=None, lag_s=None):
        """Build the filter from a fitted model (eq. 4.1).

        Parameters
        ----------
        fit : TransferFit or tuple
            A fit, or ``(model, params)`` such as ``("log10", {"A": 0.11})``.
        fs_hz : float
            Sampling rate of the records it will correct.
        band_hz : tuple of float, optional
            Calibrated band (default: the range of the fitted bins).
        outside : {"taper", "hold"}
            Gain above the band.
        taper_hz : float, optional
            Taper width (default a quarter of the band's top, at least 5 Hz).
        n_taps : int, optional
            FIR length (default one second of samples, made odd: 1 Hz resolution).
        lag_s : float, optional
            Stored with the filter.

        Returns
        -------
        CorrectionFilter

        Examples
        --------
        >>> filt = CorrectionFilter.from_model(("log10", {"A": 0.11}), fs_hz=4000,
        ...                                    band_hz=(1, 140))
        >>> [round(float(g), 4) for g in filt.gain([0, 99, 140, 500])]
        [1.0, 1.22, 1.2364, 1.0]
        """
        if isinstance(fit, TransferFit):
            model, params = fit.model, dict(fit.params)
            if band_hz is None:
                band_hz = (float(fit.f_hz.min()), float(fit.f_hz.max()))
        else:
            model, params = fit[0], dict(fit[1])
            fit = None
            if band_hz is None:
                raise TactilecalError("band_hz is required when building from (model, params)")
        if model not in MODELS:
            raise TactilecalError(f"model={model!r}; expected one of {', '.join(MODELS)}")
        return cls.design(model, params, fs_hz=fs_hz, band_hz=band_hz, outside=outside,
                          taper_hz=taper_hz, n_taps=n_taps, fit=fit, lag_s=lag_s)

    @classmethod
    def design(cls, model, params, *, fs_hz, band_hz, outside="taper", taper_hz=None,
               n_taps=None, **fields):
        """Build a filter with the default design choices where none are given.

        ``taper_hz``: a quarter of the band's top, at least 5 Hz; ``n_taps``: one second of
        samples, made odd (1 Hz resolution). ``fields`` are the other attributes
        (``fit``, ``lag_s``, ``rational``, ``response_f_hz``, ...).
        """
        return cls(model, dict(params), float(fs_hz), tuple(band_hz), outside,
                   taper_hz or max(5.0, band_hz[1] / 4), n_taps or _odd(fs_hz), **fields)

    @classmethod
    def from_response(cls, f_hz, gain, *, fs_hz, band_hz=None, outside="taper",
                      taper_hz=None, n_taps=None, lag_s=None):
        """Build the filter from a measured gain ``|reference(f)| / |sensor(f)|``.

        The gain is linearly interpolated between the given bins (and to 1 at 0 Hz).

        Parameters
        ----------
        f_hz, gain : array_like
            Measured response (e.g. ``tf.f_hz[tf.used]``, ``tf.gain[tf.used]``).
        fs_hz, band_hz, outside, taper_hz, n_taps, lag_s
            As in :meth:`from_model` (default band: the range of ``f_hz``).

        Returns
        -------
        CorrectionFilter

        Examples
        --------
        >>> filt = CorrectionFilter.from_response([10, 20], [1.1, 1.2], fs_hz=400)
        >>> [round(float(g), 3) for g in filt.gain([0, 5, 15, 20])]
        [1.0, 1.05, 1.15, 1.2]
        """
        f_hz, gain = np.asarray(f_hz, float), np.asarray(gain, float)
        if f_hz.size < 2 or f_hz.shape != gain.shape or np.any(np.diff(f_hz) <= 0):
            raise TactilecalError(f"f_hz ({f_hz.size} values) and gain ({gain.size} values): "
                                  "expected equal lengths >= 2 and increasing frequencies")
        if band_hz is None:
            band_hz = (float(f_hz[0]), float(f_hz[-1]))
        return cls.design("response", {}, fs_hz=fs_hz, band_hz=band_hz, outside=outside,
                          taper_hz=taper_hz, n_taps=n_taps, response_f_hz=f_hz,
                          response_gain=gain, lag_s=lag_s)

    # -- frequency response -------------------------------------------------------------
    def sos(self):
        """Second-order sections of the causal inverse (``model="rational"`` only).

        An improper inverse (a response with more poles than zeros, e.g. a resonance)
        rolls off with real poles at the taper's top (below 0.45 ``fs_hz``); see
        :meth:`RationalModel.inverse_sos`.
        """
        if self.rational is None:
            raise TactilecalError(f"a {self.model!r} filter has no causal (IIR) form; expected a "
                                  "rational model (tactilecal dynamic fit --model rational|auto)")
        rolloff_hz = min(self.band_hz[1] + self.taper_hz, 0.45 * self.fs_hz)
        return self.rational.inverse_sos(self.fs_hz, rolloff_hz=rolloff_hz)

    @property
    def has_phase(self):
        """True when the correction is complex (``model`` in :data:`PHASE_MODELS`)."""
        return self.model in PHASE_MODELS

    def _inside(self, f_hz):
        """Return the correction inside the band: the model or the measured response."""
        if self.model == "rational":
            return self.rational.correction(f_hz)
        if self.model in ("response", "wiener"):
            keep = self.response_f_hz > 0
            f = np.r_[0.0, self.response_f_hz[keep]]
            g = np.r_[1.0, self.response_gain[keep]]
            if self.model == "response":
                return np.interp(f_hz, f, g)
            return np.interp(f_hz, f, g.real) + 1j * np.interp(f_hz, f, g.imag)
        return model_gain(self.model, self.params, f_hz)

    def target(self, f_hz):
        """Return the correction ``G(f)`` the filter applies (see the module notes).

        Real for the zero-phase models, complex for :data:`PHASE_MODELS`.
        """
        f_hz = np.asarray(f_hz, dtype=float)
        hi = self.band_hz[1]
        inside = self._inside(np.minimum(f_hz, hi))
        if self.outside == "hold":
            return inside
        x = np.clip((f_hz - hi) / self.taper_hz, 0.0, 1.0)
        weight = 0.5 * (1.0 + np.cos(np.pi * x))
        if np.iscomplexobj(inside):  # log-magnitude and phase to 0: never through 0 gain
            return np.exp(weight * np.log(inside))
        return 1.0 + (inside - 1.0) * weight

    def gain(self, f_hz):
        """Return the magnitude of the correction, ``|G(f)|`` (see :meth:`target`)."""
        return np.abs(self.target(f_hz))

    @property
    def taps(self):
        """The centred FIR (length ``n_taps``) realising :meth:`target`, with no delay.

        Raises
        ------
        TactilecalError
            A correction that is not finite or larger than ``MAX_GAIN`` somewhere: the
            filter could only write non-finite or absurd values.
        """
        if self._taps is None:
            grid = np.linspace(0.0, self.fs_hz / 2, 8 * self.n_taps + 1)
            with np.errstate(all="ignore"):
                target = self.target(grid)
            bad = ~np.isfinite(target) | (np.abs(target) > MAX_GAIN)
            if bad.any():
                k = int(np.flatnonzero(bad)[0])
                raise TactilecalError(f"the {self.model} filter's correction is {target[k]:.3g} at "
                                      f"{grid[k]:.4g} Hz; expected a finite gain up to "
                                      f"{MAX_GAIN:g}")
            self._taps = centred_fir(self.n_taps, grid, target, self.fs_hz)
        return self._taps

    def realised_gain(self, f_hz):
        """Return the gain the FIR actually applies at ``f_hz`` (its magnitude)."""
        return np.abs(self.realised_target(f_hz))

    def realised_target(self, f_hz):
        """Return the complex response the centred FIR actually applies at ``f_hz``."""
        f_hz = np.asarray(f_hz, float)
        _, h = signal.freqz(self.taps, worN=f_hz, fs=self.fs_hz)
        return h * np.exp(2j * np.pi * f_hz / self.fs_hz * (self.n_taps // 2))  # centred

    @property
    def length_s(self):
        """FIR length in seconds: the shortest record it can correct."""
        return self.n_taps / self.fs_hz

    def spectrum(self, n_fft):
        """Real half-spectrum of the centred FIR on an ``n_fft``-point grid (overlap-save)."""
        if n_fft not in self._spectra:
            self._spectra[n_fft] = centred_spectrum(self.taps, n_fft, phase=self.has_phase)
        return self._spectra[n_fft]

    # -- JSON ---------------------------------------------------------------------------
    def _to_dict(self):
        """Return the FILTER.json content (keys of the CLI contract first), JSON-ready."""
        return to_jsonable({
            "model": self.model,
            "A": self.params.get("A"),
            "log_base": MODELS[self.model][0] if self.model in MODELS else None,
            "lag_s": self.lag_s,
            "fs_hz": self.fs_hz,
            "band_hz": list(self.band_hz),
            "fit": None if self.fit is None else self.fit.to_dict(),
            "params": self.params,
            "outside": self.outside,
            "taper_hz": self.taper_hz,
            "n_taps": self.n_taps,
            "response": None if self.response_f_hz is None else {
                "f_hz": self.response_f_hz, "gain": np.abs(self.response_gain),
                **({"phase_rad": np.angle(self.response_gain)} if self.has_phase else {})},
            "forced": self.forced is not None,
            "forced_reason": self.forced,
            "rational": None if self.rational is None else self.rational.to_dict(),
            "correction": self._correction_grid(),
        })

    def _correction_grid(self, n_points=256):
        """Return the correction on a grid up to the taper's top (FILTER.json ``correction``)."""
        f_hz = np.linspace(0.0, min(self.fs_hz / 2, self.band_hz[1] + self.taper_hz), n_points)
        target = self.target(f_hz)
        return {"f_hz": f_hz, "gain": np.abs(target), "phase_deg": np.degrees(np.angle(target))}

    @classmethod
    def from_dict(cls, d, *, where="filter", source=None):
        """Rebuild a filter from :meth:`to_dict` output (``source``/``where`` names it)."""
        return super().from_dict(d, source=source or where)

    @classmethod
    def check_format(cls, d, source):
        """Raise unless ``d`` has the filter's tag and keys (FILTER.json always had the tag)."""
        check_type(d, dict, source, expected=f"{cls.DESCRIPTION} object")
        missing = [k for k in ("model", "fs_hz", "band_hz", "params", "outside", "taper_hz",
                               "n_taps") if k not in d]
        if d.get("format") != FORMAT or missing:
            raise TactilecalError(f"{source}: not a tactilecal dynamic filter (format "
                                  f"{d.get('format')!r}, missing keys {missing}); expected "
                                  f"format {FORMAT!r} as written by 'tactilecal dynamic fit'")

    @classmethod
    def _from_dict(cls, d, where):
        _check_filter_dict(d, where)
        response = d.get("response") or {}
        gain = None if not response else np.asarray(response["gain"], float)
        if "phase_rad" in response:
            gain = gain * np.exp(1j * np.asarray(response["phase_rad"], float))
        fit = d.get("fit")
        filt = cls(d["model"], dict(d["params"]), float(d["fs_hz"]), tuple(d["band_hz"]),
                   d["outside"], float(d["taper_hz"]), int(d["n_taps"]),
                   None if not response else np.asarray(response["f_hz"], float), gain,
                   None if fit is None else TransferFit.from_dict(fit, f"key 'fit' of {where}"),
                   d.get("lag_s"), d.get("forced_reason"),
                   None if d.get("rational") is None else RationalModel.from_dict(d["rational"]))
        _check_correction(filt, where)
        return filt

    def _repr_fields(self):
        return [("model", self.model), ("params", self.params), ("fs_hz", self.fs_hz),
                ("band_hz", self.band_hz), ("outside", self.outside),
                ("n_taps", self.n_taps), ("lag_s", self.lag_s), ("forced", self.forced)]

    plot_transfer = _plots.plot_transfer  # thesis Figure 4.9

    def summary(self):
        """Return the filter and the fit it came from as readable lines."""
        pars = (self.rational.describe() if self.rational is not None else
                ", ".join(f"{k} = {v:.5g}" for k, v in self.params.items()))
        above = (f"tapers to 1 by {self.band_hz[1] + self.taper_hz:g} Hz"
                 if self.outside == "taper" else "holds the band's top gain")
        lines = []
        fit = self.fit
        if fit is not None:
            if self.model in MODELS:
                lines.append(f"fit: {fit.summary()}")
            if fit.band_note:
                lines.append(f"band: {fit.band_note}")
            if fit.model_choice is not None:
                lines.append(f"model choice: {fit.model_choice.summary()}")
            delay = fit.model_choice.delay_s if fit.model_choice is not None else fit.delay_s
            if self.lag_s is not None:
                lines.append(f"clock: lag {self.lag_s:.6f} s added to the reference's times "
                             f"(the alignment's lag minus the model's delay "
                             f"{1e3 * delay:.3g} ms); static factor {fit.static_factor:.6g}")
            if fit.amplitude is not None:
                lines.append(f"amplitude: {fit.amplitude.summary()}")
        lines.append(f"filter: {self.model} ({pars}) for {self.fs_hz:g} Hz, band "
                     f"{self.band_hz[0]:g}..{self.band_hz[1]:g} Hz, above it {above}; "
                     f"{self.n_taps} taps ({self.length_s:.3g} s)")
        if self.forced:
            lines.append(f"FORCED: {self.forced}")
        return "\n".join(lines)


def _check_filter_dict(d, where):
    """Types and ranges of a FILTER.json's keys, before any is used (names the file and key).

    Every number is finite and bounded: a rate up to ``MAX_FS_HZ``, at most ``MAX_TAPS``
    taps, parameters within ``MAX_PARAM``, measured gains in ``(1 / MAX_GAIN, MAX_GAIN]``,
    poles and zeros in the left half-plane below the Nyquist frequency.
    """
    key = f"key '{{}}' of {where}".format
    fs_hz = check_number(d["fs_hz"], key("fs_hz"), minimum=0.0, min_inclusive=False,
                         maximum=MAX_FS_HZ)
    band = check_type(d["band_hz"], list | tuple, key("band_hz"), expected="[low, high] in Hz")
    if len(band) != 2:
        raise TactilecalError(f"{key('band_hz')} has {len(band)} values; expected [low, high]")
    low, high = (check_number(v, key("band_hz"), minimum=0.0, maximum=fs_hz / 2) for v in band)
    if not low < high:
        raise TactilecalError(f"{key('band_hz')} is {band}; expected low < high")
    if d["model"] not in (*MODELS, "response", *PHASE_MODELS):
        raise TactilecalError(f"{key('model')} is {str(d['model'])[:40]!r}; expected one of "
                              f"{[*MODELS, 'response', *PHASE_MODELS]}")
    if d["model"] == "rational" or d.get("rational") is not None:
        _check_rational(d.get("rational"), key, fs_hz)
    for name, value in check_type(d["params"], dict, key("params"),
                                  expected="an object of numbers").items():
        check_number(value, key(f"params.{name}"), minimum=-MAX_PARAM, maximum=MAX_PARAM)
    if d["model"] in MODELS:
        require_keys(d["params"], MODELS[d["model"]][1], key("params"),
                     expected=f"the parameters of the {d['model']} model")
    if d["outside"] not in ("taper", "hold"):
        raise TactilecalError(f"{key('outside')} is {str(d['outside'])[:40]!r}; expected 'taper' "
                              "or 'hold'")
    check_number(d["taper_hz"], key("taper_hz"), minimum=0.0, min_inclusive=False,
                 maximum=MAX_FS_HZ)
    if d.get("fit") is not None:
        check_type(d["fit"], dict, key("fit"), expected="an object")
    check_number(d["n_taps"], key("n_taps"), minimum=1, maximum=MAX_TAPS, integer=True)
    check_number(d.get("lag_s"), key("lag_s"), minimum=-86400.0, maximum=86400.0,
                 allow_none=True)
    _check_response(d, key, fs_hz)


def _check_rational(rational, key, fs_hz):
    """Check a rational model: roots in the left half-plane below Nyquist, a positive gain."""
    check_type(rational, dict, key("rational"),
               expected="the zeros, poles and gain of a rational model")
    require_keys(rational, ("zeros_rad_s", "poles_rad_s", "gain"), key("rational"),
                 expected="a rational model")
    nyquist_rad_s = np.pi * fs_hz
    for name in ("zeros_rad_s", "poles_rad_s"):
        where = key(f"rational.{name}")
        for pair in check_type(rational[name], list, where, expected="a list of [re, im] pairs"):
            if not isinstance(pair, list) or len(pair) != 2:
                raise TactilecalError(f"{where} holds {str(pair)[:40]}; expected [re, im] pairs")
            check_number(pair[0], where, minimum=-nyquist_rad_s, maximum=0.0,
                         max_inclusive=False)
            check_number(pair[1], where, minimum=-nyquist_rad_s, maximum=nyquist_rad_s)
    check_number(rational["gain"], key("rational.gain"), minimum=0.0, min_inclusive=False)


def _check_response(d, key, fs_hz):
    """Check a response: lists of one length, increasing frequencies, bounded gains."""
    response = d.get("response") or {}
    check_type(response, dict, key("response"), expected="an object")
    if d["model"] in ("response", "wiener") and not response:
        raise TactilecalError(f"{key('response')} is missing; a {d['model']!r} filter needs its "
                              "measured response")
    if not response:
        return
    require_keys(response, ("f_hz", "gain"), key("response"), expected="a response")
    lengths = set()
    for name in ("f_hz", "gain", "phase_rad"):
        if name == "phase_rad" and name not in response:
            continue
        lengths.add(len(check_numbers(response[name], key(f"response.{name}"))))
    if len(lengths) > 1 or min(lengths) < 2:
        raise TactilecalError(f"{key('response')} has lists of lengths {sorted(lengths)}; "
                              "expected f_hz, gain (and phase_rad) of one length >= 2")
    f_hz, gain = np.asarray(response["f_hz"], float), np.asarray(response["gain"], float)
    if np.any(np.diff(f_hz) <= 0) or f_hz[0] < 0 or f_hz[-1] > fs_hz / 2:
        raise TactilecalError(f"{key('response.f_hz')} runs from {f_hz[0]:g} to {f_hz[-1]:g} Hz "
                              f"or does not increase; expected increasing frequencies within "
                              f"0..{fs_hz / 2:g} Hz")
    bad = np.flatnonzero(~((gain > 1.0 / MAX_GAIN) & (gain <= MAX_GAIN)))
    if bad.size:
        raise TactilecalError(f"{key('response.gain')} holds {gain[bad[0]]:.3g} at "
                              f"{f_hz[bad[0]]:g} Hz; expected gains in ({1 / MAX_GAIN:g}, "
                              f"{MAX_GAIN:g}]")


def _check_correction(filt, where):
    """Refuse parameters whose correction is not finite, positive and bounded in the band."""
    grid = np.linspace(0.0, filt.band_hz[1], 65)
    with np.errstate(all="ignore"):
        target = filt.target(grid)
    size = np.abs(target) if filt.has_phase else target
    bad = ~np.isfinite(target) | (size <= 0) | (size > MAX_GAIN)
    if bad.any():
        k = int(np.flatnonzero(bad)[0])
        source = {"rational": "rational", "wiener": "response", "response": "response"}.get(
            filt.model, "params")
        raise TactilecalError(f"key '{source}' of {where}: the correction it gives is "
                              f"{target[k]:.3g} at {grid[k]:.3g} Hz; expected a finite, positive "
                              f"gain up to {MAX_GAIN:g} in the band")


def load_filter(path):
    """Read a FILTER.json written by :meth:`CorrectionFilter.save`.

    The same as ``CorrectionFilter.from_json(path)``.

    Raises
    ------
    ValueError
        Not JSON, or not a filter file.
    """
    return CorrectionFilter.from_json(path)
