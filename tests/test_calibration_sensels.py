"""Non-working sensels and equilibration against simulated sensors with known truth."""

import re

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from tactilecal.calibration import (
    Equilibration,
    calibrate,
    equilibrate,
    find_dead_sensels,
    points_from_frames,
    validate,
)
from tactilecal.simulate import deadweight_session, make_sensor, uniform_load


def test_dead_sensels_found_under_dead_weights():
    sensor = make_sensor("5051", n_dead=6, seed=2)
    session = deadweight_session(sensor, n_patches=60, seed=5)
    found = find_dead_sensels(session.raw)
    truth = sensor.dead
    # every reported sensel is truly dead; dead sensels never covered by a patch with
    # responding neighbours cannot be told from unloaded ones and are not reported
    assert not (found.mask & ~truth).any()
    covered = ((session.raw.values > 0).sum(axis=0) > 0)
    assert found.mask.sum() >= 2  # 2 of the 6 with these seeds (default: all neighbours)
    assert "non-working sensels:" in found.report() and found.to_dict()["n_frames"] == 60
    assert not covered[found.mask].any()


def test_dead_sensel_errors():
    with pytest.raises(ValueError, match="neighbour_share=0; expected a share in"):
        find_dead_sensels(np.ones((1, 3, 3)), neighbour_share=0)
    with pytest.raises(ValueError, match="min_frames=0; expected an integer >= 1"):
        find_dead_sensels(np.ones((1, 3, 3)), min_frames=0)
    with pytest.raises(ValueError, match="raw has 1 dimensions; expected 3"):
        find_dead_sensels(np.ones(3))


def test_equilibration_recovers_gains(tmp_path):
    sensor = make_sensor("5051", gain_spread=0.08, n_dead=3, seed=4)
    raw, _ = uniform_load(sensor, [150.0, 400.0], frames_per_level=10, seed=1)
    levels = [raw[:10], raw[10:]]
    eq = equilibrate(levels)
    alive = ~sensor.dead
    assert np.isnan(eq.gain[sensor.dead]).all()
    # a raw gain g on a sensel is undone by 1/g, up to the level mean: compare shapes
    ratio = eq.gain[alive] * sensor.gain[alive]
    assert np.std(ratio) / np.mean(ratio) < 0.01  # gain spread 8 % -> below 1 %
    for lv in eq.levels:
        assert lv["cv_after"] < 0.2 * lv["cv_before"]
    path = tmp_path / "eq.json"
    eq.to_json(path)
    back = Equilibration.from_json(path)
    np.testing.assert_allclose(back.gain, eq.gain)
    out = back.apply(raw.values[:1])
    assert np.isnan(out[0][sensor.dead]).all() and np.nanmax(out) <= 255


def test_equilibration_improves_calibration():
    """Gains measured under uniform load lower the held-out error of a power calibration."""
    sensor = make_sensor("5051", gain_spread=0.15, n_dead=0, seed=6)
    raw, _ = uniform_load(sensor, [150.0, 400.0], frames_per_level=5, seed=2)
    eq = equilibrate([raw[:5], raw[5:]])
    cal = deadweight_session(sensor, n_patches=40, seed=7)
    val = deadweight_session(sensor, n_patches=40, seed=8)
    med = {}
    for name, tf in (("plain", lambda x: x), ("equilibrated", eq.apply)):
        fit = calibrate(points_from_frames(tf(cal.raw.values), cal.load_N), method="power")
        out = validate(fit, points_from_frames(tf(val.raw.values), val.load_N))
        med[name] = out.metrics["median_abs_error_pct"]
    assert med["equilibrated"] < 0.2 * med["plain"]  # measured 2.13 % -> 0.09 %


def test_equilibration_errors(tmp_path):
    with pytest.raises(ValueError, match="levels is empty"):
        equilibrate([])
    with pytest.raises(ValueError, match=r"level 1 has frames of shape \(2, 2\); expected"):
        equilibrate([np.ones((1, 3, 3)), np.ones((1, 2, 2))])
    with pytest.raises(ValueError, match="level 0 has no loaded, unsaturated sensel"):
        equilibrate([np.zeros((1, 3, 3))])
    eq = equilibrate([np.full((1, 3, 3), 10.0)])
    with pytest.raises(ValueError, match=r"frames have shape \(2, 2\); expected \(3, 3\)"):
        eq.apply(np.ones((1, 2, 2)))
    bad = tmp_path / "x.json"
    bad.write_text('{"kind": "calibration"}')
    with pytest.raises(ValueError, match="x.json has no key 'format'; expected an equilibration"):
        Equilibration.from_json(bad)
    bad.write_text("[")
    with pytest.raises(ValueError, match="x.json: not valid JSON"):
        Equilibration.from_json(bad)


def test_one_3d_array_is_not_taken_as_one_level_per_frame():
    sensor = make_sensor("5051", seed=4)
    raw, _ = uniform_load(sensor, [150.0], frames_per_level=6, seed=1)
    with pytest.raises(ValueError, match=r"levels is one array of shape \(6, 44, 44\); its "
                                         r"frames would each be taken as a load level"):
        equilibrate(raw.values)
    with pytest.raises(ValueError, match=r"levels is one array of shape \(6, 44, 44\)"):
        equilibrate(raw)
    assert equilibrate([raw]).levels[0]["n_frames"] == 6


_DOORS = {
    "points_from_frames": lambda f: points_from_frames(f, np.ones(len(f))),
    "equilibrate": lambda f: equilibrate([f]),
    "find_dead_sensels": lambda f: find_dead_sensels(f, chunk_frames=2),
    "Equilibration.apply": lambda f: Equilibration(gain=np.ones(f.shape[1:])).apply(f),
}


@given(frames=st.integers(1, 5), where=st.integers(0, 10**6),
       value=st.floats(allow_nan=False) | st.sampled_from([np.inf, -np.inf, 255.5, 0.5]),
       door=st.sampled_from(sorted(_DOORS)))
def test_every_door_of_raw_frames_refuses_a_reading_outside_0_255(frames, where, value, door):
    """Out of 0..255 (infinity too) is one message at every door, in whichever frame (blocks
    of two frames); NaN and fractions (equilibrated frames) are readings."""
    data = np.full((frames, 3, 3), 40.0)
    data[:, 0, 0] = np.nan
    data.flat[where % data.size] = value
    if 0 <= np.rint(value) <= 255:  # readings are counted at their nearest level
        _DOORS[door](data)
        return
    shown = re.escape(f"{np.rint(value):g}")
    with pytest.raises(ValueError, match=rf"raw frames contain the value {shown}; expected "
                                         r"raw readings 0..255"):
        _DOORS[door](data)
