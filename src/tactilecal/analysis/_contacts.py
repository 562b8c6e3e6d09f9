"""Regions of a recording: separated contact areas found automatically, and per-region numbers.

:func:`split_contacts` finds the separated contact areas of a recording (two knee
compartments, two feet, a heel and a forefoot far apart) and returns them as
:class:`~tactilecal.analysis._regionset.Regions` that cover the whole sensor, so their
forces add up to the total. :func:`region_analysis` gives force, contact area, peak and
mean pressure and centre of force of every region in every frame, and per region its
peak force, impulse and pressure-time integral.
"""

import math
from dataclasses import dataclass

import numpy as np
import pandas as pd
import xarray as xr

from tactilecal._contact import DEFAULT_GAP_MM
from tactilecal._errors import TactilecalError
from tactilecal._model import check_recording, recording_name
from tactilecal.analysis._gait import (
    pressure_time_integral,
    time_integral,
    time_s,
)
from tactilecal.analysis._regionset import Regions
from tactilecal.analysis._units import pressure_map_kPa, spacing_mm

__all__ = ["DEFAULT_MIN_SHARE", "split_contacts", "RegionAnalysis", "region_analysis",
           "as_regions"]

DEFAULT_MIN_SHARE = 0.05
"""A loaded area carrying less than this share of the recording's load (its
pressure-time integral) is no contact of its own: it joins the nearest contact."""


def _load_map(recording, calibration):
    """Each sensel's load summed over frames (pressure-time proxy), and the blank sensels.

    A raw recording without a calibration is weighed by its raw readings (loaded = raw > 0).
    """
    _, kind = check_recording(recording)
    values = recording if kind == "raw" and calibration is None else \
        pressure_map_kPa(recording, calibration=calibration)
    stack = np.asarray(values.values, dtype=float)
    blank = np.isnan(stack).all(axis=0)
    return np.nansum(np.clip(stack, 0, None), axis=0), blank


def _joined(loaded, inside, gap_mm, spacing):
    """Label the contacts: loaded areas joined across unloaded gaps of up to ``gap_mm``.

    Each area grows by ``floor(gap / spacing / 2)`` sensels per axis, through sensor
    sensels only (never across blank ones), so a gap of up to ``gap_mm`` (rounded down to an
    even number of sensels) closes and the areas touch.
    """
    from scipy import ndimage

    steps = [int(math.floor(gap_mm / s / 2)) for s in spacing]
    grown = loaded.copy()
    for k in range(max(steps)):
        structure = np.zeros((3, 3), dtype=bool)
        structure[1, 1] = True
        structure[:, 1] |= k < steps[0]
        structure[1, :] |= k < steps[1]
        if k < steps[0] and k < steps[1]:
            structure[:] = True
        grown = ndimage.binary_dilation(grown, structure=structure, mask=inside | loaded)
    labels, n = ndimage.label(grown, structure=np.ones((3, 3), dtype=bool))
    return np.where(loaded, labels, 0), n


def split_contacts(recording, *, gap_mm=None, min_share=DEFAULT_MIN_SHARE,
                   calibration=None):
    """Find the separated contact areas of a recording, as regions covering the sensor.

    Parameters
    ----------
    recording : xarray.DataArray
        Recording in the data model; a raw one without ``calibration`` is weighed by its raw
        readings.
    gap_mm : float, optional
        Loaded areas separated by an unloaded gap of up to this width (rounded down to an
        even number of sensels) are one contact; never joined across blank sensels.
        Default (None) :data:`DEFAULT_GAP_MM`, 20 mm.
    min_share : float, default :data:`DEFAULT_MIN_SHARE` (5 %)
        An area carrying less of the recording's load joins the nearest contact.
    calibration : CalibrationResult or path, optional
        Applied to a raw recording.

    Returns
    -------
    Regions
        ``contact 1``, ``contact 2``, ... ordered by the column of their load centre (left
        to right across the map), then by row. Every sensel belongs to the contact of the
        nearest loaded sensel of a contact (in mm), so the regions cover the sensor and
        their forces add up to the total in every frame.

    Raises
    ------
    TactilecalError
        If nothing is ever loaded, or ``gap_mm``/``min_share`` are out of range.

    Notes
    -----
    The ever-loaded map (every sensel that reads above 0 in some frame) is split into
    connected areas (8-neighbourhood) after closing gaps narrower than ``gap_mm``; each
    area's load is its summed pressure over all frames. Areas with at least ``min_share`` of
    the total load are the contacts; the rest, and every unloaded sensel, go to the nearest
    contact sensel (Euclidean distance in mm, :func:`scipy.ndimage.distance_transform_edt`).

    Examples
    --------
    >>> import numpy as np, xarray as xr
    >>> p = np.zeros((2, 3, 7)); p[:, 1, 0:2] = 50.0; p[:, 1, 5:7] = 80.0
    >>> rec = xr.DataArray(p, dims=("frame", "row", "col"),
    ...                    attrs={"units": "kPa", "row_spacing_mm": 2.0, "col_spacing_mm": 2.0})
    >>> regions = split_contacts(rec, gap_mm=4.0)
    >>> regions.names, regions.labels()[1].tolist()
    (['contact 1', 'contact 2'], [1, 1, 1, 1, 2, 2, 2])
    """
    from scipy import ndimage

    gap_mm = DEFAULT_GAP_MM if gap_mm is None else gap_mm
    if not (np.isfinite(gap_mm) and gap_mm >= 0):
        raise TactilecalError(f"gap_mm is {gap_mm!r}; expected a width >= 0 in mm")
    if not (0 <= min_share < 1):
        raise TactilecalError(f"min_share is {min_share!r}; expected a share in 0..1 (e.g. "
                              "0.05)")
    load, blank = _load_map(recording, calibration)
    loaded = load > 0
    if not loaded.any():
        raise TactilecalError(f"{recording_name(recording)}: no sensel is ever loaded; expected "
                              "a recording with contact to split")
    spacing = spacing_mm(recording)
    labels, n = _joined(loaded, ~blank, gap_mm, spacing)
    shares = ndimage.sum_labels(load, labels, np.arange(1, n + 1)) / load.sum()
    major = [k + 1 for k in np.argsort(-shares) if shares[k] >= min_share] or \
        [int(np.argmax(shares)) + 1]
    centres = [ndimage.center_of_mass(load, labels, k) for k in major]
    major = [k for _, k in sorted(zip([(c[1], c[0]) for c in centres], major, strict=True))]
    seeds = np.zeros(labels.shape, dtype=int)
    for i, k in enumerate(major, 1):
        seeds[labels == k] = i
    _, (rows, cols) = ndimage.distance_transform_edt(seeds == 0, sampling=spacing,
                                                     return_indices=True)
    nearest = seeds[rows, cols]
    how = f"split_contacts (gap {gap_mm:g} mm, min share {min_share:g})"
    return Regions({f"contact {i}": nearest == i for i in range(1, len(major) + 1)},
                   how={f"contact {i}": how for i in range(1, len(major) + 1)})


def as_regions(regions, recording, *, gap_mm=None):
    """Return ``regions`` as :class:`Regions`: given as Regions or ``{name: spec}``.

    ``"contacts"`` means :func:`split_contacts` (with ``gap_mm``).
    """
    if isinstance(regions, Regions):
        found = regions
    elif isinstance(regions, str) and regions == "contacts":
        found = split_contacts(recording, gap_mm=gap_mm)
    elif isinstance(regions, dict):
        found = Regions.from_specs(regions, shape=(recording.sizes["row"],
                                                   recording.sizes["col"]))
    else:
        raise TactilecalError(f"regions of type {type(regions).__name__}; expected Regions, "
                              "a dict {name: box, polygon or mask} or 'contacts'")
    shape = (recording.sizes["row"], recording.sizes["col"])
    if found.shape != shape:
        raise TactilecalError(f"regions are for a {found.shape[0]} x {found.shape[1]} sensor; "
                              f"{recording_name(recording)} has {shape[0]} x {shape[1]} sensels")
    return found


@dataclass
class RegionAnalysis:
    """Per-region numbers of a recording.

    Attributes
    ----------
    regions : Regions
        The regions analysed.
    summary : xarray.Dataset
        Dims ``("region", "frame")``: ``force_N``, ``contact_area_mm2``, ``cof_row_mm``,
        ``cof_col_mm``, ``peak_kPa``, ``mean_kPa`` (and ``saturated_sensels`` when the
        recording says what saturation is), as ``rec.tactile.frame_summary()`` of each
        region.
    table : pandas.DataFrame
        One row per region: ``region``, ``sensels``, ``peak_force_N``,
        ``peak_force_time_s``, ``impulse_N_s`` (force-time integral), ``max_contact_area_mm2``,
        ``peak_pressure_kPa``, ``pti_peak_kPa_s`` (peak pressure integrated over time),
        ``pti_max_sensel_kPa_s`` (largest pressure-time integral of one sensel),
        ``mean_cof_row_mm``, ``mean_cof_col_mm`` (force-weighted over frames),
        ``share_of_impulse``.
    pti_map : xarray.DataArray
        Each sensel's pressure-time integral [kPa s].
    """

    regions: Regions
    summary: xr.Dataset
    table: pd.DataFrame
    pti_map: xr.DataArray

    def plot_force_time(self, *, ax=None):
        """Force of every region against time (and their sum when they cover the sensor)."""
        from tactilecal.analysis._plots import plot_region_forces

        return plot_region_forces(self, ax=ax)

    def plot_centres(self, recording, *, ax=None, units=None, min_force_N=None):
        """Each region's centre-of-force path over the recording's peak-pressure map."""
        from tactilecal.analysis._plots import plot_region_centres

        return plot_region_centres(self, recording, ax=ax, units=units,
                                   min_force_N=min_force_N)


def region_analysis(recording, regions="contacts", *, threshold_kPa=0.0, calibration=None,
                    cof_min_force_N=0.0, gap_mm=None):
    """Force, area, pressures and centre of force of every region, frame by frame.

    Parameters
    ----------
    recording : xarray.DataArray
        Recording in the data model (raw needs ``calibration``).
    regions : Regions, dict or "contacts", default "contacts"
        The regions: :class:`Regions`, ``{name: spec}`` (a box, polygon or mask, see
        :meth:`Regions.from_specs`) or ``"contacts"`` (:func:`split_contacts`).
    threshold_kPa : float, default 0
        Loaded-sensel threshold for contact area and mean pressure.
    calibration : CalibrationResult or path, optional
        Applied to a raw recording (once).
    cof_min_force_N : float, default 0
        A region's centre of force is NaN in frames where its force is not above this.
    gap_mm : float, optional
        For ``regions="contacts"``: see :func:`split_contacts` (None: its default).

    Returns
    -------
    RegionAnalysis

    Notes
    -----
    Each region is analysed as the recording with NaN outside it (``select_region``), so
    its numbers are those of ``frame_summary``; regions that cover the sensor without
    overlapping (:meth:`Regions.is_partition`, as :func:`split_contacts` makes) have forces
    that add up to the total force in every frame, to rounding.

    Examples
    --------
    >>> import numpy as np, xarray as xr
    >>> p = np.zeros((2, 1, 4)); p[:, 0, 0] = 100.0; p[:, 0, 3] = 300.0
    >>> rec = xr.DataArray(p, dims=("frame", "row", "col"),
    ...                    coords={"time": ("frame", [0.0, 1.0])},
    ...                    attrs={"units": "kPa", "sensel_area_mm2": 10.0,
    ...                           "row_spacing_mm": 1.0, "col_spacing_mm": 1.0})
    >>> out = region_analysis(rec, {"a": (0, 1, 0, 2), "b": (0, 1, 2, 4)})
    >>> out.table[["region", "peak_force_N", "impulse_N_s"]].values.tolist()
    [['a', 1.0, 1.0], ['b', 3.0, 3.0]]
    """
    from tactilecal.analysis._maps import summary

    pressure = pressure_map_kPa(recording, calibration=calibration)
    regions = as_regions(regions, pressure, gap_mm=gap_mm)
    t = time_s(pressure)
    pti = pressure_time_integral(pressure)
    per_region = []
    for name, mask in regions.items():
        plane = xr.DataArray(mask, dims=("row", "col"))
        s = summary(pressure.where(plane), threshold_kPa=threshold_kPa,
                    cof_min_force_N=cof_min_force_N)
        per_region.append(s.expand_dims(region=[name]))
    ds = xr.concat(per_region, dim="region", combine_attrs="override").compute()
    return RegionAnalysis(regions, ds, _region_table(ds, regions, pti, t), pti)


def _region_table(ds, regions, pti, t):
    rows = []
    impulses = [float(time_integral(ds["force_N"].sel(region=n), t)) for n in regions]
    total = float(np.nansum(impulses))
    for name, impulse in zip(regions, impulses, strict=True):
        one = ds.sel(region=name)
        force = np.asarray(one["force_N"].values, dtype=float)
        i = int(np.nanargmax(force)) if np.isfinite(force).any() else 0
        weight = np.where(np.isfinite(one["cof_row_mm"].values), force, 0.0)
        mask = xr.DataArray(regions[name], dims=("row", "col"))
        rows.append({
            "region": name, "sensels": int(regions[name].sum()),
            "peak_force_N": float(force[i]), "peak_force_time_s": float(t[i]) if t.size else
            np.nan, "impulse_N_s": impulse,
            "max_contact_area_mm2": float(one["contact_area_mm2"].max()),
            "peak_pressure_kPa": float(one["peak_kPa"].max()),
            "pti_peak_kPa_s": float(time_integral(one["peak_kPa"].fillna(0.0), t)),
            "pti_max_sensel_kPa_s": float(pti.where(mask).max()),
            "mean_cof_row_mm": _weighted(one["cof_row_mm"].values, weight),
            "mean_cof_col_mm": _weighted(one["cof_col_mm"].values, weight),
            "share_of_impulse": impulse / total if total > 0 else np.nan,
        })
    return pd.DataFrame(rows)


def _weighted(values, weight):
    values = np.nan_to_num(np.asarray(values, dtype=float))
    return float(np.dot(values, weight) / weight.sum()) if weight.sum() > 0 else float("nan")
