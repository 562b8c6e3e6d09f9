"""Unit factors used across the package, defined once (exact by definition unless noted).

Sources: NIST SP 811 (2008), appendix B: 1 lb = 0.45359237 kg, standard gravity
g = 9.80665 m/s2 (CGPM 1901), 1 lbf = 1 lb x g, 1 in = 25.4 mm (1 in2 = 645.16 mm2),
1 psi = 1 lbf/in2. Pressure times area: 1 kPa x 1 mm2 = 1e3 Pa x 1e-6 m2 = 1e-3 N, so a
force per sensel in N is ``pressure_kPa * sensel_area_mm2 * KPA_MM2_TO_N`` and a pressure in
kPa is ``force_N / sensel_area_mm2 * N_PER_MM2_TO_KPA`` (1 N/mm2 = 1 MPa = 1000 kPa).

Sensor constants (pitch, sensel area, capacity) are not here: they come from the sensor
catalogue, :mod:`tactilecal.sensors`.
"""

__all__ = ["G_STANDARD", "LB_KG", "LBF_N", "PSI_TO_KPA", "KPA_MM2_TO_N", "N_PER_MM2_TO_KPA"]

G_STANDARD = 9.80665
"""Standard acceleration of gravity in m/s2 (exact, CGPM 1901)."""

LB_KG = 0.45359237
"""Kilograms per avoirdupois pound (exact)."""

LBF_N = LB_KG * G_STANDARD
"""Newtons per pound-force, 4.4482216152605 N (1 lbf = 1 lb x g)."""

PSI_TO_KPA = LBF_N / 645.16 * 1000.0
"""Kilopascals per psi, 6.894757... kPa (1 lbf / 645.16 mm2, in kPa)."""

KPA_MM2_TO_N = 1e-3
"""Newtons per kPa x mm2: ``force_N = pressure_kPa * area_mm2 * KPA_MM2_TO_N``."""

N_PER_MM2_TO_KPA = 1e3
"""Kilopascals per N/mm2 (1 N/mm2 = 1 MPa = 1000 kPa): ``1 / KPA_MM2_TO_N``."""
