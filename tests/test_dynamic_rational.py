"""Rational models of the complex response, chosen automatically, undone causally (issue 13).

A simulated viscoelastic sensor (first- and second-order relaxation, gain falling to 0.25
and 0.13) on the short test sweep; the thesis sensor must keep its log model.
"""

import json

import numpy as np
import pytest
from scipy import signal

from tactilecal.cli import main
from tactilecal.dynamic import CorrectionFilter, RationalModel, apply_filter, evaluate, fit_filter
from tactilecal.simulate import random_sine_sets, sine_sweep, through_response

RATES = {"fs_sensor_hz": 1000.0, "fs_reference_hz": 1250.0, "sensor_noise_N": 0.2,
         "reference_noise_N": 0.05}
FAST = {"step_hz": 2, "cycles_high": 10, **RATES}
VISCO1 = RationalModel.from_corners_hz(zeros_hz=[40.0], poles_hz=[10.0])
VISCO2 = RationalModel.from_corners_hz(zeros_hz=[30.0, 120.0], poles_hz=[8.0, 60.0])
LAG_S = 0.8373  # the simulator's clock offset of the sweep


def _corners_hz(model):
    return sorted(-complex(r).real / (2 * np.pi) for r in model.zeros_rad_s), \
        sorted(-complex(r).real / (2 * np.pi) for r in model.poles_rad_s)


@pytest.fixture(scope="module")
def sweep():
    return sine_sweep(seed=0, A=0.0, **FAST)


@pytest.fixture(scope="module")
def visco1_filter(sweep):
    """The filter ``auto`` fits to the first-order sensor (several tests check it)."""
    return fit_filter(through_response(sweep.sensor, VISCO1), sweep.reference, model="auto")


@pytest.fixture(scope="module")
def visco1_blind():
    """Blind Test 2 as the first-order sensor reads it: ``(sensor, reference)``."""
    blind = random_sine_sets(seed=5, A=0.0, **RATES)
    return through_response(blind.sensor, VISCO1), blind.reference


@pytest.mark.parametrize(("truth", "order", "rtol"), [(VISCO1, 1, 0.02), (VISCO2, 2, 0.08)])
def test_auto_chooses_rational_and_finds_the_corners(request, sweep, truth, order, rtol):
    filt = request.getfixturevalue("visco1_filter") if truth is VISCO1 else fit_filter(
        through_response(sweep.sensor, truth), sweep.reference, model="auto")
    assert filt.model == "rational" and filt.params["order"] == order
    assert "-> rational" in filt.fit.excluded["model_choice"]
    for fitted, true in zip(_corners_hz(filt.rational), _corners_hz(truth), strict=True):
        np.testing.assert_allclose(fitted, true, rtol=rtol)
    # the clock offset is kept apart from the sensor's own delay
    assert abs(filt.lag_s - LAG_S) < 1e-3 / 4  # within a quarter sample at 1000 Hz
    assert filt.fit.excluded["sensor_delay_s"] > 5e-4


def test_thesis_sensor_keeps_its_log_model():
    thesis = sine_sweep(seed=0, **FAST)
    filt = fit_filter(thesis.sensor, thesis.reference, model="auto")
    assert filt.model == "log" and "-> log" in filt.fit.excluded["model_choice"]


def test_both_inverses_cut_the_blind_test_error_tenfold(sweep, visco1_filter, visco1_blind):
    sensor, reference = visco1_blind
    offline = evaluate(visco1_filter, sensor, reference)
    causal = evaluate(visco1_filter, sensor, reference, causal=True)
    magnitude_only = evaluate(fit_filter(through_response(sweep.sensor, VISCO1),
                                         sweep.reference, model="log", force=True),
                              sensor, reference)
    assert offline.improvement >= 10 and causal.improvement >= 10
    assert magnitude_only.improvement < 1.5  # the zero-phase model cannot (measured 1.06x)


def test_causal_inverse_undoes_the_response_and_is_stable():
    sos = VISCO1.inverse_sos(1000.0)
    assert np.all(np.abs(signal.sos2zpk(sos)[1]) < 1)  # poles inside the unit circle
    f_hz = np.array([0.0, 10.0, 40.0, 100.0, 140.0])
    _, h = signal.sosfreqz(sos, worN=f_hz, fs=1000.0)
    np.testing.assert_allclose(h * VISCO1.response(f_hz), 1.0, atol=0.02)


def test_dask_and_in_memory_causal_filtering_agree(sweep, visco1_filter):
    import xarray as xr

    filt = visco1_filter
    t = sweep.sensor.time.values
    rec = xr.DataArray(np.random.default_rng(1).normal(100, 3, (t.size, 2, 3)),
                       dims=("frame", "row", "col"), coords={"time": ("frame", t)})
    for causal in (False, True):  # the offline FIR in double precision, as the log filters
        eager = apply_filter(rec, filt, causal=causal, precision="double")
        lazy = apply_filter(rec.chunk({"frame": 500, "row": 1}), filt, causal=causal,
                            precision="double")
        np.testing.assert_allclose(lazy.values, eager.values, rtol=0, atol=1e-9)


def test_rational_filter_json_round_trip_and_cli(sweep, visco1_filter, tmp_path, capsys):
    filt = visco1_filter
    path = tmp_path / "FILTER.json"
    filt.save(path)
    assert json.loads(path.read_text())["rational"]["gain"] == pytest.approx(filt.rational.gain)
    back = CorrectionFilter.from_json(path)
    np.testing.assert_allclose(back.sos(), filt.sos())
    log_filter = tmp_path / "LOG.json"
    fit_filter(sweep.sensor, sweep.reference, model="log", force=True).save(log_filter)
    series = tmp_path / "s.csv"
    series.write_text("t,x\n" + "".join(f"{k / 1000},{np.sin(k / 50)}\n" for k in range(3000)))
    assert main(["-q", "dynamic", "apply", str(log_filter), str(series), "--out",
                 str(tmp_path / "o.csv"), "--causal"]) == 1
    assert "has no causal (IIR) form" in capsys.readouterr().err
    assert main(["-q", "dynamic", "apply", str(path), str(series), "--out",
                 str(tmp_path / "o.csv"), "--causal"]) == 0


def test_a_resonant_sensor_no_model_describes_is_refused_with_the_reason(sweep):
    """A lightly damped resonance at 60 Hz: no real-corner model, no log model fits it."""
    w0, zeta = 2 * np.pi * 60, 0.1
    pole = complex(-zeta * w0, w0 * np.sqrt(1 - zeta**2))
    resonant = RationalModel((), (pole, pole.conjugate()), w0**2)
    with pytest.raises(ValueError, match="simulated sensor: the (best rational model|inverse)"):
        fit_filter(through_response(sweep.sensor, resonant), sweep.reference, model="auto")


def test_gain_error_band_holds_the_expected_gain():
    """Bendat & Piersol's random error of |H1|: the 95 % band holds the expectation."""
    import xarray as xr

    from tactilecal.dynamic import transfer_function

    inside = []
    for seed in range(20):
        rng = np.random.default_rng(seed)
        t = np.arange(0, 60, 1 / 400)
        y = rng.normal(size=t.size)
        x = y / 2 + rng.normal(scale=0.25, size=t.size)  # sensor: half the load plus noise
        tf = transfer_function(xr.DataArray(x, dims="time", coords={"time": t}),
                               xr.DataArray(y, dims="time", coords={"time": t}),
                               nperseg=200, method="h1", min_coherence=0.5)
        expected = 0.5 / (0.25 + 0.25**2)  # E[P_xy] / E[P_xx]
        used = tf.used
        inside.extend(np.abs(tf.gain[used] - expected) <= 1.96 * tf.gain_error[used] * expected)
    assert 0.90 <= np.mean(inside) <= 0.99  # measured 0.944


def test_evaluation_reports_the_phase_before_and_after(visco1_filter, visco1_blind):
    ev = evaluate(visco1_filter, *visco1_blind)
    assert np.abs(ev.phase_before_deg).max() > 30  # the sensor lags (first-order, 10-40 Hz)
    assert np.abs(ev.phase_after_deg).max() < 5
    assert "largest phase error" in ev.summary() and "phase_after_deg" in ev.to_dict()
