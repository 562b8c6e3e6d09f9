"""Simulated sessions of Gillis (2013) Table 4.2 carry the truth they claim."""

import numpy as np
import pytest

from tactilecal.simulate._dynamic import LBF_N, random_sine_sets, sensel_matrix, sine_sweep


def test_sweep_follows_table_4_2():
    s = sine_sweep(f_stop_hz=12, sensor_noise_N=0.0, reference_noise_N=0.0)
    assert s.sets["f_hz"].tolist() == list(np.arange(1.0, 13.0))
    assert s.sets["cycles"].tolist() == [3] * 5 + [20] * 7
    assert s.offset_N == pytest.approx(120 * LBF_N)
    assert s.sets["amplitude_N"].iloc[0] == pytest.approx(20 * LBF_N)
    t_s, t_r = s.sensor.time.values, s.reference.time.values
    assert np.diff(t_s)[0] == pytest.approx(1 / 4000) and np.diff(t_r)[0] == pytest.approx(1 / 5000)
    # the load cell's own clock: its sample k happened at sensor time t_r[k] + lag_s
    np.testing.assert_allclose(s.reference.values, s.load_N(t_r + s.lag_s))
    assert sine_sweep(f_stop_hz=12, reverse=True).sets["f_hz"].iloc[0] == 12.0


def test_sensor_reads_load_through_the_known_gain():
    s = sine_sweep(f_start_hz=80, f_stop_hz=80, sensor_noise_N=0.0, reference_noise_N=0.0)
    t = s.sensor.time.values
    start = s.sets["start_s"].iloc[0]
    mid = (t > start + 0.05) & (t < start + 0.2)
    amp_sensor = np.ptp(s.sensor.values[mid]) / 2
    assert amp_sensor == pytest.approx(20 * LBF_N / s.true_gain(80.0), rel=2e-3)
    # DC gain 1: the record's mean is the load's (a log gain law settles slowly after a
    # ramp, so a short steady stretch would not show it)
    assert np.mean(s.sensor.values) == pytest.approx(np.mean(s.load_N(t)), rel=1e-12)


def test_blind_test_2_sets():
    b = random_sine_sets(seed=4)
    assert len(b.sets) == 20
    assert b.sets["f_hz"].between(10, 200).all()
    assert b.sets["amplitude_N"].between(0.5 * LBF_N, 60 * LBF_N).all()
    assert b.sets["cycles"].between(10, 200).all()
    assert b.offset_N == pytest.approx(100 * LBF_N)
    by_f = b.sets.sort_values("f_hz")
    assert by_f["amplitude_N"].is_monotonic_decreasing and by_f["cycles"].is_monotonic_increasing
    again = random_sine_sets(seed=4)
    np.testing.assert_array_equal(again.sensor.values, b.sensor.values)


def test_sensel_matrix_sums_to_the_sensor_force():
    s = sine_sweep(f_stop_hz=3)
    m = sensel_matrix(s, shape=(3, 4), gain_spread=0.0, noise_N=0.0)
    np.testing.assert_allclose(m.sum(("row", "col")).values, s.sensor.values)
    assert m.attrs["seconds_per_frame"] == pytest.approx(1 / 4000)


def test_bad_log_base():
    with pytest.raises(ValueError, match="log_base='2'; expected 'e' or '10'"):
        sine_sweep(f_stop_hz=3, log_base="2")


def test_written_sweep_fits_to_its_truth_from_the_command_line(tmp_path):
    import json

    from tactilecal.cli import main

    # the test's rates (1000 / 1250 Hz, a quarter of the thesis' samples to write and read):
    # A within 0.2 % and the lag within 2 us of the truth, as at 4000 / 5000 Hz
    paths = sine_sweep(f_stop_hz=40, seed=2, fs_sensor_hz=1000.0,
                       fs_reference_hz=1250.0).write(tmp_path / "sweep")
    truth = json.loads(paths["truth"].read_text())
    assert main(["-q", "dynamic", "fit", str(paths["sensor"]), str(paths["reference"]),
                 "--model", "log10", "--out", str(tmp_path / "F.json")]) == 0
    fitted = json.loads((tmp_path / "F.json").read_text())
    assert fitted["A"] == pytest.approx(truth["A"], rel=0.05)
    assert fitted["lag_s"] == pytest.approx(truth["lag_s"], abs=1e-3)
    assert truth["sets"]["f_hz"] == list(np.arange(1.0, 41.0))
