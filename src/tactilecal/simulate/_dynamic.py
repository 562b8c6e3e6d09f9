"""Simulated dynamic-calibration sessions of Gillis (2013), section 4.3-4.4 and Table 4.2.

A loading machine applies a load made of sine *sets* (frequency, amplitude, whole cycles)
about an offset. The sensor records it through a known frequency-dependent gain and the
machine's load cell records it unchanged, each at its own rate, with its own clock and
noise. Everything returned is in newtons on 1-D records with a ``time`` coordinate (s).

The sensor's gain law is the inverse of the thesis' eq. 4.1 transfer function:
``sensor(f) = load(f) / (1 + A log_base(f + 1))``, applied in the frequency domain (zero
phase) to the load sampled at the sensor's rate.
"""

from dataclasses import dataclass
from functools import partial

import numpy as np
import pandas as pd
import xarray as xr
from scipy import fft

from tactilecal._errors import TactilecalError
from tactilecal._units import LBF_N

__all__ = ["DynamicSensor", "DynamicSession", "sine_sweep", "random_sine_sets",
           "sensel_matrix", "LBF_N"]

_BASES = {"e": np.e, "10": 10.0}
#: The thesis' sweep amplitude (20 lb), the amplitude a sensor's law ``A`` is stated at.
SWEEP_AMPLITUDE_N = 20.0 * LBF_N


@dataclass(frozen=True)
class DynamicSensor:
    """The dynamic response of a simulated sensor: ``H(f) = sensor(f) / load(f)``, the truth.

    ``H`` is the product of three parts, each equal to 1 at 0 Hz (a static calibration is
    not changed by the dynamics):

    * the thesis' gain law, ``1 / (1 + A log_base(f + 1))`` (Gillis 2013, eq. 4.1 inverted;
      zero phase, as the thesis observed);
    * real corners of a linear viscoelastic solid, ``prod(1 + j f/fz) / prod(1 + j f/fp)``
      (METHOD-NOTES D; causal, with the phase lag that goes with a falling gain);
    * mounting resonances, ``prod 1 / (1 - (f/fn)^2 + 2 j zeta f/fn)`` (METHOD-NOTES G),
      and anti-resonances, ``prod (1 - (f/fn)^2 + 2 j zeta f/fn)`` (a frequency the sensor
      barely reads).

    ``amplitude_exponent`` makes the gain law depend on the load's amplitude: a sine set
    of amplitude ``a`` sees ``A (a_ref / a) ** amplitude_exponent`` (``a_ref`` =
    ``reference_amplitude_N``, the thesis' 20 lb); 0 is a linear sensor.

    Examples
    --------
    >>> s = DynamicSensor(A=0.0, resonances=((80.0, 0.05),))
    >>> round(float(abs(s.response(80.0))), 6), round(float(abs(s.response(0.0))), 6)
    (10.0, 1.0)
    >>> round(float(abs(DynamicSensor().correction(99.0))), 4)  # 1 + 0.11 log10(100)
    1.22
    """

    A: float = 0.11
    log_base: str = "10"
    zeros_hz: tuple = ()
    poles_hz: tuple = ()
    resonances: tuple = ()
    antiresonances: tuple = ()
    amplitude_exponent: float = 0.0
    reference_amplitude_N: float = SWEEP_AMPLITUDE_N

    def __post_init__(self):
        if self.log_base not in _BASES:
            raise TactilecalError(f"log_base={self.log_base!r}; expected 'e' or '10'")
        pairs = (*self.resonances, *self.antiresonances)
        corners = [*self.zeros_hz, *self.poles_hz, *(f for f, _ in pairs)]
        if any(not np.isfinite(f) or f <= 0 for f in corners):
            raise TactilecalError(f"corner frequencies {corners}; expected finite values > 0 Hz")
        if any(not 0 < z < 1 for _, z in pairs):
            raise TactilecalError(f"(anti)resonances {pairs}; expected damping in (0, 1)")

    def law_A(self, amplitude_N=None):
        """Return the gain law's ``A`` at a sine amplitude (N); ``A`` itself when None."""
        if amplitude_N is None or self.amplitude_exponent == 0:
            return self.A
        return self.A * (self.reference_amplitude_N / amplitude_N) ** self.amplitude_exponent

    def response(self, f_hz, amplitude_N=None):
        """Return the complex ``H(f)`` (sensor / load) at ``f_hz`` for a sine of that amplitude."""
        f = np.asarray(f_hz, dtype=float)
        h = 1.0 / (1.0 + self.law_A(amplitude_N) * np.log(f + 1.0) / np.log(_BASES[self.log_base]))
        h = h + 0j
        for fz in self.zeros_hz:
            h = h * (1 + 1j * f / fz)
        for fp in self.poles_hz:
            h = h / (1 + 1j * f / fp)
        for fn, zeta in self.resonances:
            h = h / (1 - (f / fn) ** 2 + 2j * zeta * f / fn)
        for fn, zeta in self.antiresonances:
            h = h * (1 - (f / fn) ** 2 + 2j * zeta * f / fn)
        return h

    def correction(self, f_hz, amplitude_N=None):
        """Return the exact correction ``1 / H`` (reference / sensor)."""
        return 1.0 / self.response(f_hz, amplitude_N)

    def read(self, record):
        """Return ``record`` (a load, 1-D with ``time``) as this sensor reads it: ``H`` applied.

        The record's deviation from its mean passes through ``H`` in the frequency domain
        (circularly: give a record that starts and ends at rest); the mean is kept.

        Examples
        --------
        >>> import xarray as xr
        >>> t = np.arange(0, 2, 1e-3)
        >>> load = xr.DataArray(100 + np.sin(2 * np.pi * 40 * t), dims="time", coords={"time": t})
        >>> seen = DynamicSensor(A=0.0, zeros_hz=(40.0,), poles_hz=(10.0,)).read(load)
        >>> round(float(np.ptp(seen.values) / 2), 2)  # |H(40 Hz)| = |1 + j| / |1 + 4j|
        0.34
        """
        time_s = np.asarray(record["time"].values, dtype=float)
        values = np.asarray(record.values, dtype=float)
        fs_hz = (time_s.size - 1) / (time_s[-1] - time_s[0])
        f_hz = fft.rfftfreq(values.size, 1.0 / fs_hz)
        mean = values.mean()
        out = fft.irfft(fft.rfft(values - mean) * self.response(f_hz), n=values.size) + mean
        return record.copy(data=out)

    def truth(self):
        """Return the response's parameters as plain values."""
        return {"A": self.A, "log_base": self.log_base, "zeros_hz": list(self.zeros_hz),
                "poles_hz": list(self.poles_hz),
                "resonances_hz_damping": [list(r) for r in self.resonances],
                "antiresonances_hz_damping": [list(r) for r in self.antiresonances],
                "amplitude_exponent": self.amplitude_exponent,
                "reference_amplitude_N": self.reference_amplitude_N,
                "response": "H = sensor/load = 1/(1 + A log_base(f + 1)) x prod(1 + j f/fz) / "
                            "prod(1 + j f/fp) x prod 1/(1 - (f/fn)^2 + 2 j zeta f/fn) "
                            "[resonances] x prod (1 - (f/fn)^2 + 2 j zeta f/fn) "
                            "[antiresonances]"}


@dataclass
class DynamicSession:
    """A simulated loading-machine test with its truth.

    Attributes
    ----------
    sensor : xarray.DataArray
        Statically calibrated sensor force (N), dim ``time`` (sensor clock, from 0 s).
    reference : xarray.DataArray
        Load-cell force (N), dim ``time`` on the load cell's own clock (from 0 s).
    lag_s : float
        True shift to add to the reference's stamps to put them on the sensor's clock.
    response : DynamicSensor
        The sensor's true dynamic response.
    sets : pandas.DataFrame
        One row per sine set: ``f_hz``, ``amplitude_N``, ``cycles``, ``start_s`` (sensor
        clock).
    offset_N : float
        Static load the sets oscillate about.
    """

    sensor: xr.DataArray
    reference: xr.DataArray
    lag_s: float
    response: DynamicSensor
    sets: pd.DataFrame
    offset_N: float

    @property
    def A(self):
        """The gain law's ``A`` (eq. 4.1) at the thesis' amplitude."""
        return self.response.A

    @property
    def log_base(self):
        """The base of the gain law's logarithm (``"e"`` or ``"10"``)."""
        return self.response.log_base

    def true_gain(self, f_hz):
        """Return the true transfer function ``|load(f)| / |sensor(f)|`` (eq. 4.1)."""
        return np.abs(self.response.correction(f_hz))

    def load_N(self, time_s):
        """Return the applied load (N) at sensor-clock times ``time_s``."""
        return _load(np.asarray(time_s, float), self.sets, self.offset_N, self._ramp_s)

    def truth(self):
        """Return the truth as plain values: response, lag, offset and the sine sets."""
        return {"kind": "loading-machine sine sets (Gillis 2013, Table 4.2)",
                "gain_law": f"Y(f) = 1 + A log_{self.log_base}(f + 1)", "A": self.A,
                "log_base": self.log_base, "response": self.response.truth(),
                "lag_s": self.lag_s,
                "lag_convention": "add lag_s to the reference's time stamps to put them on "
                                  "the sensor's clock", "offset_N": self.offset_N,
                "sets": self.sets.to_dict(orient="list")}

    def write(self, outdir, *, overwrite=False):
        """Write ``sensor.csv``, ``reference.csv`` (load cell) and ``truth.json``.

        The CSVs are :func:`tactilecal.io.write_timeseries` files (``Time (s),force (N)``),
        the inputs of ``tactilecal dynamic fit`` and ``evaluate``.

        Parameters
        ----------
        outdir : str or os.PathLike
            Folder, created if missing. Every file is written atomically.
        overwrite : bool, keyword-only
            Write into a folder that holds files: only an earlier session's.

        Returns
        -------
        dict
            Paths written, by role (``sensor``, ``reference``, ``truth``).
        """
        from tactilecal.io import write_timeseries
        from tactilecal.simulate._write import write_session

        return write_session(outdir, {
            "sensor": ("sensor.csv", partial(write_timeseries, self.sensor, overwrite=True)),
            "reference": ("reference.csv",
                          partial(write_timeseries, self.reference, overwrite=True))},
            self.truth(), overwrite=overwrite)

    _ramp_s: float = 1.0


def _sets_table(f_hz, amplitude_N, cycles, start_s, gap_s):
    durations = cycles / f_hz
    starts = start_s + np.cumsum(np.r_[0.0, (durations + gap_s)[:-1]])
    return pd.DataFrame({"f_hz": f_hz, "amplitude_N": amplitude_N, "cycles": cycles,
                         "start_s": starts})


def _load(t, sets, offset_N, ramp_s):
    """Offset with ramps in and out, plus the sine sets (whole cycles, zero phase start)."""
    starts = sets["start_s"].to_numpy()
    ends = starts + sets["cycles"].to_numpy() / sets["f_hz"].to_numpy()
    t_on, t_off = starts[0] - 1.0, ends[-1] + 1.0  # 1 s of steady offset each side
    base = offset_N * np.interp(t, [t_on - ramp_s, t_on, t_off, t_off + ramp_s],
                                [0.0, 1.0, 1.0, 0.0])
    i = np.clip(np.searchsorted(starts, t, side="right") - 1, 0, len(starts) - 1)
    inside = (t >= starts[i]) & (t < ends[i])
    phase = 2 * np.pi * sets["f_hz"].to_numpy()[i] * (t - starts[i])
    return base + np.where(inside, sets["amplitude_N"].to_numpy()[i] * np.sin(phase), 0.0)


def _record(time_s, values, source):
    return xr.DataArray(values, dims="time", coords={"time": time_s}, name="force",
                        attrs={"units": "N", "source": source})


def _sine_parts(t, sets):
    """Yield ``(amplitude_N, part)``: the load's sine sets grouped by amplitude."""
    starts = sets["start_s"].to_numpy()
    ends = starts + sets["cycles"].to_numpy() / sets["f_hz"].to_numpy()
    amplitudes = sets["amplitude_N"].to_numpy()
    for amplitude in np.unique(amplitudes):
        part = np.zeros(t.size)
        for k in np.flatnonzero(amplitudes == amplitude):
            inside = (t >= starts[k]) & (t < ends[k])
            part[inside] = amplitude * np.sin(2 * np.pi * sets["f_hz"].iloc[k]
                                              * (t[inside] - starts[k]))
        yield amplitude, part


def _read(response, load, t, sets, offset_N, ramp_s, fs_hz):
    """Return the sensor's noiseless reading of ``load``: ``H`` in the frequency domain.

    The record starts and ends at zero load, so the circular FFT convolution is the
    linear one. An amplitude-dependent response reads each group of sine sets of one
    amplitude through its own ``H``, the offset and ramps through ``H`` at ``a_ref``.
    """
    f_hz = fft.rfftfreq(t.size, 1.0 / fs_hz)
    if response.amplitude_exponent == 0:
        return fft.irfft(fft.rfft(load) * response.response(f_hz), n=t.size)
    base = _load(t, sets.assign(amplitude_N=0.0), offset_N, ramp_s)  # offset and ramps
    out = fft.irfft(fft.rfft(base) * response.response(f_hz), n=t.size)
    for amplitude, part in _sine_parts(t, sets):
        out += fft.irfft(fft.rfft(part) * response.response(f_hz, amplitude), n=t.size)
    return out


def _session(sets, offset_N, *, response, fs_sensor_hz, fs_reference_hz, lag_s,
             sensor_noise_N, reference_noise_N, rng, ramp_s=1.0):
    end_s = sets["start_s"].iloc[-1] + sets["cycles"].iloc[-1] / sets["f_hz"].iloc[-1]
    total_s = end_s + 1.0 + ramp_s + 0.5
    t_sens = np.arange(0.0, total_s, 1.0 / fs_sensor_hz)
    load = _load(t_sens, sets, offset_N, ramp_s)
    sensor = _read(response, load, t_sens, sets, offset_N, ramp_s, fs_sensor_hz)
    sensor += rng.normal(0.0, sensor_noise_N, t_sens.size)
    t_ref = np.arange(0.0, total_s - lag_s, 1.0 / fs_reference_hz)
    reference = _load(t_ref + lag_s, sets, offset_N, ramp_s)
    reference += rng.normal(0.0, reference_noise_N, t_ref.size)
    session = DynamicSession(_record(t_sens, sensor, "simulated sensor"),
                             _record(t_ref, reference, "simulated load cell"),
                             float(lag_s), response, sets, float(offset_N))
    session._ramp_s = ramp_s
    return session


def _response(A, log_base, response):
    """Return the response: ``response``, or the thesis' law of ``A`` and ``log_base``."""
    if response is None:
        law = {"A": A, "log_base": log_base}
        return DynamicSensor(**{key: value for key, value in law.items() if value is not None})
    if A is not None or log_base is not None:
        raise TactilecalError("A and log_base describe the thesis' law; expected them or "
                              "response=DynamicSensor(...), not both")
    if not isinstance(response, DynamicSensor):
        raise TypeError(f"response of type {type(response).__name__}; expected a DynamicSensor")
    return response


def sine_sweep(*, f_start_hz=1, f_stop_hz=140, step_hz=1, reverse=False, A=None,
               log_base=None, response=None, offset_lbf=120.0, amplitude_lbf=20.0, cycles_low=3,
               cycles_high=20, low_until_hz=5, fs_sensor_hz=4000.0, fs_reference_hz=5000.0,
               lag_s=0.8373, sensor_noise_N=1.0, reference_noise_N=0.2, seed=0):
    """Simulate the thesis' sine-sweep calibration or its reverse (Blind Test 1).

    Gillis (2013), section 4.3.1 and Table 4.2: 1 to 140 Hz in 1 Hz steps, 3 cycles up to
    5 Hz then 20, 20 lb amplitude about 120 lb, load cell at 5000 Hz, sensor at 4000 Hz.

    Parameters
    ----------
    f_start_hz, f_stop_hz, step_hz : float
        Frequencies of the sets (``reverse=True`` runs them from high to low).
    A, log_base : float, {"e", "10"}
        True gain law of eq. 4.1; the sensor reads ``load(f) / (1 + A log(f + 1))``
        (default A = 0.11, log10).
    response : DynamicSensor, optional
        The sensor's whole dynamic response instead (then A and log_base are not given).
    offset_lbf, amplitude_lbf : float
        Offset and amplitude in pound-force (converted to N).
    cycles_low, cycles_high, low_until_hz : int, int, float
        Cycles per set: ``cycles_low`` for frequencies up to ``low_until_hz``.
    fs_sensor_hz, fs_reference_hz : float
        Sampling rates.
    lag_s : float
        The load cell starts this much later than the sensor (positive).
    sensor_noise_N, reference_noise_N : float
        Standard deviations of the white noise added to each record.
    seed : int
        Seed of :func:`numpy.random.default_rng`.

    Returns
    -------
    DynamicSession

    Examples
    --------
    >>> s = sine_sweep(f_stop_hz=20, step_hz=5)
    >>> s.sets["f_hz"].tolist(), s.sets["cycles"].tolist()
    ([1.0, 6.0, 11.0, 16.0], [3, 20, 20, 20])
    >>> round(float(s.true_gain(100.0)), 4)
    1.2205
    """
    f_hz = np.arange(f_start_hz, f_stop_hz + 1e-9 * step_hz, step_hz, dtype=float)
    if reverse:
        f_hz = f_hz[::-1]
    cycles = np.where(f_hz <= low_until_hz, cycles_low, cycles_high)
    sets = _sets_table(f_hz, np.full(f_hz.size, amplitude_lbf * LBF_N), cycles,
                       start_s=2.0, gap_s=0.0)
    return _session(sets, offset_lbf * LBF_N, response=_response(A, log_base, response),
                    fs_sensor_hz=fs_sensor_hz, fs_reference_hz=fs_reference_hz, lag_s=lag_s,
                    sensor_noise_N=sensor_noise_N, reference_noise_N=reference_noise_N,
                    rng=np.random.default_rng(seed))


def random_sine_sets(*, n_sets=20, f_range_hz=(10.0, 200.0), amplitude_range_lbf=(0.5, 60.0),
                     cycles_range=(10, 200), offset_lbf=100.0, gap_s=0.5, A=None,
                     log_base=None, response=None, fs_sensor_hz=4000.0, fs_reference_hz=5000.0,
                     lag_s=0.6121, sensor_noise_N=1.0, reference_noise_N=0.2, seed=1):
    """Simulate Blind Test 2 of Gillis (2013), Table 4.2: random sine sets about 100 lb.

    Frequencies are drawn uniformly in ``f_range_hz``; amplitudes log-uniformly in
    ``amplitude_range_lbf`` and paired so that higher frequencies get lower amplitudes, and
    cycles grow with frequency inside ``cycles_range`` (as the thesis describes). Sets are
    separated by ``gap_s`` of steady offset ("dead zones").

    Parameters
    ----------
    n_sets : int
        About 20 in the thesis.
    f_range_hz, amplitude_range_lbf, cycles_range : tuple
        Ranges of the sets.
    offset_lbf, gap_s : float
        Offset load and pause between sets.
    A, log_base, response, fs_sensor_hz, fs_reference_hz, lag_s
        As in :func:`sine_sweep`.
    sensor_noise_N, reference_noise_N, seed
        As in :func:`sine_sweep`.

    Returns
    -------
    DynamicSession

    Examples
    --------
    >>> s = random_sine_sets(n_sets=4, seed=3)
    >>> bool((s.sets["amplitude_N"].diff().dropna() <= 0).all())
    False
    >>> bool(s.sets.sort_values("f_hz")["amplitude_N"].is_monotonic_decreasing)
    True
    """
    rng = np.random.default_rng(seed)
    f_hz = np.round(rng.uniform(*f_range_hz, n_sets), 1)
    amp = np.exp(rng.uniform(*np.log(amplitude_range_lbf), n_sets))
    rank = np.argsort(np.argsort(f_hz))  # rank of each frequency, 0 = lowest
    amp_lbf = np.sort(amp)[::-1][rank]
    frac = (f_hz - f_range_hz[0]) / (f_range_hz[1] - f_range_hz[0])
    cycles = np.round(cycles_range[0] + frac * (cycles_range[1] - cycles_range[0]))
    sets = _sets_table(f_hz, amp_lbf * LBF_N, cycles.astype(int), start_s=2.0, gap_s=gap_s)
    return _session(sets, offset_lbf * LBF_N, response=_response(A, log_base, response),
                    fs_sensor_hz=fs_sensor_hz, fs_reference_hz=fs_reference_hz, lag_s=lag_s,
                    sensor_noise_N=sensor_noise_N, reference_noise_N=reference_noise_N,
                    rng=rng)


def sensel_matrix(session, *, shape=(14, 14), gain_spread=0.05, noise_N=0.01, seed=2):
    """Spread a session's sensor force over a small sensel matrix (N per sensel).

    Every sensel carries ``force / n_sensels`` times its own gain (``1 + gain_spread``
    x standard normal) plus white noise, so each sensel has the session's dynamic gain law.

    Parameters
    ----------
    session : DynamicSession
    shape : tuple of int
        ``(rows, cols)``; 14 x 14 is the 9500 sensor of the thesis.
    gain_spread, noise_N : float
        Relative spread of sensel gains and per-sensel noise (N).
    seed : int

    Returns
    -------
    xarray.DataArray
        dims ``("frame", "row", "col")``, ``time`` coordinate along ``frame``, units N.

    Examples
    --------
    >>> m = sensel_matrix(sine_sweep(f_stop_hz=10, step_hz=5), shape=(2, 3))
    >>> m.dims, m.sizes["row"], m.attrs["units"]
    (('frame', 'row', 'col'), 2, 'N')
    """
    rng = np.random.default_rng(seed)
    rows, cols = shape
    gains = 1.0 + gain_spread * rng.standard_normal(shape)
    force = session.sensor.values
    data = force[:, None, None] * (gains / (rows * cols))
    data += rng.normal(0.0, noise_N, data.shape)
    time_s = session.sensor["time"].values
    fs_hz = (time_s.size - 1) / (time_s[-1] - time_s[0])
    return xr.DataArray(
        data, dims=("frame", "row", "col"),
        coords={"frame": np.arange(1, time_s.size + 1), "time": ("frame", time_s),
                "row": np.arange(rows), "col": np.arange(cols)},
        attrs={"units": "N", "source": "simulated sensel matrix",
               "seconds_per_frame": 1.0 / fs_hz})
