"""K0, unit weights and stresses against hand-worked values and Gillis (2013) Tables 5.2-5.3."""

import numpy as np
import pytest

from tactilecal import geotech

# Gillis (2013) Table 5.2 with its e_min/e_max (and unit weight) labels put right:
# Dr = 0 % is the loosest state (e_max = 0.85, 14.02 kN/m3), Dr = 100 % the densest
# (e_min = 0.59, 16.37 kN/m3). Gs is not printed; 2.65 reproduces all three unit weights.
E_MIN, E_MAX, GS = 0.59, 0.85, 2.65
TABLE_5_2 = {0: (0.85, 14.02), 60: (0.69, 15.36), 100: (0.59, 16.37)}
# Table 5.3: g-level at soil mid depth -> normal pressure under 25 cm of sand (kPa)
TABLE_5_3 = {1.0: 3.8, 11.2: 46.1, 23.0: 92.2, 35.6: 99.8, 47.6: 184.3, 59.1: 257.7}


def test_k0_jaky_hand_worked():
    # 1 - sin(33 deg) = 1 - 0.544639 ; 1 - sin(38 deg) = 1 - 0.615661
    np.testing.assert_allclose(geotech.k0_jaky([33, 38]), [0.455361, 0.384339], atol=1e-6)
    assert geotech.k0_jaky(30) == pytest.approx(0.5)
    with pytest.raises(ValueError, match=r"phi_deg is 90; expected friction angles in \(0, 90\)"):
        geotech.k0_jaky(90)
    with pytest.raises(ValueError, match="phi_deg is -5; expected finite values > 0"):
        geotech.k0_jaky(-5)


@pytest.mark.parametrize("dr", sorted(TABLE_5_2))
def test_table_5_2_void_ratio_and_unit_weight(dr):
    e_table, gamma_table = TABLE_5_2[dr]
    e = geotech.void_ratio(dr, e_min=E_MIN, e_max=E_MAX)
    assert e == pytest.approx(e_table, abs=0.005)  # table prints 2 decimals
    gamma = geotech.unit_weight_from_relative_density(dr, e_min=E_MIN, e_max=E_MAX,
                                                      specific_gravity=GS)
    assert gamma == pytest.approx(gamma_table, rel=0.003)


def test_swapped_void_ratios_are_refused():
    with pytest.raises(ValueError, match="e_min is 0.85 and e_max is 0.59; expected e_min < e_max"):
        geotech.void_ratio(60, e_min=0.85, e_max=0.59)
    with pytest.raises(ValueError, match="relative_density_pct is 120; expected finite values"):
        geotech.void_ratio(120, e_min=E_MIN, e_max=E_MAX)


def test_dry_unit_weight_hand_worked():
    # 2.65 x 9.80665 / 1.694 = 15.3410 kN/m3
    assert geotech.dry_unit_weight_kN_m3(0.694, 2.65) == pytest.approx(15.3410, abs=1e-4)


def test_vertical_stress_table_5_3():
    n = np.array(sorted(TABLE_5_3))
    sigma = geotech.vertical_stress_kPa(0.25, n, unit_weight_kN_m3=15.36)
    # hand-worked: 15.36 kN/m3 x 0.25 m = 3.84 kPa per g
    np.testing.assert_allclose(sigma, 3.84 * n)
    table = np.array([TABLE_5_3[k] for k in n])
    # the table agrees at 1.0 g and 47.6 g (within its rounding, 1 %) ...
    for g in (1.0, 47.6):
        i = int(np.flatnonzero(n == g)[0])
        assert sigma[i] == pytest.approx(table[i], rel=0.012)
    # ... but its other rows equal 3.84 kPa x (12.0, 24.0, 26.0, 67.1) g, not the listed
    # mid-depth g-levels; 99.8 kPa at 35.6 g is 27 % short of 136.7 kPa (the typo).
    np.testing.assert_allclose(table[1:4] / 3.84, [12.0, 24.0, 26.0], atol=0.02)
    assert sigma[3] == pytest.approx(136.7, abs=0.05) and table[3] / sigma[3] < 0.75


def test_vertical_stress_from_relative_density():
    by_dr = geotech.vertical_stress_kPa(0.25, 10.0, relative_density_pct=60, e_min=E_MIN,
                                        e_max=E_MAX, specific_gravity=GS)
    assert by_dr == pytest.approx(10 * 0.25 * 15.3410, rel=1e-4)
    assert geotech.vertical_stress_kPa(0.1, 2.0, unit_weight_kN_m3=15.0,
                                       surcharge_kPa=5.0) == pytest.approx(8.0)
    with pytest.raises(ValueError, match="give unit_weight_kN_m3, or relative_density_pct"):
        geotech.vertical_stress_kPa(0.25, 10.0)
    with pytest.raises(ValueError, match="give unit_weight_kN_m3, or relative_density_pct"):
        geotech.vertical_stress_kPa(0.25, 10.0, unit_weight_kN_m3=15.0, relative_density_pct=60)
    with pytest.raises(ValueError, match="e_min, e_max and specific_gravity are all needed"):
        geotech.vertical_stress_kPa(0.25, 10.0, relative_density_pct=60)
    with pytest.raises(ValueError, match="depth_m is -1; expected finite values >= 0"):
        geotech.vertical_stress_kPa(-1, 10.0, unit_weight_kN_m3=15.0)
    with pytest.raises(ValueError, match="g_level is 0; expected finite values > 0"):
        geotech.vertical_stress_kPa(1, 0, unit_weight_kN_m3=15.0)


def test_hydrostatic_and_at_rest():
    # 7.0 cm of water at 77 g (Gillis 4.4.2): 1000 x 77 x 9.80665 x 0.07 / 1000 kPa
    assert geotech.hydrostatic_pressure_kPa(0.07, 77) == pytest.approx(52.8578, abs=1e-4)
    assert geotech.hydrostatic_pressure_kPa(1.0, 1.0, density_kg_m3=1025.0) == pytest.approx(
        10.0518, abs=1e-4)
    sigma_h = geotech.at_rest_pressure_kPa(0.2, 65.0, [33, 38], unit_weight_kN_m3=15.36)
    np.testing.assert_allclose(sigma_h, np.array([0.455360965, 0.384338525]) * 65 * 15.36 * 0.2,
                               rtol=1e-6)
