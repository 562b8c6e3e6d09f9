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
(:func:`hysteresis`).
"""

from tactilecal.analysis._accessor import TactileAccessor  # registers .tactile
from tactilecal.analysis._describe import overview
from tactilecal.analysis._gait import align_recordings
from tactilecal.analysis._plots import peak_frame
from tactilecal.analysis._regionset import Regions
from tactilecal.analysis._time import creep, hysteresis

__all__ = ["TactileAccessor", "Regions", "overview", "peak_frame", "creep", "hysteresis",
           "align_recordings"]

