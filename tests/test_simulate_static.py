"""Uniform loads and ramp-and-hold sessions: truth recovered from the simulated records."""

import numpy as np
import pytest

from tactilecal.simulate import make_sensor, ramp_hold, uniform_load
from tactilecal.simulate._static import ramp_hold_profile

LBF_N = 4.4482216152605


@pytest.fixture(scope="module")
def sensor():
    return make_sensor("5051", seed=1)


@pytest.fixture(scope="module")
def session(sensor):
    return ramp_hold(sensor, seed=2)


def test_uniform_load_recovers_gains_and_pressure(sensor):
    raw, pressure = uniform_load(sensor, [100.0, 400.0], frames_per_level=20, seed=3)
    assert raw.shape == (40, 44, 44) and raw.attrs["units"] == "raw"
    np.testing.assert_array_equal(pressure, np.repeat([100.0, 400.0], 20))
    live = ~sensor.dead
    for level, frames in ((100.0, raw.values[:20]), (400.0, raw.values[20:])):
        f = level * sensor.sensel_area_mm2 * 1e-3
        ideal = (f / sensor.A_N) ** (1 / sensor.b)
        err = frames.mean(axis=0)[live] - sensor.gain[live] * ideal
        # mean of 20 readings: noise sd 0.5 plus rounding (1/12 variance) gives an error of
        # sd sqrt((0.25 + 1/12) / 20) = 0.129 counts; max over 1933 sensels < 5 sd
        assert np.sqrt(np.mean(err ** 2)) == pytest.approx(0.129, rel=0.1)
        assert np.abs(err).max() < 5 * 0.129
        assert (frames[:, sensor.dead] == 0).all()


def test_uniform_load_errors(sensor):
    with pytest.raises(ValueError, match=r"pressures_kPa: got \[-1\.0\]; expected one or more"):
        uniform_load(sensor, [-1.0])
    with pytest.raises(ValueError, match=r"frames_per_level: got 0; expected a positive"):
        uniform_load(sensor, 10.0, frames_per_level=0)
    with pytest.raises(TypeError, match="sensor: expected a SimulatedSensor"):
        uniform_load(None, 10.0)


def test_profile_matches_gillis_sequence():
    t, f = ramp_hold_profile(np.array([50, 100, 150, 200]) * LBF_N, hold_s=3, ramp_s=2,
                             lead_s=1)
    assert t.tolist() == [0, 1, 3, 6, 8, 11, 13, 16, 18, 21, 23, 24]
    np.testing.assert_allclose(f[2:-2:2], np.array([50, 100, 150, 200]) * LBF_N)
    np.testing.assert_array_equal(f[2:-2:2], f[3:-2:2])


def test_ramp_hold_sensor_and_loadcell(session, sensor):
    raw, lc = session.raw, session.loadcell
    assert raw.sizes["frame"] == 2400 and raw.attrs["seconds_per_frame"] == pytest.approx(0.01)
    np.testing.assert_allclose(raw["time"].values, np.arange(2400) / 100.0)
    assert lc.dims == ("time",) and lc.attrs["units"] == "N" and lc["time"].values[0] == 0
    np.testing.assert_allclose(np.diff(lc["time"].values), 1 / 500.0)
    # load-cell clock: its time t is sensor time t + 0.37 s
    truth = np.interp(lc["time"].values + 0.37, raw["time"].values, session.load_N)
    interior = lc["time"].values + 0.37 <= raw["time"].values[-1]
    np.testing.assert_allclose(session.loadcell_true_N[interior], truth[interior], atol=1e-9)
    resid = lc.values - session.loadcell_true_N
    assert np.std(resid) == pytest.approx(0.5, rel=0.05)
    np.testing.assert_allclose(session.weights.sum(), 1.0, rtol=1e-12)
    assert (session.weights > 0).mean() == pytest.approx(0.5, abs=0.02)


def test_ramp_hold_holds_read_the_law(session, sensor):
    raw = session.raw
    for (start, end), level in zip(session.hold_windows_s, session.loads_N, strict=True):
        hold = raw.sel(frame=(raw["time"] > start + 0.05) & (raw["time"] < end - 0.05))
        np.testing.assert_allclose(session.load_N[np.isin(raw["frame"], hold["frame"])], level)
        ideal = sensor.gain * (level * session.weights / sensor.A_N) ** (1 / sensor.b)
        ok = (session.weights > 0) & ~sensor.dead & (ideal > 4) & (ideal < 254)
        mean = hold.values.mean(axis=0)
        assert np.abs(mean - ideal)[ok].max() < 0.5  # 290 noisy rounded frames averaged


def test_ramp_hold_deterministic_and_errors(sensor):
    a = ramp_hold(sensor, hold_s=0.2, ramp_s=0.1, lead_s=0.1, seed=4)
    b = ramp_hold(sensor, hold_s=0.2, ramp_s=0.1, lead_s=0.1, seed=4)
    np.testing.assert_array_equal(a.raw.values, b.raw.values)
    np.testing.assert_array_equal(a.loadcell.values, b.loadcell.values)
    with pytest.raises(ValueError, match=r"hold_s: got 0; expected a positive number"):
        ramp_hold(sensor, hold_s=0)
    with pytest.raises(ValueError, match=r"loadcell_start_offset_s: got -1; expected a non"):
        ramp_hold(sensor, loadcell_start_offset_s=-1)
    with pytest.raises(ValueError, match=r"pad_fraction: got 1.5; expected a share in"):
        ramp_hold(sensor, pad_fraction=1.5)
    with pytest.raises(ValueError, match=r"loads_N: got \[\]; expected one or more"):
        ramp_hold(sensor, loads_N=[])
    with pytest.raises(ValueError, match=r"frame_rate_hz: 0.01 Hz over the 24 s sequence "
                                         r"gives 0 frames; expected at least 2"):
        ramp_hold(sensor, frame_rate_hz=0.01)
    with pytest.raises(ValueError, match=r"loadcell_start_offset_s: 100 s leaves no load-cell"):
        ramp_hold(sensor, loadcell_start_offset_s=100)


def test_ramp_hold_write_reads_back(tmp_path, sensor):
    from tactilecal import read_tekscan, read_timeseries

    s = ramp_hold(sensor, loads_N=(100.0, 200.0), hold_s=0.3, ramp_s=0.2, lead_s=0.1, seed=5)
    paths = s.write(tmp_path / "rh")
    assert paths["loadcell"].read_text().splitlines()[0] == "Time (s),Load (N)"
    rec = read_tekscan(paths["recording"])
    np.testing.assert_array_equal(rec.values, s.raw.values)
    np.testing.assert_allclose(rec["time"].values, s.raw["time"].values, atol=1e-12)
    lc = read_timeseries(paths["loadcell"])
    np.testing.assert_allclose(lc.values, s.loadcell.values, atol=1e-6)
    np.testing.assert_allclose(lc["time"].values, s.loadcell["time"].values, atol=1e-6)
