"""Prediction intervals that hold (issue 12): coverage over 50 simulated sessions; no
parameter intervals (they did not hold)."""


import numpy as np
import pytest

from tactilecal import calibrate
from tactilecal.calibration import points_from_frames, validate
from tactilecal.calibration._uncertainty import prediction_interval
from tactilecal.simulate import family_sessions


def _points(session):
    return points_from_frames(session.raw.values, session.load_N,
                              sensel_area_mm2=session.sensor.sensel_area_mm2)


def _coverage(seeds):
    """Share of unsaturated held-out patches inside the 95 % prediction interval, over the
    sessions ``seeds`` of the family's hardest-gain member (9500, b 1.4, 12 % gains, noise 1)."""
    inside = []
    for seed in seeds:
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
    return float(np.mean(inside)), len(inside)


@pytest.mark.slow
def test_95pct_prediction_interval_holds_90_to_99pct_of_held_out_patches():
    """50 sessions (1,800 held-out patches): measured 0.924."""
    coverage, n = _coverage(range(50))
    assert n > 1000
    assert 0.90 <= coverage <= 0.99, coverage


def test_95pct_prediction_interval_on_the_first_ten_sessions():
    """The fast check of the same interval: a session's coverage varies (standard deviation
    0.071 over the 50 sessions above), so the mean of 10 has a standard error of 0.023; the
    band is the 50-session coverage 0.924 +- 3 of those, capped at 0.99. Measured 0.864."""
    coverage, n = _coverage(range(10))
    assert n == 360
    assert 0.855 <= coverage <= 0.99, coverage


def test_no_parameter_interval_is_reported_and_the_json_says_why(tmp_path):
    """Issue 12's rule: the bootstrap interval of b held the truth in only 0.38-0.82 of 50
    sessions on two family members (benchmarks/bench_static_family.py --coverage 50), so
    no method reports one; the keys stay, as null, with the reason."""
    from tactilecal.calibration import load_calibration
    from tactilecal.report import write_report

    train, _ = family_sessions("5051-sensor2", seed=0)
    for method in ("power", "zvyagin"):
        cal = calibrate(_points(train), method=method, n_bootstrap=20, seed=1)
        assert cal.params_stderr == {"A": None, "b": None}
        assert cal.details["params_interval"] is None and cal.options["n_bootstrap"] == 20
        assert cal.details["stderr_method"].startswith("none: no parameter interval held")
        assert "parameter intervals: none: no parameter interval held" in cal.summary()
        assert "interval" not in cal.summary().split("b = ")[1].splitlines()[0]
        cal.to_json(tmp_path / f"{method}.json")
        loaded = load_calibration(tmp_path / f"{method}.json")
        assert loaded.details["params_interval"] is None and \
            loaded.params_stderr == {"A": None, "b": None}
        assert loaded.details["stderr_method"] == cal.details["stderr_method"]
    single = calibrate(_points(train))  # without n_bootstrap: the same keys, no summary line
    assert single.details["params_interval"] is None and not single.options["n_bootstrap"]
    assert "parameter intervals" not in single.summary()
    html = write_report([tmp_path / "zvyagin.json"], tmp_path / "r.html").read_text()
    assert "none (no interval of b held 90-99 % in simulation)" in html


def test_a_calibration_saved_with_an_interval_still_shows_it(tmp_path):
    from tactilecal.calibration import load_calibration

    train, _ = family_sessions("5051-sensor2", seed=0)
    cal = calibrate(_points(train))
    cal.details["params_interval"] = {"level": 0.95, "method": "normal bootstrap over patches "
                                      "(20 refits, 0 failed)", "A": [0.002, 0.003],
                                      "b": [1.1, 1.3]}
    cal.to_json(tmp_path / "old.json")
    summary = load_calibration(tmp_path / "old.json").summary()
    assert "(95% interval 1.1 .. 1.3)" in summary
    assert "parameter intervals: normal bootstrap over patches (20 refits" in summary
    cal.details["params_interval"] = {"level": 0.95, "method": "m", "unbounded": "3 of 40 failed"}
    assert "parameter intervals: unbounded (3 of 40 failed)" in cal.summary()


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
    assert 0.0 <= report.metrics["interval_coverage"] <= 1.0
    saturated = [r for r in report.points if r["saturated"]]
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
