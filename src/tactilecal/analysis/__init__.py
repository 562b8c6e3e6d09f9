"""Pressure-map analysis: force, area, centre of force, profiles, zones, time effects.

Every function takes a recording in the data model (``docs/data-model.md``): a
DataArray ``("frame", "row", "col")`` with a ``time`` coordinate and the sensor's
attributes, in pressure (kPa, MPa, psi) or force (N, kgf, lbf) units. A raw recording
needs ``calibration=`` (a CalibrationResult or the path of its JSON). Results are
vectorised over frames and carry the ``time`` coordinate.

Importing this package registers the xarray accessor ``recording.tactile``
(:class:`TactileAccessor`): ``rec.tactile.force()``, ``.area()``, ``.centre()``,
``.peak()``, ``.pressure_map()``, ``.calibrate(cal)``...
"""

from tactilecal.analysis._accessor import TactileAccessor
from tactilecal.analysis._describe import FRAME_COLUMNS, describe, frame_table, overview
from tactilecal.analysis._maps import (
    centre_of_force,
    contact_area,
    loaded_mask,
    mean_pressure,
    peak_pressure,
    summary,
    total_force,
)
from tactilecal.analysis._plots import (
    peak_frame,
    plot_cof_path,
    plot_force_time,
    plot_pressure_map,
    plot_profiles,
)
from tactilecal.analysis._regions import (
    column_profile,
    high_pressure_zones,
    label_zones,
    max_window_load,
    row_profile,
    select_region,
)
from tactilecal.analysis._time import CreepResult, HysteresisResult, creep, hysteresis
from tactilecal.analysis._units import force_map_N, pressure_map_kPa, saturated_sensels

__all__ = [
    "CreepResult",
    "FRAME_COLUMNS",
    "HysteresisResult",
    "TactileAccessor",
    "centre_of_force",
    "column_profile",
    "contact_area",
    "creep",
    "describe",
    "force_map_N",
    "frame_table",
    "high_pressure_zones",
    "hysteresis",
    "label_zones",
    "loaded_mask",
    "max_window_load",
    "overview",
    "mean_pressure",
    "peak_frame",
    "peak_pressure",
    "plot_cof_path",
    "plot_force_time",
    "plot_pressure_map",
    "plot_profiles",
    "pressure_map_kPa",
    "row_profile",
    "saturated_sensels",
    "select_region",
    "summary",
    "total_force",
]
