"""patch_histograms: dead-weight patches as histograms under a known law (one simulator)."""

import numpy as np
import pytest

from tactilecal.simulate import patch_histograms
from tactilecal.simulate._loads import PAD_MASS_G

G = 9.80665


def test_loads_are_mass_plus_pad_under_standard_gravity():
    _, load, mass = patch_histograms(40, masses_kg=(2, 5), pad_sides_cm=(2,), seed=4)
    assert set(mass) <= {2.0, 5.0}
    np.testing.assert_allclose(load, (mass + PAD_MASS_G[2] / 1000) * G, rtol=1e-12)


def test_histograms_add_up_to_the_load_within_rounding():
    # linear law, no threshold, light loads (nothing saturates): sum_i A X_i = load up to
    # half a count per loaded sensel
    A_N = 0.01
    hist, load, _ = patch_histograms(20, A_N=A_N, b=1.0, masses_kg=(0.5,),
                                     pad_sides_cm=(2, 3), threshold=0, seed=2)
    assert hist[:, 255].sum() == 0
    force = hist @ (A_N * np.arange(256.0))
    cells = hist.sum(axis=1)
    assert np.all(np.abs(force - load) <= 0.5 * A_N * cells)
    # the pad covers round(side_mm / 1.27)**2 sensels of a 5051
    sides = np.rint(np.sqrt(cells)).astype(int)
    assert set(sides) <= {round(20 / 1.27), round(30 / 1.27)}


def test_threshold_zeroes_low_readings_and_seed_repeats():
    hist, _, _ = patch_histograms(10, threshold=5, seed=1)
    assert hist[:, 1:5].sum() == 0
    again, _, _ = patch_histograms(10, threshold=5, seed=1)
    np.testing.assert_array_equal(hist, again)
    assert patch_histograms(1, seed=0)[0].sum() > 0


@pytest.mark.parametrize("pitch", [1.27, 2.54])
def test_pitch_sets_the_patch_size(pitch):
    hist, _, _ = patch_histograms(5, pad_sides_cm=(4,), sensel_pitch_mm=pitch, seed=3)
    assert set(hist.sum(axis=1)) == {round(40 / pitch) ** 2}
