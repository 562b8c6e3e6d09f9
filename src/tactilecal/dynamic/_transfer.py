"""Transfer function ``|reference(f)| / |sensor(f)|`` with coherence (Gillis 2013, 4.3.3).

Three estimates on the same Welch frequency grid (:func:`scipy.signal.welch`,
:func:`scipy.signal.csd`), with the sensor as input ``x`` and the reference as output ``y``:

``"ratio"``
    The thesis' ratio of amplitude spectra, ``sqrt(P_yy / P_xx)`` (Welch-averaged).
``"h1"``
    ``|P_xy| / P_xx``: unbiased by noise on the reference, biased low by sensor noise.
``"h2"``
    ``P_yy / |P_xy|``: unbiased by noise on the sensor (the noisier channel here), biased
    high by reference noise.

The magnitude-squared coherence ``|P_xy|^2 / (P_xx P_yy)`` tells which bins carry the
loading; bins below ``min_coherence`` are left out of the fit, and so are bins whose load-cell
power is more than ``min_power_db`` below the median of the coherent bins: the abrupt start
and end of each sine set leak a little energy some way above the sweep's top frequency,
coherent but weak, which is not a calibration of those frequencies (METHOD-NOTES G: a filter
is only meaningful where the sweep carried coherent energy).
"""

from dataclasses import dataclass, field

import numpy as np
from scipy import signal

from tactilecal._errors import TactilecalError
from tactilecal.dynamic._records import label, sampling_rate_hz, time_and_values

__all__ = ["TransferFunction", "transfer_function", "pool_transfer", "METHODS"]

METHODS = ("ratio", "h1", "h2")


@dataclass
class TransferFunction:
    """Measured transfer function on a frequency grid.

    Attributes
    ----------
    f_hz, gain, coherence : numpy.ndarray
        Frequencies (Hz), ``|reference| / |sensor|`` and magnitude-squared coherence.
    used : numpy.ndarray of bool
        Bins kept for a fit: coherence at least ``min_coherence``, load-cell power within
        ``min_power_db`` of the coherent bins' median, ``f > 0``, inside ``band_hz`` when
        one was given.
    method : str
        ``"ratio"``, ``"h1"`` or ``"h2"``.
    fs_hz, nperseg, min_coherence : float, int, float
        How it was computed.
    excluded : dict
        Number of bins left out, per reason (``low_coherence``, ``low_power``,
        ``outside_band``, ``zero_frequency``).
    response : numpy.ndarray of complex or None
        The complex ``reference / sensor`` of the same estimator (``h1``: ``P_xy / P_xx``,
        ``h2``: ``P_yy / P_yx``, ``ratio``: the ratio's magnitude with the phase of
        ``P_xy``); its phase is the sensor's lag (after the clocks were aligned). ``gain``
        is its magnitude.
    gain_error : numpy.ndarray or None
        Normalised random error of ``gain`` per bin, ``sqrt(1 - coherence) / (|gamma|
        sqrt(2 n_d))`` with ``n_d`` Welch averages (Bendat & Piersol, Random Data, eq. 9.90):
        the 95 % band is ``gain (1 +- 1.96 gain_error)``; the phase's standard deviation in
        radians is the same number (eq. 9.91).
    """

    f_hz: np.ndarray
    gain: np.ndarray
    coherence: np.ndarray
    used: np.ndarray
    method: str
    fs_hz: float
    nperseg: int
    min_coherence: float
    excluded: dict = field(default_factory=dict)
    response: np.ndarray | None = None
    gain_error: np.ndarray | None = None
    min_power_db: float = float("inf")
    power: np.ndarray | None = None

    def band_note(self):
        """Say where the coherent energy of the sweep lies and which bins were left out."""
        if not self.used.any():
            return "no bin has coherent energy"
        f = self.f_hz[self.used]
        weak = self.excluded.get("low_power", 0)
        note = (f"the sweep has coherent energy from {f.min():g} to {f.max():g} Hz "
                f"({f.size} bins with coherence >= {self.min_coherence:g}")
        if np.isfinite(self.min_power_db):
            note += f" and load-cell power within {self.min_power_db:g} dB of their median"
        note += ")"
        if weak:
            note += f"; {weak} coherent bins with less power left out"
        above = int(np.count_nonzero(self.f_hz > f.max()))
        return note + f"; {above} bins above {f.max():g} Hz are not calibrated"


def _check_band(band_hz, fs_hz, where):
    if band_hz is None:
        return None
    lo, hi = (float(v) for v in band_hz)
    if not 0 <= lo < hi:
        raise TactilecalError(f"band_hz=({lo:g}, {hi:g}); expected 0 <= LO < HI")
    if hi > fs_hz / 2:
        raise TactilecalError(f"band_hz=({lo:g}, {hi:g}) reaches beyond the Nyquist frequency "
                              f"{fs_hz / 2:g} Hz of {where} (sampled at {fs_hz:g} Hz); expected "
                              f"HI <= {fs_hz / 2:g}")
    return lo, hi


def transfer_function(sensor, reference, *, method="h2", nperseg=None, min_coherence=0.9,
                      min_power_db=20.0, band_hz=None):
    """Estimate ``|reference(f)| / |sensor(f)|`` from aligned records.

    Implements the transfer function of Gillis (2013), section 4.3.3 (Figure 4.9).

    Parameters
    ----------
    sensor, reference : xarray.DataArray
        Aligned 1-D records on the same time stamps (see :func:`align`).
    method : {"h2", "h1", "ratio"}
        Estimator, see the module notes. ``"h2"`` (default) is unbiased by sensor noise.
    nperseg : int, optional
        Welch segment length (default one second of samples: 1 Hz bins, the thesis' sweep
        step).
    min_coherence : float
        Bins with a lower coherence are not used.
    min_power_db : float
        Coherent bins whose load-cell power is more than this many dB below the median of
        the coherent bins are not used (``inf``: no power criterion).
    band_hz : tuple of float, optional
        ``(lo, hi)``: only bins inside are used.

    Returns
    -------
    TransferFunction

    Raises
    ------
    ValueError
        Unknown method, records of different lengths, a record shorter than ``nperseg``,
        a band beyond the Nyquist frequency.

    Examples
    --------
    >>> import numpy as np, xarray as xr
    >>> rng = np.random.default_rng(0)
    >>> t = np.arange(0, 8, 1 / 400)
    >>> y = rng.normal(size=t.size)
    >>> ref = xr.DataArray(y, dims="time", coords={"time": t})
    >>> sens = ref / 2
    >>> tf = transfer_function(sens, ref, nperseg=200)
    >>> bool(np.allclose(tf.gain[tf.used], 2.0))
    True
    """
    if method not in METHODS:
        raise TactilecalError(f"method={method!r}; expected one of {', '.join(METHODS)}")
    t_s, x = time_and_values(sensor, "sensor")
    t_r, y = time_and_values(reference, "reference")
    where = label(sensor, "sensor")
    if t_s.size != t_r.size or not np.allclose(t_s, t_r, rtol=0, atol=1e-6 * (t_s[1] - t_s[0])):
        raise TactilecalError(f"{where} and {label(reference, 'reference')} are not on the same "
                              f"time stamps ({t_s.size} and {t_r.size} samples); expected aligned "
                              "records (use tactilecal.dynamic.align)")
    fs_hz = sampling_rate_hz(t_s, where)
    nperseg = int(round(fs_hz)) if nperseg is None else int(nperseg)
    if x.size < nperseg:
        raise TactilecalError(f"{label(reference, 'reference')}: the overlap with {where} is "
                              f"{x.size} samples ({x.size / fs_hz:.3g} s); expected at least "
                              f"nperseg = {nperseg} samples (the filter's 1/resolution)")
    band = _check_band(band_hz, fs_hz, where)
    f_hz, pxx = signal.welch(x, fs=fs_hz, nperseg=nperseg)
    _, pyy = signal.welch(y, fs=fs_hz, nperseg=nperseg)
    _, pxy = signal.csd(x, y, fs=fs_hz, nperseg=nperseg)
    with np.errstate(divide="ignore", invalid="ignore"):
        coherence = np.abs(pxy) ** 2 / (pxx * pyy)
        gain = {"ratio": np.sqrt(pyy / pxx), "h1": np.abs(pxy) / pxx,
                "h2": pyy / np.abs(pxy)}[method]
        response = gain * np.exp(1j * np.angle(pxy))  # csd(x, y) = E[conj(X) Y]: y/x phase
        n_averages = max(1, (x.size - nperseg) // (nperseg // 2) + 1)  # Welch, 50 % overlap
        gain_error = np.sqrt(1 - np.clip(coherence, 0, 1)) / (
            np.sqrt(np.clip(coherence, 1e-12, 1)) * np.sqrt(2 * n_averages))
    coherent = (np.nan_to_num(coherence) >= min_coherence) & (f_hz > 0) & np.isfinite(gain)
    in_band = np.ones(f_hz.size, bool) if band is None else (f_hz >= band[0]) & (f_hz <= band[1])
    strong = _strong(pyy, coherent & in_band, min_power_db)
    used = coherent & strong & in_band
    excluded = {"low_coherence": int(np.count_nonzero(~coherent & in_band & (f_hz > 0))),
                "low_power": int(np.count_nonzero(coherent & ~strong & in_band)),
                "outside_band": int(np.count_nonzero(~in_band)), "zero_frequency": 1}
    return TransferFunction(f_hz, gain, coherence, used, method, fs_hz, nperseg,
                            float(min_coherence), excluded, response, gain_error,
                            float(min_power_db), pyy)


def _strong(power, coherent, min_power_db):
    """Bins whose power is within ``min_power_db`` of the median over the ``coherent`` bins."""
    if not coherent.any() or not np.isfinite(min_power_db):
        return np.ones(power.size, bool)
    return power >= np.median(power[coherent]) * 10.0 ** (-min_power_db / 10.0)


def pool_transfer(tfs):
    """Pool transfer functions of several sweeps on one grid, bin by bin.

    Each bin's correction is the mean of the sweeps that use it, weighted by ``1 / e^2``
    (``e`` its random error); the pooled error is ``1 / sqrt(sum 1 / e^2)``. A bin is used
    when any sweep uses it.

    Raises
    ------
    TactilecalError
        Sweeps on different frequency grids (another rate or ``nperseg``).
    """
    first = tfs[0]
    if len(tfs) == 1:
        return first
    for tf in tfs[1:]:
        if tf.f_hz.shape != first.f_hz.shape or not np.allclose(tf.f_hz, first.f_hz):
            raise TactilecalError(f"sweeps sampled at {first.fs_hz:g} and {tf.fs_hz:g} Hz give "
                                  "different frequency grids; expected sweeps recorded at one "
                                  "rate")
    used = np.array([tf.used for tf in tfs])
    weight = np.where(used, 1.0 / np.maximum(np.array([tf.gain_error for tf in tfs]),
                                             1e-12) ** 2, 0.0)
    total = weight.sum(axis=0)
    safe = np.where(total > 0, total, 1.0)
    response = np.sum(weight * np.nan_to_num(np.array([tf.response for tf in tfs])),
                      axis=0) / safe
    response = np.where(total > 0, response, first.response)
    gain_error = np.where(total > 0, 1.0 / np.sqrt(safe), first.gain_error)
    excluded = {k: int(min(tf.excluded.get(k, 0) for tf in tfs)) for k in first.excluded}
    return TransferFunction(first.f_hz, np.abs(response),
                            np.max([tf.coherence for tf in tfs], axis=0), used.any(axis=0),
                            first.method, first.fs_hz, first.nperseg, first.min_coherence,
                            excluded, response, gain_error, first.min_power_db,
                            np.max([tf.power for tf in tfs], axis=0))
