"""Transfer function, model fit, filter and blind test on short simulated sessions.

Short records (1000 Hz sensor, 1250 Hz load cell, sweep 1..140 Hz in 2 Hz steps) keep this
file fast; benchmarks/bench_dynamic.py runs the full thesis sweep.
"""

import numpy as np
import pytest
import xarray as xr

from tactilecal.dynamic import (
    CorrectionFilter,
    apply_filter,
    evaluate,
    fit_filter,
    fit_transfer,
    transfer_function,
)
from tactilecal.simulate import random_sine_sets, sine_sweep

FAST = {"step_hz": 2, "cycles_high": 10, "fs_sensor_hz": 1000.0, "fs_reference_hz": 1250.0,
        "sensor_noise_N": 0.2, "reference_noise_N": 0.05}


@pytest.fixture(scope="module")
def sweep():
    return sine_sweep(seed=0, **FAST)


@pytest.fixture(scope="module")
def filt(sweep):
    return fit_filter(sweep.sensor, sweep.reference)


def test_fit_recovers_A_base_and_lag(sweep, filt):
    assert filt.model == "log10" and filt.fit.log_base == "10"
    assert filt.fit.A == pytest.approx(0.11, rel=0.03)
    assert abs(filt.lag_s - sweep.lag_s) < 0.5 / 1000  # half a sensor sample
    assert filt.fit.r2 > 0.85
    assert filt.fit.excluded["low_coherence"] > 0  # bins far above the sweep left out
    # leakage of the sets' abrupt ends stays coherent a little above 140 Hz at low noise
    assert 140 <= filt.band_hz[1] <= 250


def test_natural_log_model_gives_A_over_ln10(sweep):
    filt = fit_filter(sweep.sensor, sweep.reference, model="log")
    assert filt.fit.log_base == "e"
    assert filt.fit.A == pytest.approx(0.11 / np.log(10), rel=0.03)


def test_log_quadratic_model_is_flexible_and_close(sweep):
    filt = fit_filter(sweep.sensor, sweep.reference, model="log-quadratic")
    f = np.arange(5.0, 140.0)
    np.testing.assert_allclose(filt.gain(f), sweep.true_gain(f), rtol=0.01)


@pytest.mark.parametrize("method", ["ratio", "h1", "h2"])
def test_three_estimators_agree_with_truth(sweep, method):
    from tactilecal.dynamic import align

    s, r, _ = align(sweep.sensor, sweep.reference)
    tf = transfer_function(s, r, method=method, band_hz=(5, 130))
    fit = fit_transfer(tf, model="log10")
    assert fit.A == pytest.approx(0.11, rel=0.05)
    assert tf.excluded["outside_band"] > 0


def test_blind_test_rms_error_drops(filt):
    blind = random_sine_sets(n_sets=8, f_range_hz=(10, 140), cycles_range=(5, 40), seed=7,
                             fs_sensor_hz=1000.0, fs_reference_hz=1250.0,
                             sensor_noise_N=0.2, reference_noise_N=0.05)
    ev = evaluate(filt, blind.sensor, blind.reference)
    assert abs(ev.lag_s - blind.lag_s) < 1e-3
    assert ev.improvement > 3.0
    assert np.median(np.abs(ev.error_after_pct)) < np.median(np.abs(ev.error_before_pct)) / 3


def test_filter_json_round_trip(filt, tmp_path):
    path = tmp_path / "FILTER.json"
    filt.to_json(path)
    back = CorrectionFilter.from_json(path)
    f = np.linspace(0, 500, 101)
    np.testing.assert_allclose(back.gain(f), filt.gain(f))
    np.testing.assert_allclose(back.taps, filt.taps)
    assert back.fit.A == filt.fit.A and back.lag_s == filt.lag_s
    resp = CorrectionFilter.from_response(filt.fit.f_hz, filt.fit.measured, fs_hz=1000.0)
    resp.to_json(tmp_path / "RESPONSE.json")
    back = CorrectionFilter.from_json(tmp_path / "RESPONSE.json")
    np.testing.assert_allclose(back.gain(f), resp.gain(f))


def test_filter_is_zero_phase_unit_dc_and_does_not_amplify_outside():
    filt = CorrectionFilter.from_model(("log10", {"A": 0.11}), fs_hz=1000.0, band_hz=(1, 100),
                                       taper_hz=25.0)
    f = np.array([0.0, 3.0, 50.0, 100.0, 130.0, 300.0, 499.0])
    realised = filt.realised_gain(f)
    assert realised[0] == pytest.approx(1.0, abs=1e-12)
    np.testing.assert_allclose(realised[1:4], filt.gain(f[1:4]), rtol=2e-3)
    np.testing.assert_allclose(realised[4:], 1.0, atol=1e-3)
    np.testing.assert_allclose(filt.taps, filt.taps[::-1])  # symmetric: zero phase, centred
    hold = CorrectionFilter.from_model(("log10", {"A": 0.11}), fs_hz=1000.0, band_hz=(1, 100),
                                       outside="hold")
    assert hold.gain(400.0) == pytest.approx(1 + 0.11 * np.log10(101))


def test_apply_chunked_equals_dask_and_direct_convolution():
    filt = CorrectionFilter.from_model(("log", {"A": 0.05}), fs_hz=500.0, band_hz=(1, 100),
                                       n_taps=101)
    rng = np.random.default_rng(3)
    x = 50 + rng.normal(size=(1500, 2, 3)).cumsum(axis=0)
    x[:, 1, 2] = np.nan  # a sensel outside the sensor's shape
    rec = xr.DataArray(x, dims=("frame", "row", "col"),
                       coords={"time": ("frame", np.arange(1500) / 500.0)})
    out = apply_filter(rec, filt, precision="double")
    lazy = apply_filter(rec.chunk({"frame": 400}), filt, precision="double")
    assert lazy.chunks is not None
    np.testing.assert_allclose(lazy.values, out.values, atol=1e-9)
    single = apply_filter(rec, filt)  # default: single-precision FFTs
    span = np.nanmax(x) - np.nanmin(x)
    np.testing.assert_allclose(single.values, out.values, atol=1e-6 * span)
    assert np.isnan(out.values[:, 1, 2]).all()
    padded = np.pad(x[:, 0, 0], 50, mode="reflect", reflect_type="odd")
    np.testing.assert_allclose(out.values[:, 0, 0], np.convolve(padded, filt.taps, "valid"),
                               atol=1e-9)


def test_bad_inputs(sweep, filt):
    t = sweep.sensor.time.values
    with pytest.raises(ValueError, match=r"band_hz=\(1, 600\) reaches beyond the Nyquist"):
        fit_filter(sweep.sensor, sweep.reference, band_hz=(1, 600))
    # the sweep calibrates 1-148 Hz: a band to 400 Hz would be stated as calibrated
    with pytest.raises(ValueError, match=r"band_hz=\(1, 400\) reaches past the bins the sweep "
                                         r"calibrates, 1 to 148 Hz; .*band_hz=\(1, 148\)"):
        fit_filter(sweep.sensor, sweep.reference, band_hz=(1, 400))
    assert fit_filter(sweep.sensor, sweep.reference, band_hz=(1, 140)).band_hz == (1.0, 140.0)
    short = sweep.reference.isel(time=slice(0, 900)).assign_attrs(source="short.csv")
    with pytest.raises(ValueError, match="short.csv: the overlap with .* expected at least"):
        fit_filter(sweep.sensor, short)
    gap = sweep.sensor.copy()
    gap[500:510] = np.nan
    with pytest.raises(ValueError, match="10 NaN/inf values"):
        fit_filter(gap, sweep.reference)
    with pytest.raises(ValueError, match="sampled at 1000 Hz; the filter was built for 4000"):
        apply_filter(sweep.sensor, CorrectionFilter.from_model(("log", {"A": 0.1}),
                                                               fs_hz=4000, band_hz=(1, 100)))
    with pytest.raises(ValueError, match="has 500 frames .* expected at least the filter"):
        apply_filter(sweep.sensor.isel(time=slice(0, 500)), filt)
    rec = xr.DataArray(np.ones((2000, 2)), dims=("frame", "col"),
                       coords={"time": ("frame", t[:2000])}, attrs={"source": "rec.nc"})
    rec[100, 1] = np.nan
    with pytest.raises(ValueError, match="rec.nc: sensel 1 .* NaN from frame index 100"):
        apply_filter(rec, filt)
    with pytest.raises(ValueError, match="precision='half'; expected 'single' or 'double'"):
        apply_filter(sweep.sensor, filt, precision="half")
    with pytest.raises(ValueError, match="model='cubic'"):
        fit_filter(sweep.sensor, sweep.reference, model="cubic")
    with pytest.raises(ValueError, match="outside='clip'"):
        CorrectionFilter.from_model(("log", {"A": 0.1}), fs_hz=100, band_hz=(1, 10),
                                    outside="clip")
    with pytest.raises(ValueError, match="band_hz is required"):
        CorrectionFilter.from_model(("log", {"A": 0.1}), fs_hz=100)
    with pytest.raises(ValueError, match=r"band_hz=\(5, 1\); expected 0 <= LO < HI"):
        CorrectionFilter.from_model(("log", {"A": 0.1}), fs_hz=100, band_hz=(5, 1))
    with pytest.raises(ValueError, match="expected equal lengths >= 2"):
        CorrectionFilter.from_response([1.0], [1.0], fs_hz=100)
    with pytest.raises(ValueError, match="method='h3'"):
        transfer_function(sweep.sensor, sweep.sensor, method="h3")
    with pytest.raises(ValueError, match="are not on the same time stamps"):
        transfer_function(sweep.sensor, sweep.reference)


def test_bad_filter_files(tmp_path):
    bad = tmp_path / "bad.json"
    bad.write_text("{not json")
    with pytest.raises(ValueError, match="bad.json: not valid JSON"):
        CorrectionFilter.from_json(bad)
    bad.write_text('{"model": "log"}')
    with pytest.raises(ValueError, match="bad.json: not a tactilecal dynamic filter"):
        CorrectionFilter.from_json(bad)
    bad.write_text("[1, 2]")
    with pytest.raises(ValueError, match="bad.json: JSON list; expected an object"):
        CorrectionFilter.from_json(bad)


def test_more_error_messages(sweep):
    from tactilecal.dynamic import resample_to
    from tactilecal.dynamic._calibrate import static_factor
    from tactilecal.dynamic._transfer import TransferFunction

    f = np.arange(5.0)
    tf = TransferFunction(f, np.ones(5), np.zeros(5), np.zeros(5, bool), "h2", 100.0, 100, 0.9)
    with pytest.raises(ValueError, match="only 0 frequency bins have coherence >= 0.9"):
        fit_transfer(tf)
    with pytest.raises(ValueError, match="reaches beyond the Nyquist frequency 50 Hz"):
        CorrectionFilter.from_model(("log", {"A": 0.1}), fs_hz=100, band_hz=(1, 60))
    with pytest.raises(ValueError, match="taper_hz=-1; expected > 0"):
        CorrectionFilter.from_model(("log", {"A": 0.1}), fs_hz=100, band_hz=(1, 10),
                                    taper_hz=-1)
    with pytest.raises(ValueError, match="model='cubic'; expected one of"):
        CorrectionFilter.from_model(("cubic", {"A": 0.1}), fs_hz=100, band_hz=(1, 10))
    rec = xr.DataArray(np.ones((3000, 2)), dims=("col", "frame"),
                       coords={"time": ("frame", np.arange(2) / 1000)}, attrs={"source": "t.nc"})
    with pytest.raises(ValueError, match="t.nc: expected a 'time' coordinate .* along the first"):
        apply_filter(rec, CorrectionFilter.from_model(("log", {"A": 0.1}), fs_hz=1000,
                                                      band_hz=(1, 10)))
    with pytest.raises(ValueError, match="time_s: 1 target time stamps; expected at least 2"):
        resample_to(sweep.reference, [0.5])
    zero = sweep.sensor * 0
    with pytest.raises(ValueError, match="mean reading is 0"):
        static_factor(zero, sweep.sensor)
