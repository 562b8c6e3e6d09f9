"""Pressure-map analysis: force, area, centre of force, profiles, zones, time effects.

Every function takes a recording in the data model (``docs/data-model.md``): a
DataArray ``("frame", "row", "col")`` with a ``time`` coordinate and the sensor's
attributes, in pressure (kPa, MPa, psi) or force (N, kgf, lbf) units. A raw recording
needs ``calibration=`` (a CalibrationResult or the path of its JSON). Results are
vectorised over frames and carry the ``time`` coordinate.

Importing this package registers the xarray accessor ``recording.tactile``
(``analysis._accessor.TactileAccessor``): ``rec.tactile.force()``, ``.area()``, ``.centre()``,
``.peak()``, ``.pressure_map()``, ``.calibrate(cal)``... and its figures,
``.plot_pressure_map()``, ``.plot_force_time()``, ``.plot_cof_path()``, ``.plot_profiles()``.
"""

from tactilecal._deprecated import moved_names
from tactilecal.analysis._accessor import TactileAccessor  # noqa: F401 - registers .tactile
from tactilecal.analysis._describe import describe, frame_table, overview
from tactilecal.analysis._maps import (
    centre_of_force,
    contact_area,
    mean_pressure,
    peak_pressure,
    summary,
    total_force,
)
from tactilecal.analysis._plots import peak_frame
from tactilecal.analysis._regions import (
    column_profile,
    high_pressure_zones,
    label_zones,
    max_window_load,
    row_profile,
    select_region,
)
from tactilecal.analysis._time import creep, hysteresis
from tactilecal.analysis._units import force_map_N, pressure_map_kPa, saturated_sensels

__all__ = [
    "total_force", "contact_area", "centre_of_force", "peak_pressure", "mean_pressure",
    "summary", "pressure_map_kPa", "force_map_N", "saturated_sensels",
    "row_profile", "column_profile", "select_region", "high_pressure_zones", "label_zones",
    "max_window_load", "peak_frame", "describe", "frame_table", "overview",
    "creep", "hysteresis",
]

__getattr__ = moved_names(__name__, {
    "CreepResult": ("_time", "CreepResult", "creep() returns it"),
    "HysteresisResult": ("_time", "HysteresisResult", "hysteresis() returns it"),
    "loaded_mask": ("_maps", "loaded_mask", "use pressure_map_kPa(recording) > threshold"),
    "FRAME_COLUMNS": ("_describe", "FRAME_COLUMNS", "the columns of frame_table()"),
    **{name: ("_plots", name, f"use the accessor method recording.tactile.{name}()")
       for name in ("plot_pressure_map", "plot_force_time", "plot_cof_path", "plot_profiles")},
})
