"""One analysis of a recording: headline numbers, per-frame table, regions and steps.

What ``tactilecal analyze`` prints and writes, as plain data, so that Python users get the
same numbers as the command line.
"""

from dataclasses import dataclass

import pandas as pd

from tactilecal._text import number, share
from tactilecal.analysis._contacts import RegionAnalysis, region_analysis
from tactilecal.analysis._describe import FRAME_COLUMNS, frame_table, overview
from tactilecal.analysis._gait import Steps, steps
from tactilecal.analysis._maps import summary
from tactilecal.analysis._units import pressure_map_kPa

__all__ = ["Analysis", "analyze"]


@dataclass
class Analysis:
    """The analysis of one recording (``rec.tactile.analyze()``).

    Attributes
    ----------
    overview : dict
        Headline numbers (:func:`tactilecal.analysis.overview`).
    frames : pandas.DataFrame
        The per-frame table (``frame``, ``time_s``, force, area, centre, pressures...).
    regions : RegionAnalysis or None
        Per-region numbers, when regions were asked for.
    steps : Steps or None
        The steps, when asked for.
    """

    overview: dict
    frames: pd.DataFrame
    regions: RegionAnalysis | None = None
    steps: Steps | None = None

    def wide_table(self):
        """Return the per-frame table, with each region's columns (``force_N [name]``...)."""
        if self.regions is None:
            return self.frames
        ds = self.regions.summary
        columns = {f"{q} [{name}]": ds[q].sel(region=name).values
                   for name in self.regions.regions for q in FRAME_COLUMNS}
        return pd.concat([self.frames, pd.DataFrame(columns, index=self.frames.index)], axis=1)

    def to_dict(self):
        """Return everything as JSON-ready data."""
        out = {"overview": self.overview, "frames": self.frames.to_dict(orient="records")}
        if self.regions is not None:
            out["regions"] = self.regions.table.to_dict(orient="records")
            out["region_sensels"] = self.regions.regions.to_dict()
        if self.steps is not None:
            out["steps"] = self.steps.table.to_dict(orient="records")
            out["step_threshold_N"] = self.steps.threshold_N
        return out

    def text(self):
        """Return what ``tactilecal analyze`` prints: aligned lines, numbers for people."""
        width = max(map(len, self.overview))
        lines = [f"{key:<{width}}  {number(value)}" for key, value in self.overview.items()]
        if self.regions is not None:
            lines += ["", "regions:", _table_text(self.regions.table)]
        if self.steps is not None:
            lines += ["", f"steps (contact above {number(self.steps.threshold_N)} N):",
                      _table_text(self.steps.table)]
        return "\n".join(lines)


def _table_text(table):
    shown = table.copy()
    for column in shown.columns:
        if column.startswith("share_"):
            shown[column] = [share(v) for v in shown[column]]
        else:
            shown[column] = [number(v) for v in shown[column]]
    return shown.to_string(index=False)


def analyze(recording, *, calibration=None, threshold_kPa=0.0, regions=None,
            gap_mm=None, find_steps=False, source=None):
    """Analyse a recording: headline numbers, per-frame table, and optionally regions, steps.

    Parameters
    ----------
    recording : xarray.DataArray
        Recording in the data model (raw needs ``calibration``).
    calibration : CalibrationResult or path, optional
        Applied to a raw recording (once).
    threshold_kPa : float, default 0
        Loaded-sensel threshold for contact areas and mean pressures.
    regions : Regions, dict or "contacts", optional
        Regions to analyse (see ``rec.tactile.regions``).
    gap_mm : float, optional
        For ``regions="contacts"`` (see ``rec.tactile.split_contacts``; None: its default).
    find_steps : bool, default False
        Also find the steps (``rec.tactile.steps``).
    source : str, optional
        The recording's name in the overview.

    Returns
    -------
    Analysis

    Examples
    --------
    >>> import numpy as np, xarray as xr
    >>> f = np.zeros((6, 1, 4)); f[1:3, 0, 0] = 10.0; f[4, 0, 3] = 20.0
    >>> rec = xr.DataArray(f, dims=("frame", "row", "col"),
    ...                    coords={"time": ("frame", np.arange(6) * 0.5)},
    ...                    attrs={"units": "N", "sensel_area_mm2": 1.0, "row_spacing_mm": 1.0,
    ...                           "col_spacing_mm": 1.0})
    >>> out = analyze(rec, regions={"left": (0, 1, 0, 2), "right": (0, 1, 2, 4)},
    ...               find_steps=True)
    >>> out.overview["peak_force_N"], out.regions.table["impulse_N_s"].tolist()
    (20.0, [10.0, 10.0])
    >>> out.steps.table["peak_force_N"].tolist()
    [10.0, 20.0]
    """
    # saturation is read on the raw readings of a raw recording
    s = summary(recording, threshold_kPa=threshold_kPa, calibration=calibration)
    pressure = pressure_map_kPa(recording, calibration=calibration) \
        if recording.attrs.get("units") == "raw" else recording
    frames = frame_table(s)
    head = overview(frames, source=source)
    found = None if regions is None else region_analysis(
        pressure, regions, threshold_kPa=threshold_kPa, gap_mm=gap_mm)
    found_steps = steps(pressure, summary=s) if find_steps else None
    return Analysis(head, frames, found, found_steps)
