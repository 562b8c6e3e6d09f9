"""Parameter and prediction intervals that hold (issue 12): coverage over 50 simulated sessions."""


import numpy as np
import pytest

from tactilecal import calibrate
from tactilecal.calibration import points_from_frames, validate
from tactilecal.calibration._uncertainty import prediction_interval
from tactilecal.simulate import family_sessions


def _points(session):
    return points_from_frames(session.raw.values, session.load_N,
                              sensel_area_mm2=session.sensor.sensel_area_mm2)


def test_95pct_prediction_interval_holds_90_to_99pct_of_held_out_patches():
    """50 sessions of the family's hardest-gain member (9500, b 1.4, 12 % gains, noise 1)."""
    inside = []
    for seed in range(50):
        train, test = family_sessions("9500-b1.4", seed=seed)
        interval = prediction_interval(_points(train), "power", n_resamples=60, seed=seed)
        held_out = _points(test)
        cal = calibrate(_points(train))
        hist = np.array([p.histogram for p in held_out], dtype=float)
        load = np.array([p.load_N for p in held_out])
        clean = hist[:, 255] == 0
        predicted = hist[clean] @ cal.force_table()
        low, high = interval.bounds_N(predicted)
        inside.extend((low <= load[clean]) & (load[clean] <= high))
    coverage = float(np.mean(inside))
    assert len(inside) > 1000
    assert 0.90 <= coverage <= 0.99, coverage


def test_95pct_interval_of_b_holds_the_true_b_in_90_to_99pct_of_sessions():
    """50 sessions with the paper's Sensor2 law (A 0.00265 N, b 1.201, 6 % gains, 20 %
    saturated patches), the independent simulator's parameters of issue 12."""
    inside = []
    for seed in range(50):
        train, _ = family_sessions("5051-sensor2", seed=seed)
        cal = calibrate(_points(train), n_bootstrap=50, seed=seed)
        low, high = cal.details["params_interval"]["b"]
        inside.append(low <= train.sensor.b <= high)
    assert 0.90 <= np.mean(inside) <= 0.99, np.mean(inside)


def test_parameter_intervals_reach_json_and_say_when_unbounded(tmp_path):
    from tactilecal.calibration import load_calibration

    train, _ = family_sessions("5051-sensor2", seed=0)
    cal = calibrate(_points(train), method="zvyagin", n_bootstrap=20, seed=1)
    interval = cal.details["params_interval"]
    assert interval["b"][0] < cal.params["b"] < interval["b"][1]
    assert cal.options["n_bootstrap"] == 20 and "20 refits" in interval["method"]
    cal.to_json(tmp_path / "cal.json")
    assert load_calibration(tmp_path / "cal.json").details["params_interval"] == interval
    from tactilecal.report import write_report

    html = write_report([tmp_path / "cal.json"], tmp_path / "r.html").read_text()
    assert "95 % interval" in html and f"{interval['b'][0]:.6g} .. {interval['b'][1]:.6g}" in html
    # three patches: a ninth of the resamples draw one patch thrice and cannot be fitted,
    # more than the 2.5 % tail of a 95 % interval
    clean = [p for p in _points(train) if p.saturated_cells == 0]
    few = calibrate(clean[:3], method="power", n_bootstrap=40, seed=0)
    assert "b" not in few.details["params_interval"]
    assert "refits failed, more than the 2.5% tail" in few.details["params_interval"]["unbounded"]
    assert "parameter intervals: unbounded" in few.summary()


def test_interval_reaches_json_summary_and_validate(tmp_path):
    train, test = family_sessions("5051-sensor2", seed=0)
    cal = calibrate(_points(train), method="power", n_interval_resamples=50)
    stored = cal.details["prediction_interval"]
    assert stored["rel_low"] < 0 < stored["rel_high"] and stored["level"] == 0.95
    assert "95% prediction interval of a new patch's load" in cal.summary()
    path = tmp_path / "cal.json"
    cal.to_json(path)
    from tactilecal.calibration import load_calibration

    report = validate(load_calibration(path), _points(test))
    assert 0.0 <= report["summary"]["interval_coverage"] <= 1.0
    saturated = [r for r in report["points"] if r["saturated"]]
    assert saturated and all(r["predicted_is_lower_bound"] and r["predicted_high_N"] == np.inf
                             for r in saturated)


def test_interval_needs_patches_and_a_level():
    train, _ = family_sessions("9500-b1.4", seed=0)
    with pytest.raises(ValueError, match="2 patches; a prediction interval needs at least 3"):
        prediction_interval(_points(train)[:2])
    with pytest.raises(ValueError, match=r"level=1.5; expected a probability in \(0, 1\)"):
        prediction_interval(_points(train), level=1.5)
    with pytest.raises(ValueError, match=r"n_bootstrap=-1; expected a whole number >= 0"):
        calibrate(_points(train), n_bootstrap=-1)
