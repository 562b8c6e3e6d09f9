"""The earth-pressure profile plot (Gillis 2013, Figure 5.10)."""

import numpy as np
import pytest

from tactilecal import geotech


def test_profile_plot_draws_band_and_rows():
    depth = 0.02 + np.arange(14) * 0.00508  # 14 rows of a 9500 sensor from 2 cm down
    sigma_h = geotech.at_rest_pressure_kPa(depth, 65.0, 35.0, unit_weight_kN_m3=15.36)
    fig = geotech.plot_earth_pressure_profile(sigma_h, depth, g_level=65.0,
                                              unit_weight_kN_m3=15.36)
    ax = fig.axes[0]
    line = ax.lines[0]
    np.testing.assert_allclose(line.get_ydata(), depth * 65.0)  # prototype metres
    # the band spans K0(38) .. K0(33) times sigma_v at the deepest drawn depth
    band = ax.collections[0].get_paths()[0].vertices
    z_max = depth.max() * 1.05
    sigma_v = 65.0 * 15.36 * z_max
    assert band[:, 0].max() == pytest.approx(0.455361 * sigma_v, rel=1e-5)
    assert "K0 0.38-0.46" in ax.get_legend().get_texts()[0].get_text()
    assert ax.get_ylim()[0] > ax.get_ylim()[1]  # depth downwards


def test_profile_plot_errors():
    with pytest.raises(ValueError, match=r"profile_kPa has shape \(3,\) and depth_m \(2,\)"):
        geotech.plot_earth_pressure_profile([1, 2, 3], [0.1, 0.2], g_level=1,
                                            unit_weight_kN_m3=15.0)
    with pytest.raises(ValueError, match="phi_deg is 33; expected two friction angles"):
        geotech.plot_earth_pressure_profile([1], [0.1], g_level=1, phi_deg=33,
                                            unit_weight_kN_m3=15.0)
    with pytest.raises(ValueError, match="scale is 'km'; expected 'prototype' or 'model'"):
        geotech.plot_earth_pressure_profile([1], [0.1], g_level=1, scale="km",
                                            unit_weight_kN_m3=15.0)
