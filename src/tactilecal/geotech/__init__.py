"""Geotechnical helpers: Jaky's K0, vertical stress in a centrifuge, hydrostatic pressure.

Model-scale inputs (depth in model metres, g-level N); see the module notes of each function
for the source equation (Gillis 2013, sections 4.4.2, 5.4 and 5.7).
"""

from tactilecal.geotech._centrifuge import prototype_frequency_hz, to_prototype
from tactilecal.geotech._plots import plot_earth_pressure_profile
from tactilecal.geotech._soil import (
    at_rest_pressure_kPa,
    dry_unit_weight_kN_m3,
    hydrostatic_pressure_kPa,
    k0_jaky,
    unit_weight_from_relative_density,
    vertical_stress_kPa,
    void_ratio,
)

__all__ = [
    "to_prototype",
    "prototype_frequency_hz",
    "at_rest_pressure_kPa",
    "dry_unit_weight_kN_m3",
    "hydrostatic_pressure_kPa",
    "k0_jaky",
    "plot_earth_pressure_profile",
    "unit_weight_from_relative_density",
    "vertical_stress_kPa",
    "void_ratio",
]
