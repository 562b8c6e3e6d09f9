"""Evaluate a filter on a sweep or a blind test, at the clock it was fitted with (4.3.3, 4.4.1).

A dynamic correction is only as good as its timing (METHOD-NOTES G): a filter that restores
every amplitude but shifts the record by 2.5 ms has a 90 degree error at 100 Hz. Re-aligning
the corrected record on the reference before scoring it measures a different, better filter
than the one delivered. :func:`evaluate` therefore scores the corrected record at **the
fitted clock**: the blind test's clock offset found the way the filter's own offset was
(cross-correlation of the records, minus the delay of the filter's model of the sensor,
:func:`_fitted_clock`), or a clock the caller knows (``lag_s=``). The lag that would align
the corrected record best is always found too: their difference is the filter's **timing
error** (ms). With ``realign=True`` the error at that re-aligned clock is reported beside
(labelled as such), never instead.
"""

from dataclasses import dataclass, field

import numpy as np
from scipy import signal

from tactilecal._errors import TactilecalError
from tactilecal._jsonutil import to_jsonable
from tactilecal._provenance import provenance_of
from tactilecal._result import SavedResult
from tactilecal._validate import check_number, check_numbers, check_type, require_keys
from tactilecal.dynamic import _plots
from tactilecal.dynamic._align import estimate_lag, resample_to
from tactilecal.dynamic._apply import filter_values
from tactilecal.dynamic._calibrate import dynamic_part, static_factor
from tactilecal.dynamic._files import write_evaluation
from tactilecal.dynamic._fit import fit_delay
from tactilecal.dynamic._transfer import transfer_function

__all__ = ["Evaluation", "evaluate", "compare_filters", "CLOCKS"]

#: How the clock of an evaluation was set: by the filter's model ("fitted"), by the caller
#: ("given").
CLOCKS = ("fitted", "given")
#: Largest |lag| (s) and timing error (s) an evaluation file may hold (a day; 1 s).
_MAX_LAG_S, _MAX_TIMING_S = 86400.0, 1.0
_PER_BIN = ("f_hz", "error_before_pct", "error_after_pct", "phase_before_deg",
            "phase_after_deg")
_WINDOW_KEYS = ("time_s", "reference", "sensor", "corrected")
_SPECTRA_KEYS = ("f_hz", "reference", "sensor", "corrected")
#: Most points of the saved spectra, and of any saved column.
SPECTRUM_POINTS, _MAX_POINTS = 2000, 100_000
#: Zoomed window: this many periods of half the band's top, within these bounds (s).
WINDOW_PERIODS, WINDOW_BOUNDS_S = 10, (0.05, 1.0)


@dataclass(eq=False, repr=False)
class Evaluation(SavedResult):
    """A filter checked against a reference (Gillis 2013, Figs 4.10-4.14).

    Saved as ``evaluation.json``, ``"format": "tactilecal-dynamic-evaluation/1"``
    (:meth:`to_json`; :meth:`save` adds the figures); ``tactilecal.load`` reads it.

    Attributes
    ----------
    lag_s : float
        The clock offset the corrected record was scored at (added to the reference's
        stamps).
    clock : {"fitted", "given"}
        How it was set: by the filter's model (:func:`evaluate`), or by the caller.
    static_factor, fs_hz : float
        Static scale ``mean(reference) / mean(sensor)`` and sampling rate.
    band_hz : tuple of float
        The filter's calibrated band.
    rms_before_N, rms_after_N : float
        RMS of the dynamic part of ``sensor - reference`` before and after correction, at
        ``lag_s``.
    timing_error_s : float
        The shift that aligns the corrected record best minus ``lag_s``: how far the
        correction sits off the clock (0 for a filter with the right delay).
    above_band_share : float
        Share of the reference's dynamic power above the filter's band (left uncorrected).
    f_hz, error_before_pct, error_after_pct : numpy.ndarray
        Amplitude error ``100 (|sensor| / |reference| - 1)`` per coherent bin.
    phase_before_deg, phase_after_deg : numpy.ndarray
        Phase error (degrees, negative = lag) per bin, before and after correction.
    rms_after_realigned_N : float
        RMS error after correction at the re-aligned clock (NaN unless asked for).
    window : dict
        A zoomed window of the records where the reference moves fastest: ``time_s``,
        ``reference``, ``sensor``, ``corrected`` (saved; :meth:`plot_time`).
    spectra : dict
        Fourier amplitude spectra of the three records to 1.5 times the band's top
        (``f_hz``, ``reference``, ``sensor``, ``corrected``; the largest of each group of
        bins when there are more than ``SPECTRUM_POINTS``; saved; :meth:`plot_spectra`).
    inputs : dict
        Names of the evaluated files (``filter``, ``sensor``, ``reference``), if any.
    figures : tuple of str
        Figure files written beside ``evaluation.json`` by :meth:`save`.
    time_s, sensor, corrected, reference, reference_realigned : numpy.ndarray
        The aligned records (statically scaled), for plots; not saved.

    Examples
    --------
    >>> import tempfile, pathlib, tactilecal
    >>> from tactilecal.dynamic import CorrectionFilter
    >>> from tactilecal.simulate import sine_sweep
    >>> s = sine_sweep(seed=0, step_hz=2, cycles_high=10, fs_sensor_hz=1000.0,
    ...                fs_reference_hz=1250.0)  # true law: A = 0.11, log10
    >>> filt = CorrectionFilter.from_model(("log10", {"A": 0.11}), fs_hz=1000.0, band_hz=(1, 140))
    >>> ev = evaluate(filt, s.sensor, s.reference)
    >>> print(ev.summary().splitlines()[0])  # doctest: +ELLIPSIS
    dynamic RMS error 7.476 N before, 1.177 N after (6.35x smaller) at the fitted clock ...
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "evaluation.json"
    >>> ev.to_json(path)
    >>> saved = tactilecal.load(path)
    >>> type(saved).__name__, len(saved.f_hz), round(saved.improvement, 2)
    ('Evaluation', 151, 6.35)
    """

    FORMAT_KIND = "dynamic-evaluation"
    DESCRIPTION = "an evaluation.json written by 'tactilecal dynamic evaluate'"

    lag_s: float
    clock: str
    static_factor: float
    fs_hz: float
    band_hz: tuple
    rms_before_N: float
    rms_after_N: float
    timing_error_s: float
    above_band_share: float
    f_hz: np.ndarray
    error_before_pct: np.ndarray
    error_after_pct: np.ndarray
    phase_before_deg: np.ndarray
    phase_after_deg: np.ndarray
    rms_after_realigned_N: float = float("nan")
    window: dict = field(default_factory=dict)
    spectra: dict = field(default_factory=dict)
    inputs: dict = field(default_factory=dict)
    figures: tuple = ()
    time_s: np.ndarray = field(default_factory=lambda: np.empty(0))
    sensor: np.ndarray = field(default_factory=lambda: np.empty(0))
    corrected: np.ndarray = field(default_factory=lambda: np.empty(0))
    reference: np.ndarray = field(default_factory=lambda: np.empty(0))
    reference_realigned: np.ndarray = field(default_factory=lambda: np.empty(0))
    provenance: dict | None = None

    @property
    def improvement(self):
        """``rms_before_N / rms_after_N`` at the evaluated clock (inf for a perfect one)."""
        return self.rms_before_N / self.rms_after_N if self.rms_after_N else float("inf")

    @property
    def improvement_realigned(self):
        """The same at the re-aligned clock (NaN unless asked for)."""
        return self.rms_before_N / self.rms_after_realigned_N

    def _repr_fields(self):
        return [("rms_before_N", self.rms_before_N), ("rms_after_N", self.rms_after_N),
                ("improvement", self.improvement), ("clock", self.clock),
                ("lag_s", self.lag_s), ("timing_error_ms", 1e3 * self.timing_error_s),
                ("coherent_bins", len(self.f_hz))]

    def summary(self):
        """Return the evaluation as readable lines."""
        lines = [f"dynamic RMS error {self.rms_before_N:.4g} N before, {self.rms_after_N:.4g} N "
                 f"after ({self.improvement:.3g}x smaller) at the {self.clock} clock (lag "
                 f"{self.lag_s:.6g} s); timing error {1e3 * self.timing_error_s:+.3g} ms"]
        if np.isfinite(self.rms_after_realigned_N):
            lines.append(f"re-aligned by {1e3 * self.timing_error_s:+.3g} ms (what a perfectly "
                         f"re-timed record would give, not what the filter delivers): "
                         f"{self.rms_after_realigned_N:.4g} N ({self.improvement_realigned:.3g}x)")
        if len(self.f_hz):
            lines.append(
                f"amplitude error over {len(self.f_hz)} coherent bins ({self.f_hz.min():g}.."
                f"{self.f_hz.max():g} Hz): median |error| "
                f"{np.median(np.abs(self.error_before_pct)):.3g} % before, "
                f"{np.median(np.abs(self.error_after_pct)):.3g} % after; largest phase error "
                f"{np.abs(self.phase_before_deg).max():.3g} deg before, "
                f"{np.abs(self.phase_after_deg).max():.3g} deg after")
        if self.above_band_share > 0.01:
            lines.append(f"{self.above_band_share:.1%} of the reference's dynamic power lies "
                         f"above the filter's band ({self.band_hz[1]:g} Hz): not corrected")
        lines.append(f"static factor {self.static_factor:.6g}")
        return "\n".join(lines)

    def _to_dict(self):
        return to_jsonable({
            "lag_s": self.lag_s, "clock": self.clock, "static_factor": self.static_factor,
            "fs_hz": self.fs_hz, "band_hz": list(self.band_hz),
            "rms_before_N": self.rms_before_N, "rms_after_N": self.rms_after_N,
            "improvement": self.improvement, "timing_error_s": self.timing_error_s,
            "above_band_share": self.above_band_share,
            "rms_after_realigned_N": self.rms_after_realigned_N,
            **{k: getattr(self, k) for k in _PER_BIN}, "window": self.window,
            "spectra": self.spectra, "inputs": self.inputs, "figures": list(self.figures)})

    @classmethod
    def _from_dict(cls, data, where):
        """Rebuild an evaluation (without its records) from its JSON, every key checked."""
        require_keys(data, ("lag_s", "clock", "static_factor", "fs_hz", "band_hz",
                            "rms_before_N", "rms_after_N", "timing_error_s",
                            "above_band_share", *_PER_BIN), where, expected="an evaluation")
        key = f"key '{{}}' of {where}".format
        fs_hz = check_number(data["fs_hz"], key("fs_hz"), minimum=0.0, min_inclusive=False,
                             maximum=1e7)
        if data["clock"] not in CLOCKS:
            raise TactilecalError(f"{key('clock')} is {str(data['clock'])[:40]!r}; expected one "
                                  f"of {', '.join(CLOCKS)}")
        band = check_numbers(data["band_hz"], key("band_hz"))
        if len(band) != 2 or not 0 <= band[0] < band[1] <= fs_hz / 2:
            raise TactilecalError(f"{key('band_hz')} is {band[:4]}; expected [low, high] with 0 "
                                  f"<= low < high <= {fs_hz / 2:g} (half of fs_hz)")
        inputs = check_type(data.get("inputs", {}), dict, key("inputs"), expected="an object")
        figures = check_type(data.get("figures", []), list, key("figures"),
                             expected="a list of file names")
        realigned = check_number(data.get("rms_after_realigned_N"),
                                 key("rms_after_realigned_N"), minimum=0.0, allow_none=True)
        return cls(
            lag_s=check_number(data["lag_s"], key("lag_s"), minimum=-_MAX_LAG_S,
                               maximum=_MAX_LAG_S),
            clock=data["clock"], fs_hz=fs_hz, band_hz=tuple(float(b) for b in band),
            static_factor=check_number(data["static_factor"], key("static_factor"),
                                       minimum=0.0, min_inclusive=False),
            rms_before_N=check_number(data["rms_before_N"], key("rms_before_N"), minimum=0.0),
            rms_after_N=check_number(data["rms_after_N"], key("rms_after_N"), minimum=0.0),
            timing_error_s=check_number(data["timing_error_s"], key("timing_error_s"),
                                        minimum=-_MAX_TIMING_S, maximum=_MAX_TIMING_S),
            above_band_share=check_number(data["above_band_share"], key("above_band_share"),
                                          minimum=0.0, maximum=1.0),
            rms_after_realigned_N=float("nan") if realigned is None else realigned,
            inputs={str(k): str(v) for k, v in inputs.items()},
            window=_columns(data.get("window", {}), key("window"), _WINDOW_KEYS),
            spectra=_columns(data.get("spectra", {}), key("spectra"), _SPECTRA_KEYS),
            figures=tuple(str(f) for f in figures), **_per_bin_arrays(data, key, fs_hz))

    # figures (Gillis 2013, Figs 4.10-4.14), drawn by ``_plots``
    plot_time = _plots.plot_time
    plot_spectra = _plots.plot_spectra
    plot_error = _plots.plot_error

    def save(self, folder, filt):
        """Write ``evaluation.json`` and the figures into ``folder``; return the evaluation.

        The figures are ``time.png`` (the whole record and a zoomed window),
        ``spectra.png``, ``error.png`` and ``transfer.png`` (of ``filt``, the evaluated
        :class:`CorrectionFilter`); their names go to :attr:`figures`.
        """
        return write_evaluation(self, filt, folder)


def _per_bin_arrays(data, key, fs_hz):
    """Return the per-frequency lists of an evaluation JSON as arrays of one length."""
    arrays = {k: np.asarray(check_numbers(data[k], key(k)), dtype=float) for k in _PER_BIN}
    lengths = {k: a.size for k, a in arrays.items()}
    if len(set(lengths.values())) > 1:
        raise TactilecalError(f"{key('f_hz')}: per-frequency lists of lengths {lengths}; "
                              "expected f_hz, both amplitude errors and both phase errors of "
                              "one length")
    f_hz = arrays["f_hz"]
    if f_hz.size and (f_hz.min() < 0 or f_hz.max() > fs_hz / 2 or np.any(np.diff(f_hz) <= 0)):
        raise TactilecalError(f"{key('f_hz')}: frequencies from {f_hz.min():g} to "
                              f"{f_hz.max():g} Hz; expected increasing values within 0.."
                              f"{fs_hz / 2:g} Hz")
    for k in _PER_BIN[1:]:
        if np.abs(arrays[k]).max(initial=0.0) > 1e6:
            raise TactilecalError(f"{key(k)} holds {np.abs(arrays[k]).max():.3g}; expected "
                                  "errors within +-1e6 (% or degrees)")
    return arrays


def _columns(data, where, names):
    """Return a saved window or spectra: numbers of one length per name (or nothing)."""
    check_type(data, dict, where, expected="an object of number lists")
    if not data:
        return {}
    require_keys(data, names, where, expected=f"the columns {list(names)}")
    columns = {k: np.asarray(check_numbers(data[k], f"key '{k}' of {where}"), float)
               for k in names}
    sizes = {a.size for a in columns.values()}
    if len(sizes) > 1 or max(sizes) > _MAX_POINTS:
        raise TactilecalError(f"{where} has columns of lengths {sorted(sizes)}; expected one "
                              f"length up to {_MAX_POINTS}")
    return columns


def _zoom(t, reference, sensor, corrected, fs_hz, band_top_hz, static_cutoff_hz):
    """Return a window of the records where the reference's dynamic part moves fastest.

    Its slope (amplitude times frequency), smoothed over 20 ms, peaks where the filter
    matters most; the window holds ``WINDOW_PERIODS`` periods of half the band's top.
    """
    slope = np.abs(np.gradient(dynamic_part(reference, fs_hz,
                                            static_cutoff_hz=static_cutoff_hz)))
    width = max(1, int(0.02 * fs_hz))
    centre = int(np.argmax(np.convolve(slope, np.ones(width) / width, "same")))
    half = int(0.5 * fs_hz * np.clip(2 * WINDOW_PERIODS / band_top_hz, *WINDOW_BOUNDS_S))
    part = slice(max(centre - half, 0), centre + half + 1)
    return {"time_s": t[part], "reference": reference[part], "sensor": sensor[part],
            "corrected": corrected[part]}


def _spectra(reference, sensor, corrected, fs_hz, band_top_hz):
    """Fourier amplitude spectra ``2 |rfft(x - mean)| / n`` to 1.5 x the band's top.

    With more than ``SPECTRUM_POINTS`` bins there, the largest of each group is kept (the
    peaks of the sine sets survive).
    """
    n = reference.size
    f_hz = np.fft.rfftfreq(n, 1.0 / fs_hz)
    keep = f_hz <= min(fs_hz / 2, 1.5 * band_top_hz)
    groups = max(1, -(-int(keep.sum()) // SPECTRUM_POINTS))
    out = {"f_hz": f_hz[keep][::groups]}
    for name, x in (("reference", reference), ("sensor", sensor), ("corrected", corrected)):
        amp = (2.0 * np.abs(np.fft.rfft(x - x.mean())) / n)[keep]
        pad = -amp.size % groups
        out[name] = np.r_[amp, np.zeros(pad)].reshape(-1, groups).max(axis=1)
    return out


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


def _fitted_clock(filt, sensor, reference, nperseg, min_coherence):
    """Return the clock offset of these records as the filter's fit would find it.

    The records are aligned by cross-correlation (:func:`estimate_lag`, as the fit did),
    and the delay of the filter's model is fitted to their measured correction over the
    coherent bins of the filter's band (:func:`fit_delay`, as the fit did for its model):
    the offset is the lag minus that delay. With fewer than 2 such bins, the lag alone.
    """
    lag_s = estimate_lag(sensor, reference)
    ref = resample_to(reference, sensor, lag_s=lag_s)
    dim = sensor.dims[0]
    keep = np.isin(sensor["time"].values, ref["time"].values)
    sens = sensor.isel({dim: np.flatnonzero(keep)})
    sens = sens.copy(data=np.asarray(sens.values, float) * static_factor(sens.values, ref.values))
    tf = transfer_function(sens, ref, nperseg=nperseg, min_coherence=min_coherence,
                           band_hz=(0.0, filt.band_hz[1]))
    if tf.used.sum() < 2:
        return lag_s
    f_hz = tf.f_hz[tf.used]
    return lag_s - fit_delay(f_hz, tf.response[tf.used], filt.target(f_hz),
                             tf.gain_error[tf.used])


def _above_band_share(values, fs_hz, band_top_hz, static_cutoff_hz):
    """Share of the dynamic power of ``values`` above ``band_top_hz`` (Welch, 1 Hz bins)."""
    f_hz, power = signal.welch(values, fs=fs_hz, nperseg=min(values.size, int(round(fs_hz))))
    dynamic = f_hz > static_cutoff_hz
    total = power[dynamic].sum()
    return float(power[f_hz > band_top_hz].sum() / total) if total > 0 else 0.0


def _on_clock(reference, sensor, lag_s):
    """Return the reference on the sensor's stamps at ``lag_s`` and the frames it covers."""
    ref = resample_to(reference, sensor, lag_s=lag_s)
    return ref, np.flatnonzero(np.isin(sensor["time"].values, ref["time"].values))


def _dynamic_rms(x, r, fs_hz, static_cutoff_hz):
    return float(np.sqrt(np.mean(dynamic_part(x - r, fs_hz,
                                              static_cutoff_hz=static_cutoff_hz) ** 2)))


def evaluate(filt, sensor, reference, *, lag_s=None, realign=False, static_cutoff_hz=0.5,
             nperseg=None, min_coherence=0.9, progress=None, causal=False):
    """Evaluate a filter on a sweep or a blind test (Gillis 2013, 4.3.3 and 4.4.1).

    Parameters
    ----------
    filt : CorrectionFilter
    sensor, reference : xarray.DataArray
        1-D records (any rates and start times).
    lag_s : float, optional
        The records' clock offset, when it is known (e.g. a common trigger): scored there
        (``clock="given"``). Default: the fitted clock (see the module notes).
    realign : bool
        Also score the corrected record at the lag that aligns it best
        (``rms_after_realigned_N``): what a perfectly re-timed record would give.
    static_cutoff_hz : float
        The dynamic part is the content above it (:func:`dynamic_part`).
    nperseg, min_coherence
        Welch segment and coherence threshold of the amplitude-error spectrum (bins where
        either the raw or the corrected record is incoherent with the reference are left
        out) and of the fitted clock.
    progress : callable, optional
        Passed to :func:`apply_filter`.
    causal : bool
        Evaluate a rational filter's causal inverse (see :func:`apply_filter`).

    Returns
    -------
    Evaluation

    Examples
    --------
    >>> from tactilecal.dynamic import CorrectionFilter
    >>> from tactilecal.simulate import sine_sweep
    >>> s = sine_sweep(seed=0, step_hz=2, cycles_high=10, fs_sensor_hz=1000.0,
    ...                fs_reference_hz=1250.0)  # true law: A = 0.11, log10
    >>> filt = CorrectionFilter.from_model(("log10", {"A": 0.11}), fs_hz=1000.0, band_hz=(1, 140))
    >>> ev = evaluate(filt, s.sensor, s.reference)  # at the fitted clock
    >>> ev.clock, round(ev.lag_s, 3), round(ev.rms_before_N, 1), round(ev.rms_after_N, 1)
    ('fitted', 0.837, 7.5, 1.2)
    >>> abs(ev.timing_error_s) < 1e-4  # the corrected record sits on that clock
    True
    """
    fs_hz = filt.fs_hz
    nperseg = int(round(fs_hz)) if nperseg is None else int(nperseg)
    corrected_full = filter_values(sensor, filt, progress=progress, causal=causal)
    clock = "given" if lag_s is not None else "fitted"
    if lag_s is None:
        lag_s = _fitted_clock(filt, sensor, reference, nperseg, min_coherence)
    realigned_s = estimate_lag(corrected_full, reference, near_lag_s=lag_s,
                               near_width_s=0.05)
    ref, keep = _on_clock(reference, sensor, lag_s)
    dim = sensor.dims[0]
    sens = np.asarray(sensor.isel({dim: keep}).values, float)
    corr = np.asarray(corrected_full.isel({dim: keep}).values, float)
    r = np.asarray(ref.values, float)
    factor = static_factor(sens, r)
    sens, corr = sens * factor, corr * factor
    rms = [_dynamic_rms(x, r, fs_hz, static_cutoff_hz) for x in (sens, corr)]
    realigned_rms, r_realigned = float("nan"), np.empty(0)
    if realign:
        ref2, keep2 = _on_clock(reference, sensor, realigned_s)
        corr2 = np.asarray(corrected_full.isel({dim: keep2}).values, float) * factor
        r_realigned = np.interp(ref["time"].values, ref2["time"].values, ref2.values)
        realigned_rms = _dynamic_rms(corr2, np.asarray(ref2.values, float), fs_hz,
                                     static_cutoff_hz)
    f_hz, before, ok_b, phase_b = _amplitude_error_pct(sens, r, fs_hz, nperseg, min_coherence)
    _, after, ok_a, phase_a = _amplitude_error_pct(corr, r, fs_hz, nperseg, min_coherence)
    ok = ok_b & ok_a & (f_hz > 0)
    t = np.asarray(ref["time"].values)
    top = filt.band_hz[1]
    return Evaluation(
        float(lag_s), clock, factor, fs_hz, tuple(filt.band_hz), rms[0], rms[1],
        float(realigned_s - lag_s), _above_band_share(r, fs_hz, top, static_cutoff_hz),
        f_hz[ok], before[ok], after[ok], phase_b[ok], phase_a[ok], realigned_rms,
        window=_zoom(t, r, sens, corr, fs_hz, top, static_cutoff_hz),
        spectra=_spectra(r, sens, corr, fs_hz, top), time_s=t, sensor=sens, corrected=corr,
        reference=r, reference_realigned=r_realigned,
        provenance=provenance_of([sensor, reference]))


def compare_filters(filters, sensor, reference, *, lag_s=None, static_cutoff_hz=0.5,
                    nperseg=None, min_coherence=0.9, causal=False):
    """Apply several sensors' filters to one sensor's sweep (Gillis 2013, section 4.5).

    Parameters
    ----------
    filters : dict
        Name -> :class:`CorrectionFilter` (e.g. the sensor's own filter and another
        sensor's).
    sensor, reference : xarray.DataArray
        The sweep to correct and its load cell.
    lag_s : float, optional
        The records' clock offset; default that of the first filter's fitted clock, so
        every filter is scored at the same clock.
    static_cutoff_hz, nperseg, min_coherence, causal
        As in :func:`evaluate`.

    Returns
    -------
    dict
        ``{"evaluations": {name: Evaluation}, "rms_difference_N": {"a vs b": RMS of the
        difference between the two corrected records}, "max_gain_difference": {"a vs b":
        largest |G_a - G_b| over 0..max band}}``.

    Examples
    --------
    >>> from tactilecal.dynamic import CorrectionFilter
    >>> from tactilecal.simulate import sine_sweep
    >>> s = sine_sweep(seed=0, step_hz=2, cycles_high=10, fs_sensor_hz=1000.0,
    ...                fs_reference_hz=1250.0)  # true law: A = 0.11, log10
    >>> filters = {f"A={a}": CorrectionFilter.from_model(("log10", {"A": a}), fs_hz=1000.0,
    ...                                                  band_hz=(1, 140)) for a in (0.11, 0.05)}
    >>> out = compare_filters(filters, s.sensor, s.reference)
    >>> {name: round(ev.improvement, 1) for name, ev in out["evaluations"].items()}
    {'A=0.11': 6.4, 'A=0.05': 1.8}
    >>> round(out["max_gain_difference"]["A=0.11 vs A=0.05"], 3)
    0.129
    """
    names = list(filters)
    if len(names) < 2:
        raise TactilecalError(f"filters: {len(names)} given; expected at least 2 to compare")
    options = {"static_cutoff_hz": static_cutoff_hz, "nperseg": nperseg,
               "min_coherence": min_coherence, "causal": causal}
    first = evaluate(filters[names[0]], sensor, reference, lag_s=lag_s, **options)
    evals = {names[0]: first} | {n: evaluate(filters[n], sensor, reference,
                                             lag_s=first.lag_s, **options)
                                 for n in names[1:]}
    diff, gain_diff = {}, {}
    for i, a in enumerate(names):
        for b in names[i + 1:]:
            key = f"{a} vs {b}"
            diff[key] = float(np.sqrt(np.mean((evals[a].corrected - evals[b].corrected) ** 2)))
            top = max(filters[a].band_hz[1], filters[b].band_hz[1])
            f = np.linspace(0.0, top, 512)
            gain_diff[key] = float(np.max(np.abs(filters[a].gain(f) - filters[b].gain(f))))
    return {"evaluations": evals, "rms_difference_N": diff, "max_gain_difference": gain_diff}
