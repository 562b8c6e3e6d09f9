"""Uniform loads (equilibration) and ramp-and-hold loading-machine sessions (Gillis 2013)."""

from dataclasses import dataclass, field
from functools import partial
from typing import NamedTuple

import numpy as np
import xarray as xr

from tactilecal._atomic import write_text_atomic
from tactilecal._errors import TactilecalError
from tactilecal._units import KPA_MM2_TO_N
from tactilecal.simulate._loads import smooth_field
from tactilecal.simulate._sensor import SimulatedSensor
from tactilecal.simulate._write import write_session

__all__ = ["UniformLoad", "uniform_load", "RampHold", "ramp_hold", "ramp_hold_profile"]

_CHUNK_VALUES = 1_000_000
"""Sensel readings digitised per block in :func:`ramp_hold` (bounds temporary memory)."""


class UniformLoad(NamedTuple):
    """Readings under uniform pressure and the truth (unpacks as ``raw, pressure_kPa``).

    Attributes
    ----------
    raw : xarray.DataArray
        ``(frames, rows, cols)`` readings, data model.
    pressure_kPa : numpy.ndarray
        Applied pressure of each frame in kPa.
    """

    raw: xr.DataArray
    pressure_kPa: np.ndarray

    def write(self, outdir, sensor, *, overwrite=False):
        """Write one I-Scan ASCII file per pressure level and ``truth.json``.

        Parameters
        ----------
        outdir : str or os.PathLike
            Folder, created if missing; every file is written atomically.
        sensor : SimulatedSensor
            The sensor simulated (its law and per-sensel gains go into ``truth.json``).
        overwrite : bool, keyword-only
            Write into a folder that holds files: only an earlier session's.

        Returns
        -------
        dict
            Paths written, by role (``level_1``, ``level_2``... in the order of the levels,
            files ``uniform-<k>-<p>kPa.csv``; then ``truth``): the recordings that
            ``tactilecal equilibrate`` takes, one per load level.
        """
        from tactilecal.io import write_tekscan

        files = {}
        levels = list(dict.fromkeys(self.pressure_kPa.tolist()))
        for k, level in enumerate(levels, 1):
            frames = self.raw.isel(frame=np.flatnonzero(self.pressure_kPa == level))
            files[f"level_{k}"] = (f"uniform-{k}-{level:g}kPa.csv",
                                   partial(write_tekscan, frames, overwrite=True))
        truth = {"kind": "uniform pressure at each level (equilibration input)",
                 "pressures_kPa": levels,
                 "frames_per_level": int(self.raw.sizes["frame"] // len(levels)),
                 "equilibrated": "a sensel reading gain x its ideal reading is equalised by "
                                 "a gain near 1 / gain (the power law bends it slightly)",
                 "sensor": sensor.truth()}
        return write_session(outdir, files, truth, overwrite=overwrite)


def uniform_load(sensor, pressures_kPa, *, frames_per_level=5, seed=0):
    """Simulate the sensor under uniform pressure at one or several levels (equilibration).

    Every sensel carries ``p * sensel_area_mm2 * 1e-3`` newtons, so the readings differ only by
    each sensel's gain, noise, threshold, saturation and dead sensels: the input of
    equilibration ("set every sensel to equal gain under a uniform load", Gillis 2013).

    Parameters
    ----------
    sensor : SimulatedSensor
        From :func:`make_sensor`.
    pressures_kPa : float or sequence of float
        Pressure levels in kPa, applied in this order.
    frames_per_level : int
        Frames recorded at each level.
    seed : int
        Seed of the read noise.

    Returns
    -------
    UniformLoad
        ``raw`` (``len(pressures) * frames_per_level`` frames) and ``pressure_kPa`` per frame.

    Raises
    ------
    ValueError
        For negative or non-finite pressures, no pressure, or ``frames_per_level < 1``.

    Examples
    --------
    >>> from tactilecal.simulate import make_sensor
    >>> raw, p = uniform_load(make_sensor("9500"), [50.0, 100.0], frames_per_level=2)
    >>> raw.shape, p.tolist()
    ((4, 14, 14), [50.0, 50.0, 100.0, 100.0])
    """
    _check_sensor(sensor)
    levels = np.atleast_1d(np.asarray(pressures_kPa, dtype=np.float64))
    if levels.ndim != 1 or levels.size == 0 or not np.all(np.isfinite(levels) & (levels >= 0)):
        raise TactilecalError(f"pressures_kPa: got {pressures_kPa!r}; expected one or more "
                              "non-negative pressures in kPa")
    if not (int(frames_per_level) == frames_per_level >= 1):
        raise TactilecalError(f"frames_per_level: got {frames_per_level!r}; expected a positive "
                              "integer")
    pressure = np.repeat(levels, int(frames_per_level))
    force = pressure * sensor.sensel_area_mm2 * KPA_MM2_TO_N
    raw = sensor.read(np.broadcast_to(force[:, None, None], (force.size, *sensor.shape)),
                      np.random.default_rng(seed))
    return UniformLoad(sensor.to_dataarray(raw, source="simulated uniform load"), pressure)


@dataclass(eq=False)
class RampHold:
    """A simulated ramp-and-hold session: sensor movie, load-cell record and truth.

    Attributes
    ----------
    raw : xarray.DataArray
        Sensor recording, ``time`` from 0 at ``frame_rate_hz``.
    loadcell : xarray.DataArray
        1-D load-cell record, dim ``time`` in s on the load cell's own clock (first sample
        at 0), ``units="N"``, with Gaussian noise.
    load_N : numpy.ndarray
        True total load on the sensor at each frame.
    loadcell_true_N : numpy.ndarray
        Noise-free load at each load-cell sample.
    loadcell_start_offset_s : float
        Sensor time of the load cell's first sample: load-cell time ``t`` is sensor time
        ``t + loadcell_start_offset_s``.
    weights : numpy.ndarray
        ``(rows, cols)`` share of the load on each sensel (sums to 1): the force on sensel
        ``k`` at frame ``i`` is ``load_N[i] * weights[k]``.
    loads_N : numpy.ndarray
        Hold levels.
    hold_windows_s : numpy.ndarray
        ``(levels, 2)`` start and end of each hold in sensor time.
    """

    raw: xr.DataArray
    loadcell: xr.DataArray
    load_N: np.ndarray = field(repr=False)
    loadcell_true_N: np.ndarray = field(repr=False)
    loadcell_start_offset_s: float
    weights: np.ndarray = field(repr=False)
    loads_N: np.ndarray
    hold_windows_s: np.ndarray
    truth_sensor: dict = field(default_factory=dict, repr=False)

    def loadcell_csv(self):
        """Return the load-cell record as CSV text with header ``Time (s),Load (N)``."""
        table = np.column_stack([self.loadcell["time"].values, self.loadcell.values])
        body = "\n".join(f"{t:.6f},{f:.6f}" for t, f in table)
        return f"Time (s),Load (N)\n{body}\n"

    def truth(self):
        """Return the truth as plain values (sensor law, offset, hold levels and windows)."""
        return {"kind": "ramp-and-hold session (Gillis 2013, 5.3.2)",
                "loadcell_start_offset_s": self.loadcell_start_offset_s,
                "loadcell_clock": "load-cell time t is sensor time t + loadcell_start_offset_s",
                "loads_N": self.loads_N, "hold_windows_s": self.hold_windows_s,
                "sensor": self.truth_sensor}

    def write(self, outdir, *, overwrite=False):
        """Write ``recording.csv`` (I-Scan ASCII), ``loadcell.csv`` and ``truth.json``.

        Parameters
        ----------
        outdir : str or os.PathLike
            Folder, created if missing. Every file is written atomically.
        overwrite : bool, keyword-only
            Write into a folder that holds files: only an earlier session's.

        Returns
        -------
        dict
            Paths written, by role (``recording``, ``loadcell``, ``truth``).
        """
        from tactilecal.io import write_tekscan

        return write_session(outdir, {
            "recording": ("recording.csv", partial(write_tekscan, self.raw, overwrite=True)),
            "loadcell": ("loadcell.csv",
                         lambda path: write_text_atomic(path, self.loadcell_csv()))},
            self.truth(), overwrite=overwrite)


def ramp_hold_profile(loads_N, *, hold_s=3.0, ramp_s=2.0, lead_s=1.0):
    """Return the knots ``(time_s, load_N)`` of a ramp-and-hold loading sequence.

    Gillis (2013), 5.3.2: constant loads (50, 100, 150, 200 lbf) each held ``hold_s`` with
    ``ramp_s`` linear transitions; here the sequence starts at zero after ``lead_s``, steps
    through the levels and ramps back to zero, followed by ``lead_s`` of zero load.

    Examples
    --------
    >>> t, f = ramp_hold_profile([10.0, 20.0], hold_s=1.0, ramp_s=0.5, lead_s=0.0)
    >>> t.tolist(), f.tolist()
    ([0.0, 0.5, 1.5, 2.0, 3.0, 3.5], [0.0, 10.0, 10.0, 20.0, 20.0, 0.0])
    """
    loads = np.asarray(loads_N, dtype=np.float64)
    steps = np.r_[0.0, lead_s, np.tile([ramp_s, hold_s], loads.size), ramp_s, lead_s]
    times = np.cumsum(steps)
    levels = np.r_[0.0, 0.0, np.repeat(loads, 2), 0.0, 0.0]
    keep = np.r_[True, np.diff(times) > 0]
    return times[keep], levels[keep]


def ramp_hold(sensor, *, loads_N=(222.4, 444.8, 667.2, 889.6), hold_s=3.0, ramp_s=2.0,
              frame_rate_hz=100.0, loadcell_rate_hz=500.0, loadcell_start_offset_s=0.37,
              pad_fraction=0.5, lead_s=1.0, loadcell_noise_N=0.5, platen_unevenness=0.05,
              seed=0):
    """Simulate a loading-machine ramp-and-hold session with its load-cell record.

    A rigid platen covering the central ``pad_fraction`` of the sensor area presses with the
    load sequence of :func:`ramp_hold_profile` (default Gillis 2013, 5.3.2: 50, 100, 150,
    200 lbf held 3 s with 2 s linear transitions). The platen's share of the load per sensel
    is uniform within ``platen_unevenness`` (smooth relative variation); the sensor reads
    ``load(t) * weight`` through its law at ``frame_rate_hz``. The load cell samples the same
    load at ``loadcell_rate_hz`` on its own clock, starting ``loadcell_start_offset_s`` after
    the sensor, with Gaussian noise of ``loadcell_noise_N``: what movie calibration consumes.

    Parameters
    ----------
    sensor : SimulatedSensor
        From :func:`make_sensor`.
    loads_N : sequence of float
        Hold levels in N (default 50, 100, 150, 200 lbf).
    hold_s, ramp_s, lead_s : float
        Hold and transition durations, and zero-load time before and after the sequence.
    frame_rate_hz, loadcell_rate_hz : float
        Sampling rates of sensor and load cell.
    loadcell_start_offset_s : float
        Delay of the load cell's first sample after the sensor's first frame (>= 0).
    pad_fraction : float
        Share of the sensor area under the platen (centred square-ish block of sensels).
    loadcell_noise_N, platen_unevenness : float
        Load-cell noise standard deviation and relative unevenness of the platen load.
    seed : int
        Seed of the platen unevenness, sensor noise and load-cell noise.

    Returns
    -------
    RampHold

    Raises
    ------
    ValueError
        For non-positive durations or rates, negative loads or offset, or ``pad_fraction``
        outside (0, 1].

    Notes
    -----
    Sensor readings are computed in float32 blocks of about a million values and stored in a
    float64 array (the data model): a 44 x 44 x 100,000-frame session needs about 1.6 GB.
    The sensor has no creep, hysteresis or frequency dependence here.

    References
    ----------
    K. Gillis (2013), MS thesis, University of Colorado, section 5.3.2.

    Examples
    --------
    >>> from tactilecal.simulate import make_sensor
    >>> rh = ramp_hold(make_sensor("5051"), seed=1)
    >>> rh.raw.sizes["frame"], rh.loadcell.attrs["units"], float(rh.load_N.max())
    (2400, 'N', 889.6)
    """
    _check_sensor(sensor)
    _check_ramp_args(loads_N, hold_s, ramp_s, lead_s, frame_rate_hz, loadcell_rate_hz,
                     loadcell_start_offset_s, pad_fraction, loadcell_noise_N, platen_unevenness)
    rng = np.random.default_rng(seed)
    knots_t, knots_f = ramp_hold_profile(loads_N, hold_s=hold_s, ramp_s=ramp_s, lead_s=lead_s)
    n_frames = int(np.floor(knots_t[-1] * frame_rate_hz + 1e-9))
    if n_frames < 2:
        raise TactilecalError(f"frame_rate_hz: {frame_rate_hz} Hz over the {knots_t[-1]:g} s "
                              f"sequence gives {n_frames} frames; expected at least 2")
    time = np.arange(n_frames) / frame_rate_hz
    load = np.interp(time, knots_t, knots_f)
    weights = _platen_weights(sensor, pad_fraction, platen_unevenness, rng)
    raw = _read_scaled(sensor, load, weights, rng)
    da = sensor.to_dataarray(raw, time, source="simulated ramp-and-hold")
    loadcell, lc_true = _loadcell(knots_t, knots_f, time[-1], loadcell_rate_hz,
                                  loadcell_start_offset_s, loadcell_noise_N, rng)
    starts = lead_s + ramp_s + np.arange(np.size(loads_N)) * (ramp_s + hold_s)
    return RampHold(da, loadcell, load, lc_true, float(loadcell_start_offset_s), weights,
                    np.asarray(loads_N, dtype=np.float64),
                    np.column_stack([starts, starts + hold_s]), sensor.truth())


def _check_sensor(sensor):
    if not isinstance(sensor, SimulatedSensor):
        raise TypeError(f"sensor: expected a SimulatedSensor; got {type(sensor).__name__}")


def _check_ramp_args(loads_N, hold_s, ramp_s, lead_s, frame_rate_hz, loadcell_rate_hz,
                     offset_s, pad_fraction, noise_N, unevenness):
    loads = np.atleast_1d(np.asarray(loads_N, dtype=np.float64))
    if loads.ndim != 1 or loads.size == 0 or not np.all(np.isfinite(loads) & (loads >= 0)):
        raise TactilecalError(f"loads_N: got {loads_N!r}; expected one or more non-negative loads")
    for name, value in (("hold_s", hold_s), ("ramp_s", ramp_s),
                        ("frame_rate_hz", frame_rate_hz), ("loadcell_rate_hz", loadcell_rate_hz)):
        if not (np.isfinite(value) and value > 0):
            raise TactilecalError(f"{name}: got {value!r}; expected a positive number")
    for name, value in (("lead_s", lead_s), ("loadcell_start_offset_s", offset_s),
                        ("loadcell_noise_N", noise_N), ("platen_unevenness", unevenness)):
        if not (np.isfinite(value) and value >= 0):
            raise TactilecalError(f"{name}: got {value!r}; expected a non-negative number")
    if not 0 < pad_fraction <= 1:
        raise TactilecalError(f"pad_fraction: got {pad_fraction!r}; expected a share in (0, 1]")


def _platen_weights(sensor, pad_fraction, unevenness, rng):
    """Return the share of the load per sensel under a centred platen (sums to 1)."""
    side = np.sqrt(pad_fraction)
    nr = max(int(round(side * sensor.rows)), 1)
    nc = max(int(round(pad_fraction * sensor.rows * sensor.cols / nr)), 1)
    nc = min(nc, sensor.cols)
    r0, c0 = (sensor.rows - nr) // 2, (sensor.cols - nc) // 2
    weights = np.zeros(sensor.shape)
    block = 1.0 + smooth_field(rng, (nr, nc), 2.0, unevenness)
    weights[r0:r0 + nr, c0:c0 + nc] = np.maximum(block, 0.0)
    return weights / weights.sum()


def _read_scaled(sensor, load_N, weights, rng):
    """Digitise ``load_N[i] * weights`` for every frame, in float32 blocks of frames."""
    per_sensel = (sensor.gain * (weights / sensor.A_N) ** (1.0 / sensor.b)).astype(np.float32)
    per_frame = (np.maximum(load_N, 0.0) ** (1.0 / sensor.b)).astype(np.float32)
    out = np.empty((load_N.size, *sensor.shape))
    step = max(_CHUNK_VALUES // per_sensel.size, 1)
    block = np.empty((step, *sensor.shape), dtype=np.float32)
    scratch = np.empty_like(block)
    for start in range(0, load_N.size, step):
        m = min(step, load_N.size - start)
        np.multiply(per_frame[start:start + m, None, None], per_sensel, out=block[:m])
        out[start:start + m] = sensor._digitise(block[:m], rng, scratch[:m])
    return out


def _loadcell(knots_t, knots_f, end_s, rate_hz, offset_s, noise_N, rng):
    """Return the load-cell DataArray (own clock from 0) and its noise-free values."""
    n = int(np.floor((end_s - offset_s) * rate_hz + 1e-9)) + 1
    if n < 2:
        raise TactilecalError(f"loadcell_start_offset_s: {offset_s} s leaves no load-cell record "
                              f"before the sensor recording ends at {end_s} s")
    t_own = np.arange(n) / rate_hz
    true = np.interp(t_own + offset_s, knots_t, knots_f)
    noisy = true + rng.normal(0.0, noise_N, size=n) if noise_N > 0 else true.copy()
    da = xr.DataArray(noisy, dims=("time",), coords={"time": t_own},
                      attrs={"units": "N", "source": "simulated load cell",
                             "column": "Load (N)", "time_column": "Time (s)"})
    return da, true
