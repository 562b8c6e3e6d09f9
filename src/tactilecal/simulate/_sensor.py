"""Simulated matrix piezoresistive sensor with a known per-sensel power law.

The truth is the manufacturer's per-sensel law of Zvyagin (2022), eq. 1: a sensel reading
``X`` (0..255) carries the force ``f = A * X**b`` newtons. The simulator inverts it, adds a
per-sensel gain, Gaussian read noise, rounding, the noise threshold, saturation and dead
sensels, so every synthetic recording comes with the numbers it was made from.
"""

from dataclasses import dataclass, field

import numpy as np
import xarray as xr

from tactilecal._errors import TactilecalError
from tactilecal._units import KPA_MM2_TO_N
from tactilecal.sensors import get_sensor

__all__ = ["SimulatedSensor", "make_sensor", "sensor_geometry"]

SATURATION_RAW = 255
"""Largest 8-bit reading; a sensel at or above it reads 255 (saturated)."""

def _as_rng(rng):
    """Return ``rng`` as a :class:`numpy.random.Generator` (seeds and generators accepted)."""
    if isinstance(rng, np.random.Generator):
        return rng
    return np.random.default_rng(rng)


def sensor_geometry(model):
    """Return ``(name, rows, cols, row_spacing_mm, col_spacing_mm, sensel_area_mm2)``.

    Parameters
    ----------
    model : str, tuple or object
        A catalogue name for :func:`tactilecal.sensors.get_sensor` (``"5051"``,
        ``"9500"``...), a custom ``(rows, cols, spacing_mm)`` tuple, or any object with
        ``rows``, ``cols``, ``row_spacing_mm``, ``col_spacing_mm`` (and optionally
        ``name``, ``sensel_area_mm2``) such as a :class:`tactilecal.sensors.SensorModel`.

    Returns
    -------
    tuple
        Name, rows, columns, spacings in mm and sensel area in mm2.

    Raises
    ------
    ValueError
        If ``model`` is unknown or the tuple is not ``(rows, cols, spacing_mm)`` with
        positive values.

    Examples
    --------
    >>> sensor_geometry("5051")[:4]
    ('5051', 44, 44, 1.27)
    >>> sensor_geometry((4, 6, 2.0))
    ('custom', 4, 6, 2.0, 2.0, 4.0)
    """
    if isinstance(model, tuple | list):
        return _custom_geometry(model)
    if isinstance(model, str | int):
        model = get_sensor(str(model))
    try:
        rows, cols = int(model.rows), int(model.cols)
        dr, dc = float(model.row_spacing_mm), float(model.col_spacing_mm)
    except AttributeError:
        raise TactilecalError(f"model: expected a sensor name, (rows, cols, spacing_mm) or a "
                              f"sensor object; got {model!r}") from None
    area = float(getattr(model, "sensel_area_mm2", dr * dc))
    return str(getattr(model, "name", "custom")), rows, cols, dr, dc, area


def _custom_geometry(spec):
    """Validate a custom ``(rows, cols, spacing_mm)`` sensor; return the geometry tuple."""
    if len(spec) != 3:
        raise TactilecalError(f"model: a custom sensor is (rows, cols, spacing_mm); got {spec!r}")
    rows, cols, pitch = spec
    if not (int(rows) == rows >= 1 and int(cols) == cols >= 1 and float(pitch) > 0):
        raise TactilecalError(f"model: a custom sensor needs positive integer rows, cols and a "
                              f"positive spacing_mm; got {spec!r}")
    pitch = float(pitch)
    return "custom", int(rows), int(cols), pitch, pitch, pitch * pitch


@dataclass(eq=False)
class SimulatedSensor:
    """A synthetic 8-bit sensel matrix whose calibration truth is known.

    Each sensel ``k`` follows the power law of Zvyagin (2022), eq. 1, scaled by its own gain:
    an ideal sensel carrying the force ``f_k`` newtons reads ``(f_k / A_N) ** (1 / b)``; the
    simulated sensel reads ``gain[k]`` times that, plus Gaussian read noise of standard
    deviation ``read_noise`` (raw units), rounded to an integer, set to 0 at or below
    ``noise_threshold`` (as Tekscan software does: the real I-Scan export with
    ``NOISE_THRESHOLD 3`` has no reading 3), clipped at 255 (saturation), and always 0
    where ``dead``.

    Attributes
    ----------
    sensor_type : str
        Model name written to ``attrs["sensor_type"]``.
    rows, cols : int
        Sensel grid.
    row_spacing_mm, col_spacing_mm, sensel_area_mm2 : float
        Geometry, as in the data model.
    A_N : float
        Force per sensel at a reading of 1, in N (Zvyagin's ``A``).
    b : float
        Exponent of the law (Zvyagin's ``b``).
    gain : numpy.ndarray
        ``(rows, cols)`` multiplicative gain on each sensel's reading (lognormal, median 1).
    dead : numpy.ndarray
        ``(rows, cols)`` bool, non-working sensels (read 0 whatever the load).
    read_noise : float
        Standard deviation of the read noise in raw units.
    noise_threshold : int
        Readings at or below it are reported as 0. Default 2: the smallest non-zero reading
        is then 3, as in Zvyagin's (2022) sessions.
    seconds_per_frame : float
        Nominal frame period in s used when no time is given (200 Hz as in Zvyagin 2022).
    curvature : float
        Log-log curvature of the response, 0 for the pure power law: the reading ``r0`` of
        eq. 1 becomes ``r0 * exp(curvature * ln(r0 / 32)**2)``, a response no single power
        law describes (to test how each method degrades under misspecification).
    b_sensel : numpy.ndarray or None
        ``(rows, cols)`` exponent of each sensel when the exponents spread around ``b``
        (None: every sensel follows ``b``); no single law is then exact.
    """

    sensor_type: str
    rows: int
    cols: int
    row_spacing_mm: float
    col_spacing_mm: float
    sensel_area_mm2: float
    A_N: float
    b: float
    gain: np.ndarray = field(repr=False)
    dead: np.ndarray = field(repr=False)
    read_noise: float = 0.5
    noise_threshold: int = 2
    seconds_per_frame: float = 0.005
    curvature: float = 0.0
    b_sensel: np.ndarray | None = field(default=None, repr=False)

    @property
    def shape(self):
        """``(rows, cols)``."""
        return (self.rows, self.cols)

    def ideal_raw(self, force_N):
        """Noise-free, unrounded reading of a unit-gain sensel: ``(f / A) ** (1 / b)``.

        Inverse of Zvyagin (2022) eq. 1 (times the ``curvature`` term when it is not 0).
        Negative forces count as 0.
        """
        force = np.maximum(np.asarray(force_N, dtype=np.float64), 0.0)
        raw = (force / self.A_N) ** (1.0 / (self.b if self.b_sensel is None else self.b_sensel))
        if self.curvature:
            log_ratio = np.log(np.where(raw > 0, raw, 32.0) / 32.0)
            raw = raw * np.exp(self.curvature * log_ratio ** 2)
        return raw

    def force_of_raw(self, raw):
        """Force per sensel in N of a unit-gain reading, ``A * raw ** b`` (Zvyagin eq. 1)."""
        return self.A_N * np.asarray(raw, dtype=np.float64) ** self.b

    def read(self, force_N, rng=None, *, sensitivity=None):
        """Return the readings of the true per-sensel forces ``force_N``.

        Parameters
        ----------
        force_N : array_like
            ``(..., rows, cols)`` true force on each sensel in N.
        rng : numpy.random.Generator or int, optional
            Source of the read noise (a seed is accepted). ``None`` draws fresh entropy, so
            pass a generator or seed for reproducible readings.
        sensitivity : array_like, optional
            Multiplier of each frame's readings before noise (one per frame along the first
            axis), e.g. a sensor whose sensitivity drifts or depends on its loading history.

        Returns
        -------
        numpy.ndarray
            Float64 readings 0..255, integer-valued, same shape as ``force_N``.

        Raises
        ------
        ValueError
            If the last two axes of ``force_N`` are not ``(rows, cols)``.

        Examples
        --------
        >>> s = make_sensor("9500", gain_spread=0, read_noise=0, n_dead=0)
        >>> f = np.full((14, 14), s.force_of_raw(100.0))
        >>> float(s.read(f)[0, 0])
        100.0
        """
        force = np.asarray(force_N, dtype=np.float64)
        if force.shape[-2:] != self.shape:
            raise TactilecalError(f"force_N: last two axes are {force.shape[-2:]}; expected "
                                  f"(rows, cols) = {self.shape}")
        raw = self.ideal_raw(force) * self.gain
        if sensitivity is not None:
            raw *= np.asarray(sensitivity, dtype=np.float64).reshape(
                (-1,) + (1,) * (raw.ndim - 1))
        return self._digitise(raw, _as_rng(rng))

    def _digitise(self, raw, rng, scratch=None):
        """Add noise, round, apply threshold, saturation and dead sensels (in place).

        ``scratch`` is an optional buffer like ``raw`` for the noise (reused by callers that
        digitise long recordings block by block).
        """
        if self.read_noise > 0:
            noise = rng.standard_normal(dtype=raw.dtype, out=scratch) if scratch is not None \
                else rng.standard_normal(size=raw.shape, dtype=raw.dtype)
            noise *= self.read_noise
            raw += noise
        np.rint(raw, out=raw)
        np.clip(raw, 0, SATURATION_RAW, out=raw)
        np.multiply(raw, raw > self.noise_threshold, out=raw)
        np.multiply(raw, ~self.dead, out=raw)
        return raw

    def truth(self):
        """Return the sensor's truth as plain values (law, noise, gains, dead sensels).

        Examples
        --------
        >>> t = make_sensor("9500", n_dead=2).truth()
        >>> t["A_N"], t["b"], len(t["dead_sensels"]), len(t["gain"])
        (0.0035, 1.16, 2, 14)
        """
        return {"sensor_type": self.sensor_type, "rows": self.rows, "cols": self.cols,
                "law": "force per sensel f = A_N * raw**b (Zvyagin 2022, eq. 1); "
                       "raw = gain * (f / A_N)**(1/b) + noise",
                "A_N": self.A_N, "b": self.b, "read_noise": self.read_noise,
                "noise_threshold": self.noise_threshold,
                "dead_sensels": np.argwhere(self.dead).tolist(), "gain": self.gain.tolist()}

    def attrs(self, *, source="simulated", seconds_per_frame=None):
        """Data-model attributes of a raw recording from this sensor."""
        spf = self.seconds_per_frame if seconds_per_frame is None else seconds_per_frame
        return {"sensor_type": self.sensor_type, "units": "raw",
                "row_spacing_mm": self.row_spacing_mm, "col_spacing_mm": self.col_spacing_mm,
                "sensel_area_mm2": self.sensel_area_mm2, "seconds_per_frame": float(spf),
                "noise_threshold": int(self.noise_threshold), "source": str(source)}

    def to_dataarray(self, raw, time_s=None, *, source="simulated"):
        """Wrap readings in the project's data model (``docs/data-model.md``).

        Parameters
        ----------
        raw : array_like
            ``(frames, rows, cols)`` or a single ``(rows, cols)`` frame.
        time_s : array_like, optional
            Time of each frame in s; default ``frame index * seconds_per_frame``.
        source : str
            Value of ``attrs["source"]``.

        Returns
        -------
        xarray.DataArray
            Float64, dims ``("frame", "row", "col")``, 1-based ``frame``, ``time`` in s,
            ``units="raw"`` and the sensor attributes.

        Raises
        ------
        ValueError
            If the shape does not match the sensor or ``time_s`` has the wrong length.

        Examples
        --------
        >>> s = make_sensor("9500")
        >>> da = s.to_dataarray(np.zeros((2, 14, 14)))
        >>> da.dims, da.attrs["units"], da["frame"].values.tolist()
        (('frame', 'row', 'col'), 'raw', [1, 2])
        """
        values = np.asarray(raw, dtype=np.float64)
        if values.ndim == 2:
            values = values[np.newaxis]
        if values.ndim != 3 or values.shape[1:] != self.shape:
            raise TactilecalError(f"raw: shape {values.shape}; expected (frames, {self.rows}, "
                                  f"{self.cols})")
        n = values.shape[0]
        spf = None
        if time_s is None:
            time = np.arange(n) * self.seconds_per_frame
        else:
            time = np.asarray(time_s, dtype=np.float64).reshape(-1)
            if time.size != n:
                raise TactilecalError(f"time_s: {time.size} values; expected one per frame ({n})")
            spf = float(np.median(np.diff(time))) if n > 1 else None
        coords = {"frame": np.arange(1, n + 1, dtype=np.int64), "time": ("frame", time),
                  "row": np.arange(self.rows, dtype=np.int64),
                  "col": np.arange(self.cols, dtype=np.int64)}
        return xr.DataArray(values, dims=("frame", "row", "col"), coords=coords,
                            attrs=self.attrs(source=source, seconds_per_frame=spf))


def make_sensor(model="5051", *, A_N=None, b=1.16, gain_spread=0.05, read_noise=0.5,
                n_dead=3, noise_threshold=2, seed=0, A_kPa=None):
    """Build a simulated sensor with a known power law, gains and dead sensels.

    Parameters
    ----------
    model : str, tuple or sensor object
        Catalogue name (``"5051"``, ``"9500"``...), custom ``(rows, cols, spacing_mm)`` or a
        :class:`tactilecal.sensors.SensorModel`.
    A_N : float
        Force per sensel at reading 1 in N (Zvyagin 2022 eq. 1; Table 2 gives A0 of
        0.0023 to 0.0041 N for the 5051). Default 0.0035 N, near Sensor1's 0.00358, unless
        ``A_kPa`` is given.
    A_kPa : float, optional
        The same law as a pressure at reading 1 in kPa, ``A_N = A_kPa * sensel_area_mm2 /
        1000``: sensors of different sensel sizes with the same ``A_kPa`` read the same raw
        value under the same pressure (the 5051's 0.0035 N on 1.6129 mm2 is 2.17 kPa).
        Give ``A_N`` or ``A_kPa``, not both.
    b : float
        Exponent of the law (Table 2: b0 1.12 to 1.24; default near Sensor1's 1.164).
    gain_spread : float
        Standard deviation of ``log(gain)``; gains are lognormal with median 1. 0 gives
        identical sensels.
    read_noise : float
        Standard deviation of the Gaussian read noise in raw units.
    n_dead : int
        Number of non-working sensels. They are drawn uniformly at random without
        replacement over the whole matrix (from ``seed``), so they may fall inside or outside
        a loaded patch, as in use.
    noise_threshold : int
        Readings at or below it are reported as 0, as Tekscan's ``NOISE_THRESHOLD`` (the real
        exports write 3). The default 2 leaves 3 as the smallest non-zero reading, as in
        Zvyagin's (2022) sessions, eq. 5.
    seed : int
        Seed of the gains and dead-sensel positions.

    Returns
    -------
    SimulatedSensor

    Raises
    ------
    ValueError
        For a non-positive ``A_N`` or ``b``, negative spreads or noise, or ``n_dead``
        outside ``0..rows*cols``.

    References
    ----------
    P. Zvyagin (2022), Tactile pressure sensors calibration with the use of high pressure
    zones, Sensors 22(19):7290, eq. 1 and Table 2.

    Examples
    --------
    >>> s = make_sensor("5051", seed=1)
    >>> s.rows, s.cols, int(s.dead.sum()), s.gain.shape
    (44, 44, 3, (44, 44))
    """
    name, rows, cols, dr, dc, area = sensor_geometry(model)
    if A_N is not None and A_kPa is not None:
        raise TactilecalError(f"A_N = {A_N!r} and A_kPa = {A_kPa!r}; expected one of them")
    if A_kPa is not None:
        _check_positive(A_kPa=A_kPa)
        A_N = A_kPa * area * KPA_MM2_TO_N
    A_N = 0.0035 if A_N is None else A_N
    _check_positive(A_N=A_N, b=b)
    _check_non_negative(gain_spread=gain_spread, read_noise=read_noise,
                        noise_threshold=noise_threshold)
    if not (int(n_dead) == n_dead and 0 <= n_dead <= rows * cols):
        raise TactilecalError(f"n_dead: got {n_dead!r}; expected an integer in 0..{rows * cols}")
    rng = np.random.default_rng(seed)
    gain = np.exp(rng.normal(0.0, gain_spread, size=(rows, cols))) if gain_spread else \
        np.ones((rows, cols))
    dead = np.zeros(rows * cols, dtype=bool)
    dead[rng.choice(rows * cols, size=int(n_dead), replace=False)] = True
    return SimulatedSensor(name, rows, cols, dr, dc, area, float(A_N), float(b), gain,
                           dead.reshape(rows, cols), float(read_noise), int(noise_threshold))


def _check_positive(**values):
    for name, value in values.items():
        if not (np.isfinite(value) and value > 0):
            raise TactilecalError(f"{name}: got {value!r}; expected a positive number")


def _check_non_negative(**values):
    for name, value in values.items():
        if not (np.isfinite(value) and value >= 0):
            raise TactilecalError(f"{name}: got {value!r}; expected a non-negative number")
