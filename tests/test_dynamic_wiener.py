"""Filters with phase through every path, and the Wiener-regularised measured correction (issue 13).

A sensor that is neither the thesis' log law nor a rational model: the log law behind a slow
first-order creep (zero 6 Hz, pole 2 Hz). No single parametric model of the family
describes it to 1 %, so ``auto`` must choose the measured correction; its FIR must realise
the complex target, on the multirate and dask paths too.
"""

import json

import numpy as np
import pytest
import xarray as xr

from tactilecal._jsonutil import to_jsonable
from tactilecal.dynamic import (
    CorrectionFilter,
    Evaluation,
    RationalModel,
    apply_filter,
    evaluate,
    fit_filter,
)
from tactilecal.dynamic._multirate import plan_multirate
from tactilecal.dynamic._wiener import wiener_correction
from tactilecal.simulate import DynamicSensor, random_sine_sets, sine_sweep

RATES = {"fs_sensor_hz": 1000.0, "fs_reference_hz": 1250.0, "sensor_noise_N": 0.2,
         "reference_noise_N": 0.05}
CREEP = DynamicSensor(A=0.11, zeros_hz=(6.0,), poles_hz=(2.0,))
VISCO = RationalModel.from_corners_hz(zeros_hz=[40.0], poles_hz=[10.0])
VISCO_SENSOR = DynamicSensor(A=0.0, zeros_hz=(40.0,), poles_hz=(10.0,))


@pytest.fixture(scope="module")
def creep_sweep():
    sweep = sine_sweep(seed=0, response=CREEP, step_hz=2, cycles_high=10, **RATES)
    return sweep.sensor, sweep.reference


def test_auto_chooses_the_measured_correction_for_a_sensor_no_model_describes(creep_sweep):
    filt = fit_filter(*creep_sweep, model="auto")
    assert filt.model == "wiener" and filt.fit.model_choice.chosen == "wiener"
    assert filt.fit.model_choice.r2_complex >= 0.9  # held-out bins
    blind = random_sine_sets(seed=5, response=CREEP, **RATES)
    rational_filter = fit_filter(*creep_sweep, model="rational", force=True)
    wiener = evaluate(filt, blind.sensor, blind.reference, lag_s=blind.lag_s)  # true clock
    rational = evaluate(rational_filter, blind.sensor, blind.reference, lag_s=blind.lag_s)
    assert wiener.improvement >= 10  # measured 16x
    assert wiener.improvement > 1.3 * rational.improvement  # rational 3 zeros, 3 poles: 11x
    assert np.abs(wiener.phase_after_deg).max() < 10 < np.abs(wiener.phase_before_deg).max()


def test_the_shrinkage_leaves_clear_deviations_and_drops_those_within_the_error():
    measured = np.array([1.0 + 0.0j, 2.0 - 1.0j, 1.001 + 0.001j])
    out = wiener_correction(measured, [0.01, 0.001, 0.01])
    assert out[0] == 1.0
    assert abs(out[1] - measured[1]) < 1e-5 * abs(measured[1] - 1)  # kept
    assert abs(out[2] - 1) < 0.02 * abs(measured[2] - 1)  # within its error: shrunk to 1
    np.testing.assert_array_equal(wiener_correction(measured, np.zeros(3)), measured)


def test_wiener_filter_json_round_trip_keeps_the_phase(creep_sweep, tmp_path):
    filt = fit_filter(*creep_sweep, model="wiener")
    path = tmp_path / "FILTER.json"
    filt.to_json(path)
    stored = json.loads(path.read_text())
    assert stored["model"] == "wiener" and len(stored["response"]["phase_rad"]) > 100
    assert set(stored["correction"]) == {"f_hz", "gain", "phase_deg"}
    f_hz = np.linspace(0, 250, 101)
    np.testing.assert_allclose(CorrectionFilter.from_json(path).target(f_hz), filt.target(f_hz),
                               atol=1e-12)
    stored["response"]["phase_rad"] = stored["response"]["phase_rad"][:-1]
    path.write_text(json.dumps(stored))
    with pytest.raises(ValueError, match="key 'response' of .*lengths"):
        CorrectionFilter.from_json(path)


@pytest.fixture(scope="module")
def visco_filter():
    """The rational inverse of a first-order sensor at the thesis' 4000 Hz, band 1..140 Hz."""
    return CorrectionFilter("rational", {"order": 1}, 4000.0, (1.0, 140.0), rational=VISCO)


def test_the_centred_fir_realises_the_complex_target(visco_filter):
    f_hz = np.linspace(0.0, 180.0, 181)
    error = np.abs(visco_filter.realised_target(f_hz) - visco_filter.target(f_hz))
    assert error.max() < 0.01 * np.abs(visco_filter.target(f_hz)).max()
    assert np.degrees(np.angle(visco_filter.target(20.0))) > 20  # undoes a lag: a lead


def _record(values, fs_hz):
    return xr.DataArray(values, dims=("frame", "sensel"),
                        coords={"time": ("frame", np.arange(values.shape[0]) / fs_hz)})


@pytest.mark.filterwarnings("ignore::tactilecal.dynamic._apply.BandWarning")  # a random walk
def test_a_phase_filter_takes_the_multirate_and_dask_paths(visco_filter):
    rng = np.random.default_rng(3)
    rec = _record(100 + rng.standard_normal((12_000, 3)).cumsum(axis=0) * 0.1, 4000.0)
    plan = plan_multirate(visco_filter)
    assert plan is not None and plan.phase and plan.factor >= 2
    direct = apply_filter(rec, visco_filter, method="direct", precision="double").values
    multirate = apply_filter(rec, visco_filter, precision="double").values
    lazy = apply_filter(rec.chunk({"frame": 3001}), visco_filter, precision="double").values
    span = np.ptp(rec.values)
    # aliases are 70 dB below the correction, here up to 3x the signal: measured 2.6e-5 span
    np.testing.assert_allclose(multirate, direct, atol=1e-4 * span)
    np.testing.assert_allclose(lazy, multirate, atol=1e-9 * span)


def test_the_offline_inverse_restores_amplitude_and_phase_of_a_tone(visco_filter):
    fs_hz, f_hz = 4000.0, 30.0
    t = np.arange(16_000) / fs_hz
    tone = np.sin(2 * np.pi * f_hz * t)
    seen = VISCO_SENSOR.read(xr.DataArray(50 + tone, dims="time", coords={"time": t}))
    out = apply_filter(seen, visco_filter).values - 50
    np.testing.assert_allclose(out[4000:-4000], tone[4000:-4000], atol=0.01)


def test_figures_show_the_phase_of_the_correction_and_of_the_errors(creep_sweep, tmp_path):
    from tactilecal.report import write_report

    filt = fit_filter(*creep_sweep, model="wiener")
    fig = filt.plot_transfer()
    assert len(fig.axes) == 2 and "phase" in fig.axes[1].get_ylabel()
    line = next(ln for ln in fig.axes[1].lines if ln.get_label() == "correction")
    f_hz, phase = line.get_data()
    np.testing.assert_allclose(phase, np.degrees(np.angle(filt.target(f_hz))))
    assert len(CorrectionFilter.from_model(
        ("log10", {"A": 0.11}), fs_hz=1000, band_hz=(1, 100)).plot_transfer().axes) == 1
    ev = evaluate(filt, *creep_sweep)
    error_fig = ev.plot_error()
    assert [ax.get_ylabel() for ax in error_fig.axes] == ["amplitude error (%)",
                                                           "phase error (deg)"]
    back = Evaluation.from_dict(json.loads(json.dumps(to_jsonable(ev.to_dict()))))
    for key in ("f_hz", "error_after_pct", "phase_before_deg", "phase_after_deg"):
        np.testing.assert_allclose(getattr(back, key), getattr(ev, key), rtol=1e-12)
    assert back.improvement == pytest.approx(ev.improvement, rel=1e-12)
    stored_fig = back.plot_error()  # what the report draws from evaluation.json
    np.testing.assert_allclose(stored_fig.axes[1].lines[0].get_ydata(),
                               error_fig.axes[1].lines[0].get_ydata(), rtol=1e-12)
    filt.to_json(tmp_path / "FILTER.json")
    html = write_report([tmp_path / "FILTER.json"], tmp_path / "r.html").read_text()
    assert "transfer function, fitted model and filter gain" in html and "<img" in html


def test_the_report_says_a_filter_was_forced_and_how_its_model_was_chosen(tmp_path):
    from tactilecal.report import write_report

    sweep = sine_sweep(seed=0, response=VISCO_SENSOR, step_hz=2, cycles_high=10, **RATES)
    forced = fit_filter(sweep.sensor, sweep.reference, model="log", force=True)
    forced.to_json(tmp_path / "FILTER.json")
    html = write_report([tmp_path / "FILTER.json"], tmp_path / "r.html").read_text()
    assert "written with --force although its model was refused" in html
    auto = fit_filter(sweep.sensor, sweep.reference, model="auto")
    auto.to_json(tmp_path / "AUTO.json")
    html = write_report([tmp_path / "AUTO.json"], tmp_path / "a.html").read_text()
    assert "model_choice" in html and "-&gt; rational" in html and "forced" not in html


@pytest.fixture(scope="module")
def thesis_sweep():
    """The thesis sensor's short sweep (the log law, A = 0.11)."""
    return sine_sweep(seed=0, A=0.11, step_hz=2, cycles_high=10, **RATES)


def test_a_sweep_shorter_than_a_few_cycles_of_its_lowest_frequency_is_refused(thesis_sweep):
    sweep = thesis_sweep
    with pytest.raises(ValueError, match=r"simulated sensor and simulated load cell \(.* s after "
                       r"alignment\): .* holds .* cycles of the lowest fitted frequency"):
        fit_filter(sweep.sensor.isel(time=slice(0, 2500)),
                   sweep.reference.isel(time=slice(0, 3200)), model="auto")


@pytest.mark.parametrize(("params", "match"), [
    ({}, "key 'params' of .* lacks the keys \\['A'\\]"),
    ({"A": 1e308}, r"key 'params.A' of .*FILTER.json is 1e\+308; expected a finite number >= "
                   "-1000 and <= 1000"),
    ({"A": -5.0}, r"key 'params' of .*FILTER.json: the correction it gives is -1.\d+ at "
                  r"\d.* Hz; expected a finite, positive gain up to 1000 in the band"),
])
def test_a_filter_file_whose_parameters_give_no_usable_correction_is_refused(
        tmp_path, params, match):
    path = tmp_path / "FILTER.json"
    CorrectionFilter.from_model(("log10", {"A": 0.11}), fs_hz=1000, band_hz=(1, 100)).to_json(path)
    stored = json.loads(path.read_text())
    stored["params"] = params
    path.write_text(json.dumps(stored))
    with pytest.raises(ValueError, match=match):
        CorrectionFilter.from_json(path)


def test_auto_takes_the_next_candidate_when_the_chosen_one_is_refused(thesis_sweep):
    """The thesis sensor: log10 chosen (complex R2 0.99981) but refused at min_r2 0.9999;
    wiener (held-out bins 0.99998) is next."""
    sweep = thesis_sweep
    assert fit_filter(sweep.sensor, sweep.reference, model="auto").model == "log10"
    filt = fit_filter(sweep.sensor, sweep.reference, model="auto", min_r2=0.9999)
    assert filt.model == "wiener" and filt.forced is None
    assert list(filt.fit.model_choice.refused) == ["log10"]
    assert "explains 99.98% of the complex correction" in filt.fit.model_choice.refused["log10"]
