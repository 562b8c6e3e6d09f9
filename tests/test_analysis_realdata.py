"""The real F-Scan walking recording: each stance phase shows the double hump of a step."""

import numpy as np
import pytest
from scipy import ndimage, signal

import tactilecal.analysis  # noqa: F401 - registers recording.tactile
from tactilecal import read_tekscan


@pytest.fixture(scope="module")
def walk(fscan_asf):
    return read_tekscan(fscan_asf).tactile.frame_summary()


def stance_phases(force_N, level_N):
    """Frames of each complete stance phase (loaded on both sides by unloaded frames)."""
    labels, n = ndimage.label(force_N > level_N)
    phases = [np.flatnonzero(labels == i) for i in range(1, n + 1)]
    return [p for p in phases if p[0] > 0 and p[-1] < force_N.size - 1]


def test_walk_force_has_double_humped_stance_phases(walk):
    force = walk.force_N.values
    assert force.size == 205
    assert 600 < force.max() < 1200  # about 1.2 body weights of a 75 kg walker (header)
    phases = stance_phases(force, 0.05 * force.max())
    assert len(phases) == 5
    for frames in phases:
        f = ndimage.uniform_filter1d(force[frames], 3)
        peaks, props = signal.find_peaks(f, prominence=0.05 * force.max())
        assert len(peaks) == 2, (frames[0], peaks)
        dip = f[peaks[0]:peaks[1]].min()
        assert dip < 0.92 * min(f[peaks])  # a real dip between the two maxima


def test_walk_centre_of_force_rolls_from_heel_to_toe(walk):
    force = walk.force_N.values
    row_mm = walk.cof_row_mm.values
    for frames in stance_phases(force, 0.05 * force.max()):
        # row 0 is the toe end of this insole: the centre moves up by over 8 cm
        assert row_mm[frames[0]] - row_mm[frames[-1]] > 80.0
    assert np.nanmax(walk.contact_area_mm2) <= 60 * 21 * 25.8064
    assert float(walk.peak_kPa.max()) <= 1514.73 + 1e-6  # header's saturation pressure
