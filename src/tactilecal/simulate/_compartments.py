"""A recording of separated contacts with their truth: the two compartments of a knee."""

from typing import NamedTuple

import numpy as np
import xarray as xr

from tactilecal._errors import TactilecalError
from tactilecal._units import KPA_MM2_TO_N
from tactilecal.simulate._sensor import sensor_geometry

__all__ = ["CompartmentRecording", "compartment_recording"]


class CompartmentRecording(NamedTuple):
    """A calibrated recording of two or more contacts and its truth.

    Attributes
    ----------
    recording : xarray.DataArray
        ``(frames, rows, cols)`` pressure in kPa, data model; NaN on the blank strip
        between the pads (as the outline of a Tekscan knee sensor).
    force_N : numpy.ndarray
        ``(frames, contacts)`` force of each contact: the sum of its sensels' pressure
        times the sensel area.
    contact_sensels : numpy.ndarray
        ``(contacts, rows, cols)`` bool, the sensels each contact ever loads.
    pads : numpy.ndarray
        ``(contacts, rows, cols)`` bool, the sensor pad of each contact.
    centre_mm : numpy.ndarray
        ``(frames, contacts, 2)`` force-weighted centre (row, col) of each contact in mm
        from sensel (0, 0), NaN where it carries no force.
    """

    recording: xr.DataArray
    force_N: np.ndarray
    contact_sensels: np.ndarray
    pads: np.ndarray
    centre_mm: np.ndarray


def compartment_recording(*, model="4010N", n_frames=150, frame_rate_hz=100.0,
                          peak_N=(800.0, 500.0), radius_mm=(10.0, 8.0), travel_mm=8.0,
                          gap_cols=4, seed=0):
    """Simulate a loading of the two compartments of a knee sensor (or any two pads).

    The sensor is split into a left and a right pad by ``gap_cols`` blank (NaN) columns in
    its middle, as the Tekscan 4010N's outline splits the medial and lateral condyles. On
    each pad a Hertzian contact ``p = p0 sqrt(1 - (r / a)**2)`` of radius ``a`` carries a
    stance-like load (two humps, ``peak_N`` at most) while its centre travels ``travel_mm``
    along the rows; the pressure of each sensel is ``p`` at its centre.

    Parameters
    ----------
    model : str or tuple
        Sensor geometry (:func:`tactilecal.simulate.make_sensor`'s ``model``); default the
        4010N (22 x 34 sensels, 2 mm).
    n_frames : int
        Frames over one loading.
    frame_rate_hz : float
        Frame rate.
    peak_N : tuple of float
        Largest nominal force of the left and right contact (the Hertz force
        ``2/3 pi a^2 p0``; the truth is the sum over sensels, see ``force_N``).
    radius_mm : tuple of float
        Contact radius of each.
    travel_mm : float
        Distance each centre moves along the rows over the loading.
    gap_cols : int
        Blank columns between the pads.
    seed : int
        Seed of the small random offsets of the contact centres.

    Returns
    -------
    CompartmentRecording

    Raises
    ------
    TactilecalError
        If a contact does not fit on its pad, or the arguments are out of range.

    Examples
    --------
    >>> sim = compartment_recording(n_frames=20)
    >>> sim.recording.shape, sim.force_N.shape, sim.contact_sensels.shape
    ((20, 22, 34), (20, 2), (2, 22, 34))
    """
    name, rows, cols, row_mm, col_mm, area = sensor_geometry(model)
    if not (int(n_frames) == n_frames >= 3 and frame_rate_hz > 0 and 0 <= gap_cols < cols - 4
            and len(peak_N) == len(radius_mm) == 2):
        raise TactilecalError(f"n_frames={n_frames!r}, frame_rate_hz={frame_rate_hz!r}, "
                              f"gap_cols={gap_cols!r}, peak_N={peak_N!r}, radius_mm="
                              f"{radius_mm!r}; expected >= 3 frames, a positive rate, a gap "
                              "narrower than the sensor and two contacts")
    rng = np.random.default_rng(seed)
    first_gap = (cols - gap_cols) // 2
    col_index = np.arange(cols)
    pads = np.stack([np.broadcast_to(col_index < first_gap, (rows, cols)),
                     np.broadcast_to(col_index >= first_gap + gap_cols, (rows, cols))])
    t = np.arange(n_frames) / frame_rate_hz
    phase = np.linspace(0.0, 1.0, n_frames)
    shape = np.sin(np.pi * phase) + 0.4 * np.sin(3 * np.pi * phase)  # two humps, a dip
    shape = np.clip(shape / shape.max(), 0.0, None)
    r_mm, c_mm = np.meshgrid(np.arange(rows) * row_mm, np.arange(cols) * col_mm, indexing="ij")
    pressure = np.zeros((n_frames, rows, cols))
    for k, (pad, peak, a) in enumerate(zip(pads, peak_N, radius_mm, strict=True)):
        pad_cols = np.flatnonzero(pad[0])
        centre_col = (pad_cols.mean() + rng.uniform(-0.5, 0.5)) * col_mm
        centre_row = ((rows - 1) / 2 + rng.uniform(-0.5, 0.5)) * row_mm
        half_pad = (pad_cols.size / 2 - 0.5) * col_mm
        if a + 1e-9 > half_pad or a + travel_mm / 2 > (rows - 1) / 2 * row_mm:
            raise TactilecalError(f"radius_mm {a!r} (travel {travel_mm!r} mm) does not fit on a "
                                  f"pad of {pad_cols.size} x {rows} sensels of {name}; expected "
                                  "a smaller contact")
        p0 = peak * shape / (2.0 / 3.0 * np.pi * a * a) / KPA_MM2_TO_N
        rows_t = centre_row + travel_mm * (phase - 0.5) * (1 if k == 0 else -1)
        dist2 = (r_mm[None] - rows_t[:, None, None]) ** 2 + (c_mm[None] - centre_col) ** 2
        hertz = p0[:, None, None] * np.sqrt(np.clip(1.0 - dist2 / (a * a), 0.0, None))
        pressure += np.where(pad[None], hertz, 0.0)
    pressure[:, ~pads.any(axis=0)] = np.nan
    return _result(pressure, pads, t, name, row_mm, col_mm, area)


def _result(pressure, pads, t, name, row_mm, col_mm, area):
    filled = np.nan_to_num(pressure)
    force = np.stack([(filled * pad).sum(axis=(1, 2)) for pad in pads], axis=1) * area \
        * KPA_MM2_TO_N
    rows, cols = pressure.shape[1:]
    r, c = np.meshgrid(np.arange(rows) * row_mm, np.arange(cols) * col_mm, indexing="ij")
    with np.errstate(invalid="ignore", divide="ignore"):
        centre = np.stack([np.stack([(filled * pad * r).sum(axis=(1, 2)),
                                     (filled * pad * c).sum(axis=(1, 2))], axis=1)
                           / (filled * pad).sum(axis=(1, 2))[:, None] for pad in pads], axis=1)
    sensels = np.stack([((filled > 0) & pad).any(axis=0) for pad in pads])
    n = len(t)
    recording = xr.DataArray(
        pressure, dims=("frame", "row", "col"),
        coords={"frame": np.arange(1, n + 1), "time": ("frame", t),
                "row": np.arange(rows), "col": np.arange(cols)},
        attrs={"units": "kPa", "sensor_type": name, "row_spacing_mm": row_mm,
               "col_spacing_mm": col_mm, "sensel_area_mm2": area,
               "seconds_per_frame": float(t[1] - t[0]), "source": "simulated compartments"})
    return CompartmentRecording(recording, force, sensels, pads, centre)
