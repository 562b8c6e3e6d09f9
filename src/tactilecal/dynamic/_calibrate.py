"""Fit a dynamic correction filter on one or several sine sweeps (Gillis 2013, section 4.3).

Steps: align each sweep's records (:func:`align`), scale the sensor statically by
``mean(reference) / mean(sensor)`` (the thesis' static calibration of the sweep), estimate the
complex transfer function with coherence, keep the band where the sweep carried coherent
energy (:func:`transfer_function`), pool several sweeps and compare them
(:func:`~tactilecal.dynamic._amplitude.compare_amplitudes`), fit the thesis' model
(:func:`fit_transfer`) and, for ``auto``, ``rational`` and ``wiener``, the other candidates
(:func:`~tactilecal.dynamic._choice.choose_model`), each with a delay fitted jointly; build
the filter of the chosen model and refuse it when it does not describe the sensor or would
amplify noise.
"""

import warnings
from dataclasses import dataclass

import numpy as np
from scipy import signal

from tactilecal._errors import TactilecalError
from tactilecal._provenance import provenance_of
from tactilecal.dynamic._align import align
from tactilecal.dynamic._amplitude import compare_amplitudes
from tactilecal.dynamic._choice import CHOSEN_MODELS, choose_model
from tactilecal.dynamic._filter import CorrectionFilter
from tactilecal.dynamic._fit import MODELS, fit_transfer
from tactilecal.dynamic._records import label, sampling_rate_hz, time_and_values
from tactilecal.dynamic._transfer import _check_band, pool_transfer, transfer_function

__all__ = ["fit_filter", "static_factor", "dynamic_part", "FIT_MODELS", "MIN_R2_COMPLEX",
           "MAX_NOISE_GAIN", "AmplitudeWarning"]

#: Every ``model`` :func:`fit_filter` accepts.
FIT_MODELS = ("auto", *MODELS, "rational", "wiener")
MIN_R2_COMPLEX = 0.9
"""A model must explain at least this share of the complex correction."""
MAX_NOISE_GAIN = 10.0
"""The largest gain a filter may apply at any frequency (noise amplification)."""
MIN_CYCLES = 3
"""Cycles of its lowest fitted frequency a sweep must hold (a few: Welch needs them)."""


class AmplitudeWarning(UserWarning):
    """Sweeps at different amplitudes differ beyond their errors: no linear filter fits all."""


def static_factor(sensor, reference):
    """Return the static calibration factor ``mean(reference) / mean(sensor)`` (4.3.2).

    The thesis statically calibrated the sweep "by taking the average reading of the
    pressure sensor and the load cell". Use aligned records (same stamps).

    Raises
    ------
    TactilecalError
        When the sensor's mean is zero.

    Examples
    --------
    >>> static_factor(np.array([1.0, 3.0]), np.array([4.0, 4.0]))
    2.0
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

    Examples
    --------
    >>> t = np.arange(0, 10, 1e-2)
    >>> x = 5 + np.sin(2 * np.pi * 10 * t)
    >>> round(float(np.abs(dynamic_part(x, 100.0)[200:-200] - (x - 5)[200:-200]).max()), 2)
    0.0
    """
    sos = signal.butter(4, static_cutoff_hz, fs=fs_hz, output="sos")
    return values - signal.sosfiltfilt(sos, values)


@dataclass
class _Sweep:
    """One sweep aligned and scaled: its transfer function, lag, static factor, amplitude."""

    tf: object
    lag_s: float
    factor: float
    amplitude_N: float
    duration_s: float
    records: str


def _prepare(sensor, reference, options):
    """Align one sweep, scale it statically, estimate its transfer function."""
    sens, ref, lag_s = align(sensor, reference, method=options["lag_method"])
    factor = static_factor(sens, ref)
    sens = sens.copy(data=sens.values * factor)  # keeps attrs (the file named in errors)
    tf = transfer_function(sens, ref, method=options["method"], nperseg=options["nperseg"],
                           min_coherence=options["min_coherence"],
                           min_power_db=options["min_power_db"], band_hz=options["band_hz"])
    t_s = sens["time"].values
    # a sine's median |value| is its amplitude / sqrt(2); the ramps are too short to move it
    amplitude = float(np.sqrt(2) * np.median(np.abs(dynamic_part(
        np.asarray(ref.values, float), tf.fs_hz))))
    records = (f"{label(sensor, 'sensor')} and {label(reference, 'reference')} "
               f"({t_s[0]:.6g}-{t_s[-1]:.6g} s after alignment)")
    return _Sweep(tf, lag_s, factor, amplitude, float(t_s[-1] - t_s[0]), records)


def _pairs(sensor, reference):
    """Return the sweeps as ``[(sensor, reference), ...]`` (one pair, or two sequences)."""
    many = isinstance(sensor, list | tuple)
    if many != isinstance(reference, list | tuple):
        raise TypeError("sensor and reference: one record each, or two sequences of records")
    if not many:
        return [(sensor, reference)]
    if len(sensor) != len(reference) or not sensor:
        raise TactilecalError(f"{len(sensor)} sensor records and {len(reference)} references; "
                              "expected one reference per sweep, at least one sweep")
    return list(zip(sensor, reference, strict=True))


def fit_filter(sensor, reference, *, model="auto", band_hz=None, method="h2",
               min_coherence=0.9, min_power_db=20.0, nperseg=None, lag_method="xcorr",
               outside="taper", taper_hz=None, n_taps=None, min_r2=MIN_R2_COMPLEX,
               max_noise_gain=MAX_NOISE_GAIN, force=False):
    """Fit a dynamic correction filter on a sweep (Gillis 2013, section 4.3).

    Parameters
    ----------
    sensor, reference : xarray.DataArray, or sequences of them
        1-D records with a ``time`` coordinate (any rates, any start times); several sweeps
        (at different amplitudes) as two sequences of the same length, pooled bin by bin
        and compared (:class:`AmplitudeCheck` in ``fit.amplitude``; an
        :class:`AmplitudeWarning` when they differ beyond their errors).
    model : {"auto", "log10", "log", "log-quadratic", "rational", "wiener"}
        ``auto`` (default): of log10, rational and wiener, the simplest whose error on
        held-out bins is within 10 % of the best or under 1 % (if it is refused, the next);
        the thesis' zero-phase models (eq. 4.1); a rational response (real corners and
        complex pairs, the structure chosen on held-out bins); ``"wiener"``, the measured
        complex correction regularised by its random error. Every model carries a delay
        fitted jointly with it (:mod:`~tactilecal.dynamic._choice`). ``auto`` is the
        default because it is the only choice that is right on every sensor of
        :data:`tactilecal.simulate.DYNAMIC_FAMILY` (log10 is refused on a viscoelastic or
        resonant sensor, rational misses a log law, wiener extrapolates poorly).
    band_hz : tuple of float, optional
        Only bins inside are fitted; it is also the filter's calibrated band, so it must lie
        within the bins fitted, to within a bin (default: the range of the bins with
        coherent energy).
    method, min_coherence, min_power_db, nperseg
        See :func:`transfer_function`.
    lag_method : {"xcorr", "first-peak"}
        See :func:`estimate_lag`.
    outside, taper_hz, n_taps
        See :meth:`CorrectionFilter.from_model`.
    min_r2 : float
        Smallest share of the complex correction (magnitude and phase, with the model's
        delay) the model must explain; below it the model is refused, because a filter
        that misses the sensor's phase can make records worse.
    max_noise_gain : float
        Largest gain the filter (its correction tapered above the band) may apply at any
        frequency up to Nyquist; above it the model is refused (it would amplify noise).
    force : bool
        Build the filter anyway; it is marked ``forced`` with the reason (FILTER.json).

    Returns
    -------
    CorrectionFilter
        With ``fit`` (the :class:`TransferFit`: ``static_factor``, ``band_note``,
        ``model_choice``, ``amplitude``) and ``lag_s`` (the clock offset: the alignment's
        lag minus the model's delay).

    Raises
    ------
    TactilecalError
        See :func:`align`, :func:`transfer_function` (records that do not overlap, a
        reference shorter than the filter, NaN gaps, irregular time, band beyond Nyquist);
        a band past the bins the sweep calibrates; an unknown model; every candidate
        refused (unless ``force``).

    Examples
    --------
    >>> from tactilecal.simulate import sine_sweep
    >>> s = sine_sweep(seed=0, step_hz=2, cycles_high=10, fs_sensor_hz=1000.0,
    ...                fs_reference_hz=1250.0)  # true law: A = 0.11, log10
    >>> filt = fit_filter(s.sensor, s.reference)
    >>> filt.model, round(filt.params["A"], 2), round(filt.lag_s, 3), round(s.lag_s, 3)
    ('log10', 0.11, 0.837, 0.837)
    >>> round(float(filt.gain(100.0)), 2), round(float(s.true_gain(100.0)), 2)
    (1.22, 1.22)
    """
    if model not in FIT_MODELS:
        raise TactilecalError(f"model={model!r}; expected one of {', '.join(FIT_MODELS)}")
    pairs = _pairs(sensor, reference)
    where = label(pairs[0][0], "sensor")
    t_s, _ = time_and_values(pairs[0][0], "sensor")
    _check_band(band_hz, sampling_rate_hz(t_s, where), where)
    options = {"lag_method": lag_method, "method": method, "nperseg": nperseg,
               "min_coherence": min_coherence, "min_power_db": min_power_db,
               "band_hz": band_hz}
    sweeps = [_prepare(s, r, options) for s, r in pairs]
    tf = pool_transfer([s.tf for s in sweeps])
    first = sweeps[0]
    try:
        fit = fit_transfer(tf, model="log10" if model in CHOSEN_MODELS else model)
    except ValueError as exc:  # e.g. no coherent band: name the records and their overlap
        raise TactilecalError(f"{first.records}: {exc}") from None
    for sweep in sweeps:
        _check_cycles(tf, sweep.duration_s, sweep.records)
    fit.static_factor, fit.band_note = first.factor, tf.band_note()
    _check_band_measured(band_hz, fit.f_hz, tf.f_hz, first.records)
    if len(sweeps) > 1:
        fit.amplitude = _amplitude_check(sweeps)
    choice, candidates, order = choose_model(tf, fit, model)
    fit.model_choice = choice
    if not order:  # the model asked for could not be fitted
        raise TactilecalError(f"{where}: no {model} model: {'; '.join(choice.notes)}")
    design = {"fs_hz": tf.fs_hz, "band_hz": band_hz or (float(fit.f_hz.min()),
                                                        float(fit.f_hz.max())),
              "outside": outside, "taper_hz": taper_hz, "n_taps": n_taps, "fit": fit}
    refused = {}
    for name in order:  # the chosen model first, then (auto) the others by score
        filt = _build(candidates[name], design, first.lag_s)
        reason = _refusal(candidates[name], filt, fit, tf, min_r2, max_noise_gain)
        if reason is None:
            return _chosen(filt, candidates[name], refused, pairs)
        refused[candidates[name].label] = reason
    if not force:
        raise TactilecalError(f"{where}: {'; '.join(refused.values())}; expected a model of "
                              "the sensor (pass force=True to write the filter anyway, marked "
                              "forced)")
    filt = _build(candidates[order[0]], design, first.lag_s)
    filt.forced = f"{where}: {refused[candidates[order[0]].label]}"
    return _chosen(filt, candidates[order[0]], {}, pairs)


def _check_band_measured(band_hz, fitted_hz, bins_hz, where):
    """Refuse a band asked for that reaches past the fitted bins by more than a bin.

    The band becomes the filter's calibrated band, and the sweep measured nothing outside
    the bins it fitted.
    """
    if band_hz is None:
        return
    lo, hi = (float(v) for v in band_hz)
    first, last = float(fitted_hz.min()), float(fitted_hz.max())
    spacing = float(bins_hz[1] - bins_hz[0]) if bins_hz.size > 1 else 0.0
    if lo < first - spacing or hi > last + spacing:
        raise TactilecalError(
            f"{where}: band_hz=({lo:g}, {hi:g}) reaches past the bins the sweep calibrates, "
            f"{first:g} to {last:g} Hz; expected a band within them (band_hz=("
            f"{max(lo, first):g}, {min(hi, last):g}), or a sweep over the band asked for)")


def _chosen(filt, candidate, refused, pairs):
    """Record the choice in ``filt.fit`` and the records' provenance in ``filt``."""
    choice = filt.fit.model_choice
    choice.chosen, choice.refused = candidate.label, refused
    choice.delay_s, choice.r2_complex = candidate.delay_s, candidate.r2_complex
    filt.provenance = provenance_of([record for pair in pairs for record in pair])
    return filt


def _amplitude_check(sweeps):
    """Compare the sweeps; warn when the response depends on the amplitude."""
    check = compare_amplitudes([s.tf for s in sweeps], [s.amplitude_N for s in sweeps])
    if check.depends:
        warnings.warn(f"{sweeps[0].records.split(' (')[0]}: {check.summary()}; one linear "
                      "filter cannot correct it (this one is fitted to the sweeps pooled)",
                      AmplitudeWarning, stacklevel=3)
    return check


def _check_cycles(tf, duration_s, records):
    """Refuse a sweep shorter than ``MIN_CYCLES`` cycles of its lowest fitted frequency."""
    f_low = float(tf.f_hz[tf.used].min())
    if duration_s * f_low < MIN_CYCLES:
        raise TactilecalError(f"{records}: {duration_s:.3g} s holds {duration_s * f_low:.2g} "
                              f"cycles of the lowest fitted frequency {f_low:g} Hz; expected at "
                              f"least {MIN_CYCLES} (a longer sweep, or --band from "
                              f"{MIN_CYCLES / duration_s:.2g} Hz)")


def _build(candidate, design, lag_s):
    """Build one candidate's filter; its clock offset is the alignment's lag minus its delay."""
    fields = dict(candidate.design)
    return CorrectionFilter.design(fields.pop("model"), fields.pop("params"), **design,
                                   lag_s=lag_s - candidate.delay_s, **fields)


def _refusal(candidate, filt, fit, tf, min_r2, max_noise_gain):
    """Why a candidate does not describe the sensor or its filter would amplify noise.

    None when it is fine: it explains at least ``min_r2`` of the complex correction, and
    the filter's correction (tapered above the band) stays within ``max_noise_gain``.
    """
    r2 = candidate.r2_complex
    if not r2 >= min_r2:
        return _poor_fit_reason(candidate, fit, tf, min_r2)
    grid = np.linspace(0.0, filt.fs_hz / 2, 4097)
    gain = np.abs(filt.target(grid))
    if gain.max() <= max_noise_gain:
        return None
    k = int(np.argmax(gain))
    return (f"the {candidate.label} filter amplifies up to {gain[k]:.3g}x (at {grid[k]:.4g} Hz; "
            f"limit max_noise_gain={max_noise_gain:g}): it would amplify noise")


def _pct(share):
    """Write a share as a percentage with the digits that tell 99.98 % from 99.99 %."""
    return f"{100 * share:.4g}%"


def _poor_fit_reason(candidate, fit, tf, min_r2):
    """Why a model explains too little of the complex correction."""
    r2, limit = _pct(candidate.r2_complex), _pct(min_r2)
    if candidate.name == "wiener":
        return (f"the regularised measured correction predicts {r2} of the held-out bins' "
                f"complex correction, less than {limit}; the response is too noisy or too "
                "ragged between bins for any model of the family")
    if candidate.name == "rational":
        return (f"the best {candidate.label} model explains {r2} of the complex correction, "
                f"less than {limit}")
    lag_deg = float(np.degrees(np.abs(np.angle(tf.response[tf.used]))).max())
    return (f"the {fit.model} model explains {r2} of the complex correction (magnitude R2 "
            f"{fit.r2:.3g}), less than {limit}; the measured response has a phase of up to "
            f"{lag_deg:.0f} degrees, which a zero-phase model cannot express")
