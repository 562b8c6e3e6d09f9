"""Movie calibration: align, resample, trim, fit every frame; I-Scan's count-mismatch error."""

import numpy as np
import pytest

from tactilecal.calibration import calibrate_movie, read_movie_loads
from tactilecal.simulate import make_sensor, ramp_hold


@pytest.fixture(scope="module")
def session():
    return ramp_hold(make_sensor("5051", seed=0), seed=1)


def test_movie_recovers_law_and_lag(session):
    res = calibrate_movie(session.raw, session.loadcell)
    movie = res.details["movie"]
    # lag within one frame (10 ms) of the simulated load-cell start offset
    assert movie["lag_s"] == pytest.approx(session.loadcell_start_offset_s, abs=0.01)
    assert res.params["b"] == pytest.approx(1.16, abs=0.005)
    assert res.params["A"] == pytest.approx(0.0035, rel=0.02)
    assert movie["n_points"] + movie["n_outside_load_record"] + movie["n_below_load_floor"] \
        == session.raw.sizes["frame"]
    assert res.metrics["median_abs_error_pct"] < 0.5
    assert "frames outside the load record" in movie["report"]


def test_movie_one_load_per_frame(session, tmp_path):
    path = tmp_path / "loads.csv"
    path.write_text("Load (N)\n" + "\n".join(f"{v:.6f}" for v in session.load_N) + "\n")
    loads = read_movie_loads(path)
    assert isinstance(loads, np.ndarray) and len(loads) == session.raw.sizes["frame"]
    res = calibrate_movie(session.raw, path)
    assert res.details["movie"]["lag_s"] is None
    assert res.params["b"] == pytest.approx(1.16, abs=0.005)
    path.write_text("Load (N)\n" + "\n".join(f"{v:.6f}" for v in session.load_N[:-1]) + "\n")
    with pytest.raises(ValueError, match="loads have 2399 values and no time column; "
                                         "expected 2400 "):
        calibrate_movie(session.raw, path)
    path.write_text("Load (kPa)\n1\n2\n")
    with pytest.raises(ValueError, match="is in 'kPa'; expected a force or mass unit"):
        read_movie_loads(path)
    path.write_text("Load (N)\n1\nx\n")
    with pytest.raises(ValueError, match="line 3 of .*loads.csv: load 'x' is not a number"):
        read_movie_loads(path)


def test_movie_saturated_frames_trimmed(session):
    raw = session.raw.copy()
    raw[1500:1510, 20, 20] = 255.0
    res = calibrate_movie(raw, session.loadcell, lag_s=session.loadcell_start_offset_s)
    table = res.points
    sat = table["saturated_cells"] > 0
    assert sat.sum() == 10 and not table.loc[sat, "used"].any()
    assert table.loc[sat, "reason"].str.startswith("saturated").all()
    assert res.details["movie"]["lag_s"] == session.loadcell_start_offset_s


def test_movie_dask_recording_gives_same_fit(session):
    lazy = session.raw.chunk({"frame": 500})
    a = calibrate_movie(session.raw, session.loadcell, lag_s=0.37)
    b = calibrate_movie(lazy, session.loadcell, lag_s=0.37)
    assert type(lazy.data).__name__ == "Array"
    assert a.params == b.params
