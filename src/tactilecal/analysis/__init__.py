"""Pressure-map analysis: force, area, centre of force, profiles, zones, time effects.

The analysis of a recording is a set of methods of the xarray accessor
``recording.tactile`` (:class:`TactileAccessor`), registered when this package is
imported, so that it reads like xarray: ``rec.tactile.force()``, ``.area()``, ``.centre()``,
``.peak()``, ``.summary()``, ``.profile("row")``, ``.max_window_load(area_mm2=...)``,
``.high_pressure_zones(level_kPa)``, ``.calibrate(cal)``... and its figures,
``.plot_pressure_map()``, ``.plot_force_time()``, ``.plot_cof_path()``, ``.plot_profiles()``.
The recording is a DataArray ``("frame", "row", "col")`` in the data model
(``docs/data-model.md``) with a ``time`` coordinate and the sensor's attributes, in
pressure (kPa, MPa, psi) or force (N, kgf, lbf) units; a raw one needs ``calibration=`` (a
CalibrationResult or the path of its JSON). Results are vectorised over frames and carry
the ``time`` coordinate.

The functions here take what is not a recording: a per-frame table (:func:`overview`), a
summary (:func:`peak_frame`), a force signal (:func:`creep`) or a loading cycle
(:func:`hysteresis`). The functions that the accessor's methods replaced still import for
one release, with a DeprecationWarning that names the method.
"""

from tactilecal._deprecated import moved_names
from tactilecal.analysis._accessor import TactileAccessor  # registers .tactile
from tactilecal.analysis._describe import overview
from tactilecal.analysis._plots import peak_frame
from tactilecal.analysis._time import creep, hysteresis

__all__ = ["TactileAccessor", "overview", "peak_frame", "creep", "hysteresis"]

_ACCESSOR = {  # function that left the public API -> (module, its recording.tactile method)
    "total_force": ("_maps", "force"), "contact_area": ("_maps", "area"),
    "centre_of_force": ("_maps", "centre"), "peak_pressure": ("_maps", "peak"),
    "mean_pressure": ("_maps", "mean_pressure"), "summary": ("_maps", "frame_summary"),
    "pressure_map_kPa": ("_units", "pressure_map"), "force_map_N": ("_units", "force_map"),
    "saturated_sensels": ("_units", "saturated_sensels"),
    "select_region": ("_regions", "select_region"),
    "label_zones": ("_regions", "label_zones"),
    "high_pressure_zones": ("_regions", "high_pressure_zones"),
    "max_window_load": ("_regions", "max_window_load"),
    "describe": ("_describe", "describe"), "frame_table": ("_describe", "frame_table"),
}

__getattr__ = moved_names(__name__, {
    **{name: (module, name, f"use the accessor method recording.tactile.{method}()")
       for name, (module, method) in _ACCESSOR.items()},
    "row_profile": ("_regions", "row_profile", "use recording.tactile.profile('row')"),
    "column_profile": ("_regions", "column_profile", "use recording.tactile.profile('col')"),
    "CreepResult": ("_time", "CreepResult", "creep() returns it"),
    "HysteresisResult": ("_time", "HysteresisResult", "hysteresis() returns it"),
    "loaded_mask": ("_maps", "loaded_mask", "use recording.tactile.pressure_map() > threshold"),
    "FRAME_COLUMNS": ("_describe", "FRAME_COLUMNS", "the columns of "
                      "recording.tactile.frame_table()"),
    **{name: ("_plots", name, f"use the accessor method recording.tactile.{name}()")
       for name in ("plot_pressure_map", "plot_force_time", "plot_cof_path", "plot_profiles")},
})
