"""Prediction intervals that hold (issue 12): coverage over 50 simulated sessions."""


import numpy as np
import pytest

from tactilecal import calibrate
from tactilecal.calibration import points_from_frames, prediction_interval, validate
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
