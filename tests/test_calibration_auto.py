"""``method="auto"``, lack of fit said out loud, learned gains (simulated family, known truth)."""

import json
import warnings

import numpy as np
import pytest

import tactilecal as tc
from tactilecal.calibration import CalibrationPoint, calibrate, load_points, points_from_frames
from tactilecal.cli import main
from tactilecal.simulate import family_sessions


def _points(session, **kw):
    return points_from_frames(session.raw.values, session.load_N,
                              sensel_area_mm2=session.sensor.sensel_area_mm2, **kw)


def _held_out_rms(cal, session, gains=None):
    held = ~(session.raw.values >= 255).any(axis=(1, 2))
    predicted = cal.predict_force(session.raw.values[held])
    return float(np.sqrt(np.mean((predicted / session.load_N[held] - 1.0) ** 2)))


def _quiet_calibrate(points, **kw):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        cal = calibrate(points, **kw)
    return cal, [str(w.message) for w in caught]


@pytest.fixture(scope="module")
def bent():
    """Log-log curvature 0.08: held-out error of the power law 1.4 %, of a table 1.0 %."""
    return family_sessions("5051-bent", seed=0, n_test=150)


@pytest.fixture(scope="module")
def bent_auto(bent):
    """The default (auto) calibration of the bent training session and what it said."""
    train, _ = bent
    return _quiet_calibrate(_points(train))


@pytest.fixture(scope="module")
def plain():
    return family_sessions("5051-zvyagin", seed=0, n_test=150)


def test_auto_is_the_default_and_keeps_the_power_law_where_it_fits(plain):
    train, _ = plain
    cal, said = _quiet_calibrate(_points(train))
    assert cal.selection is not None and cal.selection.chosen.startswith("power")
    assert cal.method == "power" and cal.options["objective"] in ("l1", "relative", "l2")
    assert not cal.lack_of_fit.flagged and said == []
    rows = {s["candidate"]: s for s in cal.selection.scores}
    assert set(rows) == {"power:l1", "power:relative", "power:l2", "lut", "piecewise",
                         "polynomial"}
    assert all(0 < r["rms_rel"] < 0.02 for r in rows.values() if r["rms_rel"] is not None)
    text = cal.summary()
    assert "method chosen by auto" in text and "<- chosen" in text


def test_auto_follows_a_bent_response_and_says_the_power_law_does_not_fit(bent, bent_auto):
    train, test = bent
    cal, said = bent_auto
    power, _ = _quiet_calibrate(_points(train), method="power")
    assert cal.method in ("lut", "piecewise")
    assert _held_out_rms(cal, test) < 0.85 * _held_out_rms(power, test)  # measured 0.72
    assert cal.lack_of_fit.flagged
    assert any(s.startswith(f"{cal.method} calibration: no power law describes this sensor")
               for s in said), said


def test_a_bent_response_fitted_as_a_power_law_is_flagged():
    """The explicit power law on the bent sensor: its errors follow the readings.

    (Seed 1: on seed 0 the trend's p-value is 1e-3, short of the test's 1e-4; the default,
    ``auto``, says it there by its choice of a table.)
    """
    train, _ = family_sessions("5051-bent", seed=1)
    cal, said = _quiet_calibrate(_points(train), method="power")
    assert cal.lack_of_fit.flagged and cal.lack_of_fit.reading_p_value < 1e-4
    assert any("the response bends away from the law" in s for s in said)


def test_an_ascending_run_is_said_to_hide_drift():
    train, _ = family_sessions("5051-drift", seed=0)
    cal, said = _quiet_calibrate(_points(train), method="power")
    assert cal.lack_of_fit.load_order_rho > 0.9
    assert any("taken in ascending order" in s and "random order" in s for s in said)


def test_too_few_patches_fall_back_to_power_and_say_so(plain):
    train, _ = plain
    with pytest.warns(UserWarning, match=r"method='auto': 5 patches with an exact load, .*"
                                         r"too few to cross-validate .* method 'power' used"):
        cal = calibrate(_points(train)[:5])
    assert cal.method == "power" and cal.selection.chosen == "power"


def test_selection_and_lack_of_fit_survive_the_json(bent_auto, tmp_path):
    cal, _ = bent_auto
    cal.to_json(tmp_path / "cal.json")
    back = tc.load(tmp_path / "cal.json")
    assert back == cal and back.selection == cal.selection
    assert back.lack_of_fit == cal.lack_of_fit and back.lack_of_fit.flagged
    stored = json.loads((tmp_path / "cal.json").read_text())
    assert stored["selection"]["chosen"] == cal.selection.chosen
    assert stored["lack_of_fit"]["messages"] == cal.lack_of_fit.messages


def test_the_cli_says_the_choice_and_the_lack_of_fit_in_one_line_each(bent, tmp_path,
                                                                       capsys):
    train, _ = bent
    manifest = train.write(tmp_path / "session")
    assert main(["-q", "calibrate", str(manifest), "--out", str(tmp_path / "c.json")]) == 0
    out, err = capsys.readouterr()
    assert "method chosen by auto:" in out
    warning_lines = [line for line in err.splitlines() if "warning:" in line]
    assert warning_lines and all(line.startswith("tactilecal calibrate: warning: ")
                                 for line in warning_lines)
    assert any("no power law describes this sensor" in line for line in warning_lines)


def test_auto_options_are_checked():
    with pytest.raises(ValueError, match=r"candidates: 'spline' is not a method auto can "
                                         r"choose"):
        calibrate([], method="auto", candidates=("power:l1", "spline"))
    with pytest.raises(ValueError, match=r"objective='cv' is not an option of power"):
        calibrate([], method="auto", candidates=("power:cv",))
    with pytest.raises(ValueError, match=r"folds=1; expected a whole number >= 2"):
        calibrate([], method="auto", folds=1)


# ---------------------------------------------------------------- learned gains
def test_learned_gains_remove_an_edge_field():
    """Edges 15 % less sensitive: the learned map takes the held-out error below half."""
    train, test = family_sessions("5051-edges", seed=1, n_test=150)
    plain_cal, _ = _quiet_calibrate(_points(train), method="power", objective="relative")
    learned, _ = _quiet_calibrate(_points(train), method="power", objective="relative",
                                  gains="learn")
    assert learned.diagnostics["gains"]["chosen"] != "none"
    ratio = _held_out_rms(learned, test) / _held_out_rms(plain_cal, test)
    assert ratio < 0.5, ratio  # measured 0.25
    gain = learned.equilibration.gain
    centre, edge = np.nanmean(gain[18:26, 18:26]), np.nanmean(gain[:, :2])
    assert edge / centre > 1.08  # the map raises the edges' readings (truth 1 / 0.85)


def test_learned_gains_do_no_harm_without_a_gain_field(plain):
    train, test = plain
    base, _ = _quiet_calibrate(_points(train), method="power", objective="relative")
    learned, _ = _quiet_calibrate(_points(train), method="power", objective="relative",
                                  gains="learn")
    assert _held_out_rms(learned, test) <= 1.02 * _held_out_rms(base, test)


def test_learned_gains_need_the_frames(plain, tmp_path):
    train, _ = plain
    bare = [CalibrationPoint(histogram=p.histogram, load_N=p.load_N, raw_sum=p.raw_sum,
                             loaded_cells=p.loaded_cells, saturated_cells=p.saturated_cells)
            for p in _points(train)]
    with pytest.raises(ValueError, match=r"gains='learn' needs the frames of the points"):
        calibrate(bare, gains="learn")
    manifest = train.write(tmp_path / "s")
    assert all(p.readings is not None for p in load_points(manifest))


def test_learned_gains_through_the_manifest_and_the_cli_are_applied(tmp_path, capsys):
    train, test = family_sessions("5051-edges", seed=1, n_test=60)
    manifest = train.write(tmp_path / "s")
    out = tmp_path / "cal.json"
    assert main(["-q", "calibrate", str(manifest), "--method", "power", "--learn-gains",
                 "--out", str(out)]) == 0
    capsys.readouterr()
    cal = tc.load(out)
    api, _ = _quiet_calibrate(manifest, method="power", gains="learn")
    np.testing.assert_allclose(cal.equilibration.gain, api.equilibration.gain, rtol=1e-12)
    assert cal.options["gains"] == "learn"
    # apply() corrects the readings with the learned gains before the law
    rec = test.raw.isel(frame=[0])
    expected = cal.predict_histograms(tc.calibration.frame_histograms(
        cal.equilibration.apply(rec.values)))
    assert float(cal.predict_force(rec.values)[0]) == pytest.approx(expected[0], rel=0.02)


# ---------------------------------------------------------------- movie: periodic loads
@pytest.fixture(scope="module")
def gait():
    """A knee simulator's 2 s cycle, 20 cycles: 20 Hz frames, a 100 Hz load cell 0.37 s late.

    The patch keeps its shape; its load follows the cycle, so the frames' sum correlates
    with the load record almost as well at every whole cycle of lag.
    """
    from tactilecal.simulate import make_sensor

    sensor = make_sensor("5051", gain_spread=0.03, seed=3)
    rows, cols = np.mgrid[:44, :44]
    shape = np.exp(-((rows - 22) ** 2 + (cols - 20) ** 2) / 40.0)
    shape /= shape.sum()

    def cycle(t):
        phase = (t % 2.0) / 2.0
        return 20.0 + 180.0 * np.sin(np.pi * np.clip(phase / 0.6, 0, 1)) ** 2

    t_frames = np.arange(800) / 20.0
    raw = sensor.read(cycle(t_frames)[:, None, None] * shape, np.random.default_rng(4))
    recording = sensor.to_dataarray(raw, time_s=t_frames, source="gait")
    t_cell = np.arange(0.0, 40.0, 0.01)
    load = cycle(t_cell) + np.random.default_rng(5).normal(0, 0.5, t_cell.size)
    import xarray as xr

    record = xr.DataArray(load, dims="time", coords={"time": t_cell + 0.37},
                          attrs={"units": "N"})
    return recording, record


def test_a_periodic_load_takes_the_lag_that_keeps_the_record(gait):
    recording, record = gait
    with pytest.warns(UserWarning, match=r"the lag is ambiguous: \d+ near-equal correlation "
                                         r"peaks .* 2 s apart \(a periodic loading\); took"):
        cal = calibrate_movie_quiet(recording, record)
    movie = cal.diagnostics["movie"]
    assert movie["lag_s_raw_sum"] == pytest.approx(-0.37, abs=0.06)
    assert movie["lag_s"] == pytest.approx(-0.37, abs=0.03)
    # only the frames the shifted record does not cover are outside it: 0.37 s of 40
    assert movie["n_outside_load_record"] <= 9
    assert "the lag is ambiguous" in movie["lag_note"] and "lag is ambiguous" in cal.summary()


def calibrate_movie_quiet(recording, record, **kw):
    """calibrate_movie with every warning but the lag's silenced (lack of fit of a gait)."""
    from tactilecal.calibration import calibrate_movie

    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", message=".*calibration: ")
        return calibrate_movie(recording, record, method="power", **kw)


def test_a_time_and_load_window_choose_the_frames_fitted(gait):
    recording, record = gait
    with pytest.warns(UserWarning, match="the lag is ambiguous"):
        whole = calibrate_movie_quiet(recording, record)
    with pytest.warns(UserWarning, match="the lag is ambiguous"):
        part = calibrate_movie_quiet(recording, record, from_s=10.0, to_s=20.0,
                                     min_load_N=100.0)
    frames = part.points["frame"].to_numpy()
    times = recording["time"].values[frames - 1]
    assert times.min() >= 10.0 and times.max() <= 20.0
    assert part.points["load_N"].min() >= 100.0
    movie = part.diagnostics["movie"]
    assert movie["n_outside_window"] == len(whole.points) - len(part.points)
    assert movie["window"] == {"from_s": 10.0, "to_s": 20.0, "min_load_N": 100.0}


def test_a_candidate_failing_on_a_later_fold_is_dropped_without_a_warning(plain, monkeypatch):
    """Its unwritten errors were once squared: uninitialised memory, now and then an overflow
    warning from the user's call (seed 0 of 9500-b1.4, whose polynomial fails on fold 4)."""
    from tactilecal.calibration.methods import polynomial

    fit, calls = polynomial.fit, []

    def fails_second(train, options):
        calls.append(1)
        if len(calls) == 2:
            raise tc.TactilecalError("singular on this fold")
        return fit(train, options)

    monkeypatch.setattr(polynomial, "fit", fails_second)
    train, _ = plain
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        cal = calibrate(_points(train), method="auto", n_interval_resamples=0)
    assert len(calls) == 2  # not fitted again after its failure
    row, = (s for s in cal.selection.scores if s["candidate"].startswith("polynomial"))
    assert row["rms_rel"] is None and "singular on this fold" in row["note"]
    assert all(s["rms_rel"] > 0 for s in cal.selection.scores if s is not row)
