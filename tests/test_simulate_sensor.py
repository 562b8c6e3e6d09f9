"""Simulated sensor: the per-sensel power law, gain, noise, threshold, saturation, dead sensels."""

import numpy as np
import pytest

from tactilecal.simulate import make_sensor
from tactilecal.simulate._sensor import SimulatedSensor, sensor_geometry

ATTRS = ("sensor_type", "units", "row_spacing_mm", "col_spacing_mm", "sensel_area_mm2",
         "seconds_per_frame", "noise_threshold", "source")


def test_catalogue_and_custom_geometry():
    s = make_sensor("5051")
    assert (s.rows, s.cols, s.row_spacing_mm, s.sensel_area_mm2) == (44, 44, 1.27,
                                                                      pytest.approx(1.6129))
    s = make_sensor("9500")
    assert (s.rows, s.cols, s.row_spacing_mm) == (14, 14, 5.08)
    assert sensor_geometry((5, 7, 2.0)) == ("custom", 5, 7, 2.0, 2.0, 4.0)
    s = make_sensor((5, 7, 2.0), n_dead=0)
    assert s.gain.shape == (5, 7) and s.dead.shape == (5, 7)


def test_noise_free_law_inverts_exactly():
    # Zvyagin eq. 1: a sensel carrying f = A * X**b reads X (integer X, no gain, no noise).
    s = make_sensor("5051", gain_spread=0, read_noise=0, n_dead=0, A_N=0.0035, b=1.16)
    x = np.random.default_rng(4).integers(3, 255, size=(44, 44)).astype(float)
    np.testing.assert_array_equal(s.read(0.0035 * x ** 1.16, 0), x)


def test_readings_follow_law_gain_and_noise_within_quantisation():
    s = make_sensor("5051", read_noise=0.5, seed=2)
    rng = np.random.default_rng(5)
    force = rng.uniform(0.02, 1.5, size=(20, 44, 44))
    raw = s.read(force, rng)
    expected = s.gain * (force / s.A_N) ** (1 / s.b)
    ok = ~s.dead & (expected < 254) & (expected > 4)
    err = (raw - expected)[ok]
    # rounding (<= 0.5) plus Gaussian noise (sd 0.5): 6 sd bound, and the sd itself
    assert np.abs(err).max() <= 0.5 + 6 * 0.5
    assert np.std(err) == pytest.approx(np.sqrt(0.5 ** 2 + 1 / 12), rel=0.05)
    assert abs(np.mean(err)) < 0.01


def test_gain_is_lognormal_with_requested_spread():
    s = make_sensor("5051", gain_spread=0.05, seed=3)
    log_gain = np.log(s.gain)
    # 1936 draws: sd of the sd estimate ~ 0.05 / sqrt(2 * 1936) = 0.0008
    assert np.std(log_gain) == pytest.approx(0.05, abs=0.003)
    assert abs(np.mean(log_gain)) < 0.005


def test_threshold_saturation_and_dead_sensels():
    s = make_sensor("9500", gain_spread=0, read_noise=0, n_dead=5, seed=1)
    live = ~s.dead
    at = np.full((14, 14), s.force_of_raw(2.0))  # default threshold 2
    above = np.full((14, 14), s.force_of_raw(3.0))
    huge = np.full((14, 14), 1e4)
    assert (s.read(at)[live] == 0).all()
    assert (s.read(above)[live] == 3).all()
    assert (s.read(huge)[live] == 255).all()
    for f in (at, above, huge):
        assert (s.read(f)[s.dead] == 0).all()
    assert s.dead.sum() == 5


def test_readings_at_the_noise_threshold_are_zeroed_as_tekscan_does():
    # the real I-Scan export (NOISE_THRESHOLD 3) has readings 0 and 4.., never 1..3
    s = make_sensor("9500", gain_spread=0, read_noise=0, n_dead=0, noise_threshold=3)
    readings = s.read(s.force_of_raw(np.arange(1.0, 6.0))[:, None, None] * np.ones((14, 14)))
    assert readings[:, 0, 0].tolist() == [0.0, 0.0, 0.0, 4.0, 5.0]


def test_dead_sensels_are_uniform_random_positions_per_seed():
    a, b = make_sensor(n_dead=10, seed=0), make_sensor(n_dead=10, seed=1)
    assert a.dead.sum() == b.dead.sum() == 10
    assert not np.array_equal(a.dead, b.dead)


def test_deterministic_per_seed():
    a, b, c = make_sensor(seed=7), make_sensor(seed=7), make_sensor(seed=8)
    np.testing.assert_array_equal(a.gain, b.gain)
    np.testing.assert_array_equal(a.dead, b.dead)
    assert not np.array_equal(a.gain, c.gain)
    f = np.full((3, 44, 44), 0.3)
    np.testing.assert_array_equal(a.read(f, 11), b.read(f, 11))


def test_to_dataarray_follows_the_data_model():
    s = make_sensor("5051")
    raw = s.read(np.full((4, 44, 44), 0.2), 0)
    da = s.to_dataarray(raw, source="x")
    assert da.dims == ("frame", "row", "col") and da.dtype == np.float64
    assert da["frame"].values.tolist() == [1, 2, 3, 4]
    assert da["frame"].dtype == np.int64 and da["row"].dtype == np.int64
    np.testing.assert_allclose(da["time"].values, np.arange(4) * 0.005)
    assert set(ATTRS) <= set(da.attrs) and da.attrs["units"] == "raw"
    assert da.attrs["source"] == "x" and da.attrs["noise_threshold"] == 2
    da = s.to_dataarray(raw, time_s=[0.0, 0.1, 0.2, 0.3])
    assert da.attrs["seconds_per_frame"] == pytest.approx(0.1)
    assert s.to_dataarray(raw[0]).sizes["frame"] == 1


def test_dataclass_fields():
    s = make_sensor()
    assert isinstance(s, SimulatedSensor)
    for name in ("rows", "cols", "row_spacing_mm", "col_spacing_mm", "sensel_area_mm2", "A_N",
                 "b", "gain", "dead", "read_noise", "noise_threshold"):
        assert hasattr(s, name)
    assert s.dead.dtype == bool


@pytest.mark.parametrize(("kwargs", "match"), [
    ({"model": (4, 4)}, r"model: a custom sensor is \(rows, cols, spacing_mm\)"),
    ({"model": (4, 0, 1.0)}, r"model: a custom sensor needs positive integer rows"),
    ({"model": "nope"}, r"unknown sensor 'nope'"),
    ({"model": 3.5}, r"model: expected a sensor name"),
    ({"A_N": -1.0}, r"A_N: got -1.0; expected a positive number"),
    ({"b": 0}, r"b: got 0; expected a positive number"),
    ({"read_noise": -0.1}, r"read_noise: got -0.1; expected a non-negative number"),
    ({"gain_spread": float("nan")}, r"gain_spread: got nan"),
    ({"n_dead": 5000}, r"n_dead: got 5000; expected an integer in 0..1936"),
])
def test_make_sensor_errors(kwargs, match):
    with pytest.raises(ValueError, match=match):
        make_sensor(**kwargs)


def test_shape_errors():
    s = make_sensor("9500")
    with pytest.raises(ValueError, match=r"force_N: last two axes are \(3, 3\); expected"):
        s.read(np.zeros((3, 3)))
    with pytest.raises(ValueError, match=r"raw: shape \(2, 3, 3\); expected \(frames, 14, 14\)"):
        s.to_dataarray(np.zeros((2, 3, 3)))
    with pytest.raises(ValueError, match=r"time_s: 3 values; expected one per frame \(2\)"):
        s.to_dataarray(np.zeros((2, 14, 14)), time_s=[0, 1, 2])


def test_sensor_model_objects_are_accepted():
    from tactilecal.sensors import custom_sensor, get_sensor

    s = make_sensor(custom_sensor(10, 20, 2.0, col_spacing_mm=3.0), n_dead=0)
    assert (s.rows, s.cols, s.row_spacing_mm, s.col_spacing_mm, s.sensel_area_mm2) == \
        (10, 20, 2.0, 3.0, 6.0)
    assert make_sensor(get_sensor("5101")).row_spacing_mm == 2.54


def test_a_law_given_as_pressure_per_count_scales_with_the_sensel_area():
    # A_N = A_kPa * area_mm2 / 1000: 2.17 kPa is 0.0035 N on the 5051's 1.6129 mm2 sensels
    # and 0.056 N on the 9500's 25.8064 mm2 (16x the area)
    a_kpa = 0.0035e3 / 1.6129
    assert make_sensor("5051", A_kPa=a_kpa).A_N == pytest.approx(0.0035, rel=1e-12)
    assert make_sensor("9500", A_kPa=a_kpa).A_N == pytest.approx(0.0035 * 16, rel=1e-12)
    assert make_sensor("9500").A_N == 0.0035  # the default stays a force per sensel
    with pytest.raises(ValueError, match=r"A_N = 0.004 and A_kPa = 2.0; expected one of them"):
        make_sensor(A_N=0.004, A_kPa=2.0)
    with pytest.raises(ValueError, match=r"A_kPa: got -1.0; expected a positive number"):
        make_sensor(A_kPa=-1.0)
