"""Creep and hysteresis on series whose drift and loop are known."""

import numpy as np
import pytest
import xarray as xr

from tactilecal import analysis


def held_force(rate_pct_per_min=0.5, noise_N=0.2, seed=7):
    t = np.arange(0.0, 1800.0, 2.0)  # 30 min at 0.5 Hz
    force = 200.0 * (1 + rate_pct_per_min / 100 * t / 60)
    force += np.random.default_rng(seed).normal(0.0, noise_N, t.size)
    return xr.DataArray(force, dims="frame", coords={"time": ("frame", t)},
                        attrs={"units": "N"})


def test_linear_drift_recovered():
    r = analysis.creep(held_force())
    # 0.5 %/min of 200 N = 1 N/min; noise 0.2 N over 900 samples
    assert r.rate_pct_per_min == pytest.approx(0.5, abs=0.005)
    assert r.slope_per_min == pytest.approx(1.0, abs=0.01)
    assert r.reference == pytest.approx(200.0, abs=0.1)
    assert abs(r.rate_pct_per_min - 0.5) < 4 * r.rate_stderr_pct_per_min + 1e-3
    assert r.units == "N" and r.n == 900
    assert "%/min" in r.summary() and r.to_dict()["n"] == 900


def test_window_selects_samples():
    r = analysis.creep(held_force(), start_s=600.0, stop_s=1200.0)
    assert r.n == 301 and r.start_s == 600.0
    # reference is the fitted force at start_s: 200 (1 + 0.05) = 210 N
    assert r.reference == pytest.approx(210.0, abs=0.1)
    assert r.rate_pct_per_min == pytest.approx(100 / 210, abs=0.01)


def test_log_time_creep_recovered():
    t = np.linspace(0.0, 600.0, 601)
    force = 100.0 + 3.0 * np.log10(t - (-1.0))  # loaded at t = -1 s
    r = analysis.creep(force, time_s=t, t_load_s=-1.0)
    assert r.log_slope_per_decade == pytest.approx(3.0, rel=1e-10)
    assert r.log_r2 == pytest.approx(1.0)
    assert r.log_rate_pct_per_decade == pytest.approx(300.0 / r.reference)
    assert r.log_r2 > r.linear_r2


def test_creep_of_a_recording_uses_its_total_force():
    t = np.arange(10) * 6.0
    p = np.ones((10, 2, 2)) * (100.0 + t)[:, None, None]
    rec = xr.DataArray(p, dims=("frame", "row", "col"), coords={"time": ("frame", t)},
                       attrs={"units": "kPa", "sensel_area_mm2": 10.0})
    r = analysis.creep(rec)
    # total force 4 x 10 mm2 x (100 + t) kPa x 1e-3 = 4 + 0.04 t N -> 2.4 N/min over 4 N
    assert r.slope_per_min == pytest.approx(2.4) and r.rate_pct_per_min == pytest.approx(60.0)


def test_creep_errors():
    with pytest.raises(ValueError, match="signal has no 'time' coordinate"):
        analysis.creep(np.ones(5))
    with pytest.raises(ValueError, match="creep window 0-1 s holds 2 samples"):
        analysis.creep(np.ones(5), time_s=np.arange(5.0), stop_s=1.0)
    with pytest.raises(ValueError, match="1 samples after t_load_s=3 s"):
        analysis.creep(np.ones(5), time_s=np.arange(5.0), t_load_s=3.0)
    with pytest.raises(ValueError, match=r"fitted signal at start_s=0 s is 0; expected"):
        analysis.creep(np.zeros(5), time_s=np.arange(5.0))
    with pytest.raises(ValueError, match=r"signal has shape \(5,\) and time \(4,\)"):
        analysis.creep(np.ones(5), time_s=np.arange(4.0))


def sine_loop(n=201):
    up = np.linspace(0.0, 10.0, n)
    down = up[::-1][1:]
    return np.r_[up, down], np.r_[up, down + 2 * np.sin(np.pi * down / 10)]


def test_hysteresis_hand_worked_loop():
    ref, meas = sine_loop()
    r = analysis.hysteresis(ref, meas)
    # gap 2 sin(pi x / 10): largest 2 at x = 5; area integral_0^10 = 40 / pi
    assert r.max_gap == pytest.approx(2.0, abs=1e-4) and r.max_gap_at == pytest.approx(5.0)
    assert r.area == pytest.approx(40 / np.pi, rel=1e-4)
    assert r.measured_range == 10.0 and r.reference_range == 10.0
    assert r.max_gap_pct == pytest.approx(20.0, abs=1e-3)
    assert r.area_pct == pytest.approx(40 / np.pi, rel=1e-4)  # 100 x area / (10 x 10)
    assert (r.n_loading, r.n_unloading) == (201, 201)
    assert "loop area" in r.summary()


def test_hysteresis_without_loop_is_zero():
    ref, _ = sine_loop()
    r = analysis.hysteresis(ref, 3.0 * ref)
    assert r.max_gap == pytest.approx(0.0, abs=1e-12) and r.area == pytest.approx(0.0, abs=1e-9)


def test_hysteresis_errors():
    with pytest.raises(ValueError, match=r"reference has shape \(3,\) and measured \(2,\)"):
        analysis.hysteresis([0, 1, 0], [0, 1])
    with pytest.raises(ValueError, match="the reference peaks at sample 2 of 3"):
        analysis.hysteresis([0, 1, 2], [0, 1, 2])
    with pytest.raises(ValueError, match="reference or measured holds NaN"):
        analysis.hysteresis([0, 2, 1, 0], [0, np.nan, 1, 0])


def test_creep_through_a_simulated_sensor():
    """A held 30 N patch whose true load creeps by 2 % of F0 per decade of time, read as
    8-bit frames by the simulated sensor and turned back into force by its own law."""
    from tactilecal.simulate import make_sensor

    sensor = make_sensor("5051", gain_spread=0.0, read_noise=0.5, n_dead=0, seed=2)
    t = np.arange(0.0, 600.0, 1.0)
    true_N = 30.0 * (1 + 0.02 * np.log10(t + 1.0))  # loaded at t = -1 s
    force = np.zeros((t.size, sensor.rows, sensor.cols))
    force[:, 10:20, 10:20] = (true_N / 100)[:, None, None]
    rec = sensor.to_dataarray(sensor.read(force, rng=np.random.default_rng(4)), time_s=t)

    class OwnLaw:
        def apply(self, recording, units="kPa"):
            out = recording.copy(data=sensor.force_of_raw(recording.values))
            out.attrs = {**recording.attrs, "units": "N"}
            return out if units == "N" else out.tactile.pressure_map()

    r = analysis.creep(rec, t_load_s=-1.0, calibration=OwnLaw())
    # 0.02 x 30 N = 0.6 N per decade; 8-bit rounding of ~0.3 N sensels: 5 % tolerance
    assert r.log_slope_per_decade == pytest.approx(0.6, rel=0.05)
    assert r.log_r2 > r.linear_r2


def test_creep_and_hysteresis_are_saved_files_that_load_reads_back(tmp_path):
    import json

    import tactilecal

    creep = analysis.creep(held_force())
    loop = analysis.hysteresis(*sine_loop())
    for result, name, tag in ((creep, "creep.json", "tactilecal-creep/1"),
                              (loop, "loop.json", "tactilecal-hysteresis/1")):
        result.to_json(tmp_path / name)
        assert json.loads((tmp_path / name).read_text())["format"] == tag
        back = tactilecal.load(tmp_path / name)
        assert type(back) is type(result) and back == result  # equal by value
    flat = analysis.creep(np.full(50, 3.0), time_s=np.arange(50.0))  # R2 undefined: NaN
    flat.to_json(tmp_path / "flat.json")
    assert tactilecal.load(tmp_path / "flat.json") == flat  # NaN equals NaN: unknown
    data = json.loads((tmp_path / "creep.json").read_text())
    data["n"] = "many"
    (tmp_path / "bad.json").write_text(json.dumps(data))
    with pytest.raises(TypeError, match=r"key 'n' of .*bad.json is 'many' \(str\); expected a "
                                        r"whole number"):
        tactilecal.load(tmp_path / "bad.json")
