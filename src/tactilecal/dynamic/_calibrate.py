"""The dynamic-calibration workflow: fit a filter, evaluate it, transfer it between sensors.

Gillis (2013), sections 4.3 (calibration on a sine sweep), 4.4.1 (blind tests) and 4.5
(one sensor's filter applied to another sensor's sweep).
"""

from dataclasses import dataclass, field

import numpy as np
from scipy import signal

from tactilecal._errors import TactilecalError
from tactilecal._jsonutil import read_json_object
from tactilecal._provenance import provenance_of
from tactilecal._result import ShortRepr
from tactilecal._validate import check_number, check_numbers, check_type, require_keys
from tactilecal.dynamic import _plots
from tactilecal.dynamic._align import align
from tactilecal.dynamic._apply import apply_filter
from tactilecal.dynamic._files import write_evaluation
from tactilecal.dynamic._filter import CorrectionFilter
from tactilecal.dynamic._fit import fit_transfer
from tactilecal.dynamic._ratfit import (
    MATERIAL_ERROR,
    MIN_IMPROVEMENT,
    choose_rational,
    held_out_bins,
    held_out_score,
)
from tactilecal.dynamic._records import label, sampling_rate_hz, time_and_values
from tactilecal.dynamic._transfer import _check_band, transfer_function
from tactilecal.dynamic._wiener import wiener_correction, wiener_held_out

__all__ = ["fit_filter", "evaluate", "Evaluation", "compare_filters", "static_factor",
           "dynamic_part"]


def static_factor(sensor, reference):
    """Return the static calibration factor ``mean(reference) / mean(sensor)`` (4.3.2).

    The thesis statically calibrated the sweep "by taking the average reading of the
    pressure sensor and the load cell". Use aligned records (same stamps).

    Raises
    ------
    ValueError
        When the sensor's mean is zero.
    """
    mean_s = float(np.mean(sensor))
    if mean_s == 0:
        raise TactilecalError(f"{label(sensor, 'sensor')}: mean reading is 0; expected a loaded "
                              "record to calibrate statically")
    return float(np.mean(reference)) / mean_s


def dynamic_part(values, fs_hz, *, static_cutoff_hz=0.5):
    """Return ``values`` minus its slow part (zero-phase 4th-order Butterworth low-pass).

    The "dynamic part" of a record is what is left after removing the offset and the slow
    loading/unloading ramps: content above ``static_cutoff_hz``.
    """
    sos = signal.butter(4, static_cutoff_hz, fs=fs_hz, output="sos")
    return values - signal.sosfiltfilt(sos, values)


MIN_R2_COMPLEX = 0.9
"""A model must explain at least this share of the complex correction (issue 13)."""

MAX_NOISE_GAIN = 10.0
"""The largest gain an inverse with phase may apply at any frequency (noise amplification)."""


def fit_filter(sensor, reference, *, model="log10", band_hz=None, method="h2",
               min_coherence=0.9, nperseg=None, lag_method="xcorr", outside="taper",
               taper_hz=None, n_taps=None, min_r2=MIN_R2_COMPLEX, force=False):
    """Fit a dynamic correction filter on a sweep (Gillis 2013, section 4.3).

    Steps: align the records (:func:`align`, lag stored), scale the sensor statically by
    ``mean(reference) / mean(sensor)`` (the thesis' static calibration of the sweep),
    estimate the transfer function with coherence (:func:`transfer_function`), fit eq. 4.1
    (:func:`fit_transfer`), build the filter (:meth:`CorrectionFilter.from_model`).

    Parameters
    ----------
    sensor, reference : xarray.DataArray
        1-D records with a ``time`` coordinate (any rates, any start times).
    model : {"log10", "log", "log-quadratic", "rational", "wiener", "auto"}
        Model of the transfer function: the thesis' zero-phase models; a rational (pole-zero)
        response fitted to the complex transfer function with its order chosen on held-out
        bins (:func:`~tactilecal.dynamic._ratfit.choose_rational`; the filter is its inverse,
        with a causal form); ``"wiener"``, the measured complex correction regularised by
        its random error (:mod:`~tactilecal.dynamic._wiener`); or ``"auto"``: of log,
        rational and wiener (by their number of parameters), the simplest whose error on
        held-out bins is within 10 % of the best or under 1 %; if it is refused, the next
        (the scores, the choice and any refusal are in ``fit.excluded["model_choice"]``).
    band_hz : tuple of float, optional
        Only bins inside are fitted; it is also the filter's calibrated band (default: the
        range of the coherent bins).
    method, min_coherence, nperseg
        See :func:`transfer_function`.
    lag_method : {"xcorr", "first-peak"}
        See :func:`estimate_lag`.
    outside, taper_hz, n_taps
        See :meth:`CorrectionFilter.from_model`.
    min_r2 : float
        Smallest share of the complex correction (magnitude and phase, :func:`complex_r2`)
        the model must explain; below it the fit is refused, because applying a filter
        that misses the sensor's phase can make records worse (issue 13: a viscoelastic
        sensor's blind-test error grew 1.5x).
    force : bool
        Build the filter anyway; it is marked ``forced`` with the reason (FILTER.json).

    Returns
    -------
    CorrectionFilter
        With ``fit`` (the :class:`TransferFit`; its ``excluded`` also records the static
        factor) and ``lag_s``.

    Raises
    ------
    ValueError
        See :func:`align`, :func:`transfer_function` (records that do not overlap, a
        reference shorter than the filter, NaN gaps, irregular time, band beyond Nyquist).
    """
    t_s, _ = time_and_values(sensor, "sensor")
    _check_band(band_hz, sampling_rate_hz(t_s, label(sensor, "sensor")),
                label(sensor, "sensor"))
    sens, ref, lag_s = align(sensor, reference, method=lag_method)
    factor = static_factor(sens, ref)
    sens = sens.copy(data=sens.values * factor)  # keeps attrs (the file named in errors)
    tf = transfer_function(sens, ref, method=method, nperseg=nperseg,
                           min_coherence=min_coherence, band_hz=band_hz)
    t_s = sens["time"].values
    records = (f"{label(sensor, 'sensor')} and {label(reference, 'reference')} "
               f"({t_s[0]:.6g}-{t_s[-1]:.6g} s after alignment)")
    try:
        fit = fit_transfer(tf, model="log" if model in CHOSEN_MODELS else model)
    except ValueError as exc:  # e.g. no coherent band: name the records and their overlap
        raise TactilecalError(f"{records}: {exc}") from None
    _check_cycles(tf, t_s[-1] - t_s[0], records)
    fit.excluded["static_factor"] = factor
    where = label(sensor, "sensor")
    choice = {"order": [model]}
    if model in CHOSEN_MODELS:
        choice = _choose_model(tf, fit, model)
        fit.excluded["model_choice"] = choice["why"]
        if not choice["order"]:  # the model asked for could not be fitted
            raise TactilecalError(f"{where}: {choice['why']}")
    design = {"band_hz": band_hz or (float(fit.f_hz.min()), float(fit.f_hz.max())),
              "outside": outside, "taper_hz": taper_hz, "n_taps": n_taps}
    refusals = []
    for name in choice["order"]:  # the chosen model first, then (auto) the others by score
        reason = _refusal(name, fit, tf, choice, min_r2)
        if reason is None:
            if refusals:
                fit.excluded["model_choice"] += (f"; refused before {name}: "
                                                 f"{'; '.join(refusals)}")
            return _traced(_build(name, fit, tf, choice, design, lag_s, None),
                           sensor, reference)
        refusals.append(reason)
    if not force:
        raise TactilecalError(f"{where}: {'; '.join(refusals)}; expected a model of the sensor "
                              "(pass force=True, or --force, to write the filter anyway, marked "
                              "forced)")
    return _traced(_build(choice["order"][0], fit, tf, choice, design, lag_s,
                          f"{where}: {refusals[0]}"), sensor, reference)


def _traced(filt, sensor, reference):
    """Return ``filt`` with the provenance of the two records it was fitted on."""
    filt.provenance = provenance_of([sensor, reference])
    return filt


MIN_CYCLES = 3
"""Cycles of its lowest fitted frequency a sweep must hold (a few: Welch needs them)."""


def _check_cycles(tf, duration_s, records):
    """Refuse a sweep shorter than ``MIN_CYCLES`` cycles of its lowest fitted frequency."""
    f_low = float(tf.f_hz[tf.used].min())
    if duration_s * f_low < MIN_CYCLES:
        raise TactilecalError(f"{records}: {duration_s:.3g} s holds {duration_s * f_low:.2g} "
                              f"cycles "
                              f"of the lowest fitted frequency {f_low:g} Hz; expected at least "
                              f"{MIN_CYCLES} (a longer sweep, or --band from "
                              f"{MIN_CYCLES / duration_s:.2g} Hz)")


#: Models :func:`fit_filter` fits beside the thesis' log model, and ``auto``, that chooses.
CHOSEN_MODELS = ("auto", "rational", "wiener")
#: Candidates from the fewest parameters to the most: a later one must be 10 % better.
_BY_COMPLEXITY = ("log", "rational", "wiener")


def _choose_model(tf, log_fit, model):
    """Score the candidates on held-out bins; choose the simplest that is good enough.

    Good enough: a held-out error within 10 % of the best candidate's, or under
    ``MATERIAL_ERROR`` (1 %; a more complex model must fix a material error).

    Blocks of coherent bins are held out (:func:`held_out_bins`): rational orders and the
    Wiener correction are fitted without them, and each candidate is scored there by
    :func:`~tactilecal.dynamic._ratfit.held_out_score` (weighted RMS of ``|C - model| /
    |C|``; the log fit, one parameter, is scored on the same bins). Returns ``{"order",
    "why", "rational", "wiener", "wiener_r2"}``: ``order`` lists the models to try, the
    chosen one first, then (for ``auto``) the others by score, in case the chosen one is
    refused; it is empty when the model asked for could not be fitted. ``wiener`` is the
    regularised correction of the used bins (None when not a candidate).
    """
    used = tf.used
    f_hz, measured = tf.f_hz[used], tf.response[used]
    held = held_out_bins(f_hz.size)
    wanted = _BY_COMPLEXITY[1:] if model == "auto" else (model,)
    error = tf.gain_error[used]
    scores = {"log": held_out_score(measured[held], log_fit.fitted[held], error[held])}
    labels, notes, rfit, wiener, wiener_r2 = {"log": "log"}, [], None, None, None
    if "rational" in wanted:
        try:
            rfit = choose_rational(f_hz, measured, tf.coherence[used], error, fs_hz=tf.fs_hz)
            scores["rational"], labels["rational"] = rfit.held_out_error, \
                f"rational order {rfit.order}"
        except ValueError as exc:  # e.g. too few coherent bins for order 4
            notes.append(f"no rational fit: {exc}")
    if "wiener" in wanted:
        if held.sum() >= 2 and (~held).sum() >= 2:
            scores["wiener"], wiener_r2 = wiener_held_out(f_hz, measured, error, held)
            labels["wiener"], wiener = "wiener", wiener_correction(measured, error)
        else:
            notes.append(f"no wiener fit: {f_hz.size} coherent bins; expected at least 4")
    enough = max(MATERIAL_ERROR, min(scores.values()) * (1 + MIN_IMPROVEMENT))
    if model == "auto":
        good = [m for m in _BY_COMPLEXITY if scores.get(m, np.inf) <= enough]
        order = good + sorted((m for m in scores if m not in good), key=scores.get)
    else:
        order = [model] if model in scores else []
    chosen = order[0] if order else None
    why = (f"held-out error: {', '.join(f'{labels[m]} {scores[m]:.2%}' for m in scores)} -> "
           f"{chosen or 'no ' + model + ' model'} (the simplest within 10 % of the best or "
           f"under {MATERIAL_ERROR:.0%})" + "".join(f"; {n}" for n in notes))
    if rfit is not None:
        why += f"; rational orders tried { {k: round(v, 4) for k, v in rfit.candidates.items()} }"
    return {"order": order, "why": why, "rational": rfit, "wiener": wiener,
            "wiener_r2": wiener_r2}


def _refusal(name, fit, tf, choice, min_r2):
    """Why model ``name`` does not describe the sensor, or its inverse would amplify noise.

    None when it is fine. ``fit`` is the log-type fit, ``choice`` what :func:`_choose_model`
    returned (or ``{"order": [name]}`` for the thesis' models).
    """
    if name == "rational":
        rfit = choice["rational"]
        if rfit.r2_complex < min_r2:
            return (f"the best rational model (order {rfit.order}) explains "
                    f"{rfit.r2_complex:.0%} of the complex correction, less than "
                    f"{min_r2:.0%}; no model of the family (log, log10, log-quadratic, "
                    "rational 1-4, wiener) describes this sensor")
        nyquist = np.linspace(0.0, tf.fs_hz / 2, 2049)  # the causal inverse's gain to Nyquist
        return _noise_reason(rfit.model.correction(nyquist), "rational model")
    if name == "wiener":
        r2 = choice["wiener_r2"]
        if not r2 >= min_r2:
            return (f"the regularised measured correction predicts {r2:.0%} of the held-out "
                    f"bins' complex correction, less than {min_r2:.0%}; the response is too "
                    "noisy or too ragged between bins for any model of the family")
        return _noise_reason(choice["wiener"], "measured correction")
    return _poor_fit_reason(fit, tf, min_r2)


def _noise_reason(correction, what):
    """Why an inverse would amplify noise (None when its gain stays within the limit)."""
    noise_gain = float(np.max(np.abs(correction)))
    if noise_gain <= MAX_NOISE_GAIN:
        return None
    return (f"the inverse of the {what} amplifies up to {noise_gain:.3g}x (limit "
            f"{MAX_NOISE_GAIN:g}x): it would amplify noise")


def _build(name, fit, tf, choice, design, lag_s, forced):
    """Build the filter of model ``name`` (``forced``: why it was refused, or None).

    A rational filter's ``lag_s`` is the clock offset alone (the sensor's delay, fitted
    jointly, is in ``fit.excluded``). A wiener filter's R2 is that of the held-out bins (in
    sample it explains every bin by construction); its lag keeps the sensor's own delay
    (no model separates them).
    """
    if name == "rational":
        rfit = choice["rational"]
        fit.excluded.update(rational=rfit.summary(), sensor_delay_s=rfit.delay_s,
                            model_r2_complex=rfit.r2_complex)
        return CorrectionFilter.design(
            "rational", {"order": rfit.order}, fs_hz=tf.fs_hz, **design, fit=fit,
            lag_s=None if lag_s is None else lag_s - rfit.delay_s, forced=forced,
            rational=rfit.model)
    if name == "wiener":
        used = tf.used
        fit.excluded["model_r2_complex"] = choice["wiener_r2"]  # of the held-out bins
        return CorrectionFilter.design(
            "wiener", {"bins": int(used.sum())}, fs_hz=tf.fs_hz, **design,
            response_f_hz=tf.f_hz[used], response_gain=choice["wiener"], fit=fit,
            lag_s=lag_s, forced=forced)
    filt = CorrectionFilter.from_model(fit, fs_hz=tf.fs_hz, lag_s=lag_s, **design)
    filt.forced = forced
    return filt


def _poor_fit_reason(fit, tf, min_r2):
    """Why the fitted log-type model does not describe the sensor (None when it does)."""
    if fit.r2_complex is None or fit.r2_complex >= min_r2:
        return None
    lag_deg = float(np.degrees(np.abs(np.angle(tf.response[tf.used]))).max())
    return (f"the {fit.model} model explains {fit.r2_complex:.0%} of the complex "
            f"correction (magnitude R2 {fit.r2:.2f}), less than {min_r2:.0%}; the measured "
            f"response has a phase of up to {lag_deg:.0f} degrees, which a zero-phase model "
            "cannot express")


@dataclass(repr=False)
class Evaluation(ShortRepr):
    """A filter checked against a reference (Gillis 2013, Figs 4.10-4.14).

    Attributes
    ----------
    lag_s, static_factor, fs_hz : float
        Alignment and static scale used.
    rms_before_N, rms_after_N : float
        RMS of the dynamic part of ``sensor - reference`` before and after correction.
    f_hz, error_before_pct, error_after_pct : numpy.ndarray
        Amplitude error ``100 (|sensor| / |reference| - 1)`` per coherent bin.
    phase_before_deg, phase_after_deg : numpy.ndarray
        Phase error of the sensor against the reference (degrees, negative = lag) per bin,
        before and after correction.
    time_s, sensor, corrected, reference : numpy.ndarray
        The aligned records (statically scaled), for plots.
    provenance : dict or None
        The records' files with SHA-256, sensor and package version
        (:func:`tactilecal._provenance.provenance_of`).
    """

    lag_s: float
    static_factor: float
    fs_hz: float
    rms_before_N: float
    rms_after_N: float
    f_hz: np.ndarray
    error_before_pct: np.ndarray
    error_after_pct: np.ndarray
    time_s: np.ndarray = field(repr=False)
    sensor: np.ndarray = field(repr=False)
    corrected: np.ndarray = field(repr=False)
    reference: np.ndarray = field(repr=False)
    phase_before_deg: np.ndarray | None = None
    phase_after_deg: np.ndarray | None = None
    provenance: dict | None = None

    def _repr_fields(self):
        return [("rms_before_N", self.rms_before_N), ("rms_after_N", self.rms_after_N),
                ("improvement", self.improvement), ("lag_s", self.lag_s),
                ("static_factor", self.static_factor), ("fs_hz", self.fs_hz),
                ("coherent_bins", len(self.f_hz))]

    @property
    def improvement(self):
        """``rms_before_N / rms_after_N`` (infinite for a perfect correction)."""
        return self.rms_before_N / self.rms_after_N if self.rms_after_N else float("inf")

    @classmethod
    def from_json(cls, path):
        """Read an ``evaluation.json`` written by :meth:`save` (see :meth:`from_dict`)."""
        return cls.from_dict(read_json_object(path, "an evaluation.json"), where=str(path))

    @classmethod
    def from_dict(cls, data, *, where="evaluation"):
        """Rebuild an evaluation from :meth:`to_dict` (``evaluation.json``), without records.

        The per-frequency errors and the figures from them come back (:meth:`plot_error`);
        the records were not stored, so they are empty and :meth:`plot_time` and
        :meth:`plot_spectra` have nothing to draw. A missing lag or static factor is NaN.

        Raises
        ------
        ValueError, TypeError
            A missing or bad key (an RMS error that is no number >= 0, per-frequency lists
            of different lengths or with other than numbers); the message names ``where``
            and the key.
        """
        check_type(data, dict, where, expected="an evaluation object")
        require_keys(data, ("rms_before_N", "rms_after_N", "fs_hz"), where,
                     expected="an evaluation")
        key = f"key {{!r}} of {where}".format
        numbers = {k: check_number(data[k], key(k), minimum=0.0)
                   for k in ("rms_before_N", "rms_after_N")}
        numbers["fs_hz"] = check_number(data["fs_hz"], key("fs_hz"), minimum=0.0,
                                        min_inclusive=False)
        for k in ("lag_s", "static_factor"):
            value = check_number(data.get(k), key(k), allow_none=True)
            numbers[k] = float("nan") if value is None else value
        empty = np.empty(0)
        return cls(**numbers, **_per_bin_arrays(data, key), time_s=empty, sensor=empty,
                   corrected=empty, reference=empty, provenance=data.get("provenance"))

    def to_dict(self):
        """Return the JSON-ready figures (without the records)."""
        return {"lag_s": self.lag_s, "static_factor": self.static_factor,
                "fs_hz": self.fs_hz, "rms_before_N": self.rms_before_N,
                "rms_after_N": self.rms_after_N, "improvement": self.improvement,
                "f_hz": self.f_hz, "error_before_pct": self.error_before_pct,
                "error_after_pct": self.error_after_pct,
                "phase_before_deg": self.phase_before_deg,
                "phase_after_deg": self.phase_after_deg, "provenance": self.provenance}

    def summary(self):
        """Return a one-line description."""
        phase = ("" if self.phase_before_deg is None or not len(self.f_hz) else
                 f"; largest phase error {np.abs(self.phase_before_deg).max():.3g} deg before, "
                 f"{np.abs(self.phase_after_deg).max():.3g} deg after")
        return (f"dynamic RMS error {self.rms_before_N:.4g} N before, {self.rms_after_N:.4g} N "
                f"after ({self.improvement:.2f}x smaller); lag {self.lag_s:.6g} s, static "
                f"factor {self.static_factor:.4g}{phase}")

    # figures (Gillis 2013, Figs 4.10-4.14), drawn by ``_plots``
    plot_time = _plots.plot_time
    plot_spectra = _plots.plot_spectra
    plot_error = _plots.plot_error

    def save(self, folder, filt, *, extra=None):
        """Write ``evaluation.json`` and the figures into ``folder``; return what the JSON holds.

        The figures are ``time.png``, ``spectra.png``, ``error.png`` and ``transfer.png`` (of
        ``filt``, the evaluated :class:`CorrectionFilter`); ``extra`` adds keys to the JSON
        (e.g. the input file names). See :func:`tactilecal.dynamic._files.write_evaluation`.
        """
        return write_evaluation(self, filt, folder, extra=extra)


def _per_bin_arrays(data, key):
    """Return the per-frequency lists of an evaluation JSON as arrays of one length.

    ``f_hz`` with the amplitude errors, or none of them; the phase errors both or neither.
    """
    names = ("f_hz", "error_before_pct", "error_after_pct", "phase_before_deg",
             "phase_after_deg")
    given = {k: data[k] for k in names if data.get(k) is not None}
    for k, values in given.items():
        check_numbers(values, key(k))
    lengths = {len(v) for v in given.values()}
    pairs_given = [len({n in given for n in pair}) == 1
                   for pair in (names[:3], names[3:])]
    if len(lengths) > 1 or not all(pairs_given):
        found = {k: len(v) for k, v in given.items()}
        raise TactilecalError(f"{key('f_hz')}: per-frequency lists of lengths {found}; expected "
                              "f_hz, error_before_pct, error_after_pct (and both phase errors) of "
                              "one length")
    arrays = {k: np.asarray(given[k], float) if k in given else None for k in names}
    for k in names[:3]:
        arrays[k] = np.empty(0) if arrays[k] is None else arrays[k]
    return arrays


def _amplitude_error_pct(x, ref, fs_hz, nperseg, min_coherence):
    """``100 (|x| / |ref| - 1)`` and the phase of ``x`` against ``ref`` (degrees) per bin.

    H1 with the reference as input; the third result says which bins are coherent.
    """
    f_hz, p_rr = signal.welch(ref, fs=fs_hz, nperseg=nperseg)
    _, p_rx = signal.csd(ref, x, fs=fs_hz, nperseg=nperseg)
    _, p_xx = signal.welch(x, fs=fs_hz, nperseg=nperseg)
    with np.errstate(divide="ignore", invalid="ignore"):
        coherence = np.abs(p_rx) ** 2 / (p_rr * p_xx)
        ratio = np.abs(p_rx) / p_rr
    return (f_hz, 100.0 * (ratio - 1.0), np.nan_to_num(coherence) >= min_coherence,
            np.degrees(np.angle(p_rx)))


def evaluate(filt, sensor, reference, *, lag_s=None, static_cutoff_hz=0.5, nperseg=None,
             min_coherence=0.9, progress=None, causal=False):
    """Evaluate a filter on a sweep or a blind test (Gillis 2013, 4.3.3 and 4.4.1).

    Parameters
    ----------
    filt : CorrectionFilter
    sensor, reference : xarray.DataArray
        1-D records (any rates and start times; a new session, so the lag is estimated
        again unless ``lag_s`` is given).
    lag_s : float, optional
        Known lag (see :func:`estimate_lag`).
    static_cutoff_hz : float
        The dynamic part is the content above it (:func:`dynamic_part`).
    nperseg, min_coherence
        Welch segment and coherence threshold of the amplitude-error spectrum (bins where
        either the raw or the corrected record is incoherent with the reference are left
        out).
    progress : callable, optional
        Passed to :func:`apply_filter`.
    causal : bool
        Evaluate a rational filter's causal inverse (see :func:`apply_filter`).

    Returns
    -------
    Evaluation
    """
    from tactilecal.dynamic._align import estimate_lag, resample_to

    corrected_full = apply_filter(sensor, filt, progress=progress, causal=causal)
    if lag_s is None:  # an inverse with phase removes the sensor's delay: align its output
        lag_s = estimate_lag(corrected_full if filt.has_phase else sensor,
                             reference)
    ref = resample_to(reference, sensor, lag_s=lag_s)
    dim = sensor.dims[0]
    keep = np.flatnonzero(np.isin(sensor["time"].values, ref["time"].values))
    sens = np.asarray(sensor.isel({dim: keep}).values, float)
    corr = np.asarray(corrected_full.isel({dim: keep}).values, float)
    r = np.asarray(ref.values, float)
    factor = static_factor(sens, r)
    sens, corr = sens * factor, corr * factor
    fs_hz = filt.fs_hz
    nperseg = int(round(fs_hz)) if nperseg is None else int(nperseg)
    rms = [float(np.sqrt(np.mean(dynamic_part(x - r, fs_hz,
                                                static_cutoff_hz=static_cutoff_hz) ** 2)))
           for x in (sens, corr)]
    f_hz, before, ok_b, phase_b = _amplitude_error_pct(sens, r, fs_hz, nperseg, min_coherence)
    _, after, ok_a, phase_a = _amplitude_error_pct(corr, r, fs_hz, nperseg, min_coherence)
    ok = ok_b & ok_a & (f_hz > 0)
    return Evaluation(float(lag_s), factor, fs_hz, rms[0], rms[1], f_hz[ok], before[ok],
                      after[ok], np.asarray(ref["time"].values), sens, corr, r,
                      phase_b[ok], phase_a[ok], provenance_of([sensor, reference]))


def compare_filters(filters, sensor, reference, **kwargs):
    """Apply several sensors' filters to one sensor's sweep (Gillis 2013, section 4.5).

    Parameters
    ----------
    filters : dict
        Name -> :class:`CorrectionFilter` (e.g. the sensor's own filter and another
        sensor's).
    sensor, reference : xarray.DataArray
        The sweep to correct and its load cell.
    **kwargs
        Passed to :func:`evaluate`.

    Returns
    -------
    dict
        ``{"evaluations": {name: Evaluation.to_dict() figures}, "rms_difference_N":
        {"a vs b": RMS of the difference between the two corrected records},
        "max_gain_difference": {"a vs b": largest |G_a - G_b| over 0..max band}}``.
    """
    from tactilecal.dynamic._align import estimate_lag

    names = list(filters)
    if len(names) < 2:
        raise TactilecalError(f"filters: {len(names)} given; expected at least 2 to compare")
    lag_s = kwargs.pop("lag_s", None)
    if lag_s is None:
        lag_s = estimate_lag(sensor, reference)
    evals = {n: evaluate(filters[n], sensor, reference, lag_s=lag_s, **kwargs) for n in names}
    diff, gain_diff = {}, {}
    for i, a in enumerate(names):
        for b in names[i + 1:]:
            key = f"{a} vs {b}"
            diff[key] = float(np.sqrt(np.mean((evals[a].corrected - evals[b].corrected) ** 2)))
            top = max(filters[a].band_hz[1], filters[b].band_hz[1])
            f = np.linspace(0.0, top, 512)
            gain_diff[key] = float(np.max(np.abs(filters[a].gain(f) - filters[b].gain(f))))
    return {"evaluations": {n: {k: v for k, v in e.to_dict().items()
                                if k in ("rms_before_N", "rms_after_N", "improvement",
                                         "lag_s", "static_factor")}
                            for n, e in evals.items()},
            "rms_difference_N": diff, "max_gain_difference": gain_diff}
