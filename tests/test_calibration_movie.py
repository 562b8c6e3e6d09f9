"""Movie calibration: align, resample, trim, fit every frame; I-Scan's count-mismatch error."""

import hashlib

import numpy as np
import pytest

import tactilecal.calibration._movie as movie_module
from tactilecal.calibration import (
    CalibrationPoint,
    Equilibration,
    calibrate,
    calibrate_movie,
    frame_histograms,
    header_calibration,
)
from tactilecal.calibration._movie import movie_points, read_movie_loads
from tactilecal.io import read_tekscan
from tactilecal.simulate import make_sensor, ramp_hold


@pytest.fixture(scope="module")
def session():
    return ramp_hold(make_sensor("5051", seed=0), seed=1)


def test_movie_recovers_law_and_lag(session):
    res = calibrate_movie(session.raw, session.loadcell, method="power")
    movie = res.diagnostics["movie"]
    # lag within one frame (10 ms) of the simulated load-cell start offset
    assert movie["lag_s"] == pytest.approx(session.loadcell_start_offset_s, abs=0.01)
    assert res.params["b"] == pytest.approx(1.16, abs=0.005)
    assert res.params["A"] == pytest.approx(0.0035, rel=0.02)
    assert movie["n_points"] + movie["n_outside_load_record"] + movie["n_below_load_floor"] \
        == session.raw.sizes["frame"]
    assert res.metrics["median_abs_error_pct"] < 0.5
    assert "frames outside the load record" in movie["report"]


def test_movie_one_load_per_frame(session, tmp_path, assert_names_by_bytes):
    path = tmp_path / "loads.csv"
    path.write_text("Load (N)\n" + "\n".join(f"{v:.6f}" for v in session.load_N) + "\n")
    loads = read_movie_loads(path)
    assert isinstance(loads, np.ndarray) and len(loads) == session.raw.sizes["frame"]
    res = calibrate_movie(session.raw, path, method="power")
    assert res.diagnostics["movie"]["lag_s"] is None
    assert res.params["b"] == pytest.approx(1.16, abs=0.005)
    assert_names_by_bytes(res.provenance, [path])  # the movie was made in memory
    path.write_text("Load (N)\n" + "\n".join(f"{v:.6f}" for v in session.load_N[:-1]) + "\n")
    with pytest.raises(ValueError, match="loads have 2399 values and no time column; "
                                         "expected 2400 "):
        calibrate_movie(session.raw, path, method="power")
    path.write_text("Load (kPa)\n1\n2\n")
    with pytest.raises(ValueError, match="is in 'kPa'; expected a force or mass unit"):
        read_movie_loads(path)
    path.write_text("Load (N)\n1\nx\n")
    with pytest.raises(ValueError, match="line 3 of .*loads.csv: load 'x' is not a number"):
        read_movie_loads(path)


def test_movie_saturated_frames_trimmed(session):
    raw = session.raw.copy()
    raw[1500:1510, 20, 20] = 255.0
    res = calibrate_movie(raw, session.loadcell, lag_s=session.loadcell_start_offset_s,
                          method="power")
    table = res.points
    sat = table["saturated_cells"] > 0
    assert sat.sum() == 10 and not table.loc[sat, "used"].any()
    assert table.loc[sat, "reason"].str.startswith("saturated").all()
    assert res.diagnostics["movie"]["lag_s"] == session.loadcell_start_offset_s


def test_movie_dask_recording_gives_same_fit(session):
    lazy = session.raw.chunk({"frame": 500})
    a = calibrate_movie(session.raw, session.loadcell, lag_s=0.37, method="power")
    b = calibrate_movie(lazy, session.loadcell, lag_s=0.37, method="power")
    assert type(lazy.data).__name__ == "Array"
    assert a.params == b.params


# ------------------------------------------------ same calibration as the definition
def _reference_histograms(frames):
    """Per-frame np.bincount of the rounded finite readings (what frame_histograms defines)."""
    flat = np.asarray(frames, dtype=float).reshape(len(frames), -1)
    return np.stack([np.bincount(np.rint(f[np.isfinite(f)]).astype(int), minlength=256)
                     for f in flat])


_REFERENCES = {}


def _reference_calibration(raw, load_N, *, min_load_fraction=0.02, area=np.nan, **options):
    """calibrate() on points made from reference histograms of the frames movie keeps.

    Computed once per distinct input (the frames' values, the loads and the options): the
    storage and counting variants of a test compare their calibrations with the same one.
    """
    frames, load_N = np.asarray(raw, dtype=float), np.asarray(load_N, dtype=float)
    key = (frames.shape, hashlib.blake2b(frames.tobytes()).hexdigest(),
           hashlib.blake2b(load_N.tobytes()).hexdigest(), min_load_fraction, repr(area),
           tuple(sorted(options.items())))
    if key not in _REFERENCES:
        _REFERENCES[key] = _reference_calibration_of(frames, load_N, min_load_fraction, area,
                                                     options)
    return _REFERENCES[key]


def _reference_calibration_of(raw, load_N, min_load_fraction, area, options):
    hist = _reference_histograms(raw)
    keep = load_N >= min_load_fraction * load_N.max()
    total = int(np.isfinite(np.asarray(raw[0], dtype=float)).sum())
    points = [CalibrationPoint(histogram=h, load_N=float(f), raw_sum=float(h @ np.arange(256)),
                               loaded_cells=int(h[1:].sum()), saturated_cells=int(h[255]),
                               frame=i + 1, sensel_area_mm2=area, working_cells=int(h.sum()),
                               total_cells=total)
              for i, (h, f) in enumerate(zip(hist, load_N, strict=True)) if keep[i]]
    return calibrate(points, **{"method": "power", **options})


def _assert_same_calibration(new, ref):
    assert new.params.keys() == ref.params.keys()
    for key, value in ref.params.items():
        assert new.params[key] == pytest.approx(value, rel=1e-9, abs=0)
    a, b = new.points, ref.points
    for column in ("frame", "raw_sum", "loaded_cells", "saturated_cells", "used"):
        np.testing.assert_array_equal(a[column].to_numpy(), b[column].to_numpy())
    np.testing.assert_allclose(a["predicted_N"], b["predicted_N"], rtol=1e-9, atol=0)


@pytest.fixture(scope="module")
def shaped(session):
    """The session's movie with NaN cells outside a shape and saturated frames."""
    raw = session.raw.copy()
    raw[:, :3, :5] = np.nan
    raw[1500:1510, 20, 20] = 255.0
    return raw


@pytest.fixture(params=["numpy", "compiled"])
def counting(request, monkeypatch):
    """Force the histogram counting path (the session's movie is below the size switch)."""
    import tactilecal.calibration._histogram as histogram

    monkeypatch.setattr(histogram, "COMPILED_MIN_VALUES",
                        0 if request.param == "compiled" else 2 ** 62)
    return request.param


@pytest.mark.parametrize("storage", ["float64", "float32", "uint8", "dask"])
def test_movie_equals_reference_calibration_one_load_per_frame(session, shaped, storage,
                                                               counting):
    raw = shaped
    if storage == "uint8":
        raw = session.raw.astype(np.uint8)
    elif storage == "float32":
        raw = shaped.astype(np.float32)
    elif storage == "dask":
        raw = shaped.chunk({"frame": 333, "row": 20})  # blocks split frames and rows
    res = calibrate_movie(raw, session.load_N, objective="l2", method="power")
    ref = _reference_calibration(np.asarray(raw), session.load_N, objective="l2",
                                 area=raw.attrs["sensel_area_mm2"])
    _assert_same_calibration(res, ref)
    assert res.diagnostics["movie"]["n_saturated_frames"] == (0 if storage == "uint8" else 10)


def test_movie_with_mask_and_equilibration_equals_reference(session, shaped, counting):
    gain = np.random.default_rng(5).uniform(0.9, 1.1, shaped.shape[1:])
    gain[10, 10] = np.nan
    eq = Equilibration(gain=gain)
    dead = np.zeros(shaped.shape[1:], bool)
    dead[30, 12] = True
    prepared = eq.apply(shaped.values)
    prepared[:, dead] = np.nan
    ref = _reference_calibration(prepared, session.load_N, area=shaped.attrs["sensel_area_mm2"],
                                 method="power")  # the points are compared, not the choice
    keep = session.load_N >= 0.02 * session.load_N.max()
    expected = _reference_histograms(prepared)[keep]
    for raw in (shaped, shaped.chunk({"frame": 500})):
        points, _ = movie_points(raw, session.load_N, mask=dead, equilibration=eq)
        hist = np.stack([p.histogram for p in points])
        np.testing.assert_array_equal(hist, expected)
        _assert_same_calibration(calibrate(points, method="power"), ref)


def test_aligned_movie_equals_movie_on_reference_histograms(session, shaped, monkeypatch):
    """The two-pass alignment (raw sum, then calibrated force) with reference histograms."""
    new = calibrate_movie(shaped, session.loadcell, method="power")

    calls = []

    def reference(values, *, out, prepare=None, mask=None, compiled=None):
        calls.append(len(values))
        out[...] = _reference_histograms(values)
        return out

    monkeypatch.setattr(movie_module, "_frame_histograms", reference)
    ref = calibrate_movie(shaped, session.loadcell, method="power")
    assert sum(calls) == shaped.sizes["frame"]
    assert new.diagnostics["movie"]["lag_s"] == ref.diagnostics["movie"]["lag_s"]
    assert new.diagnostics["movie"]["lag_s_raw_sum"] == ref.diagnostics["movie"]["lag_s_raw_sum"]
    _assert_same_calibration(new, ref)


def test_real_iscan_movie_equals_reference(iscan_csv, counting):
    rec = read_tekscan(iscan_csv)
    raw = rec.values
    assert np.isnan(raw).any()  # cells outside the sensor shape
    np.testing.assert_array_equal(frame_histograms(raw), _reference_histograms(raw))
    # a known law: loads that a power law gives on these real frames
    load = 0.0035 * np.nansum(raw ** 1.16, axis=(1, 2))
    res = calibrate_movie(rec, load, objective="l2", method="power")
    _assert_same_calibration(res, _reference_calibration(
        raw, load, objective="l2", area=rec.attrs["sensel_area_mm2"]))
    assert res.params["b"] == pytest.approx(1.16, rel=1e-6)


@pytest.mark.parametrize("which", ["fscan_asf", "fscan_right_asf"])
def test_real_fscan_frames_histograms_equal_reference(which, request, counting):
    rec = read_tekscan(request.getfixturevalue(which))
    cal = header_calibration(rec)
    raw = rec.values / (cal.params["A"] / cal.sensel_area_mm2 * 1000)  # kPa -> raw counts
    assert np.isnan(raw).any()
    np.testing.assert_array_equal(frame_histograms(raw), _reference_histograms(raw))
    lazy = rec.copy(data=raw).chunk({"frame": 50}).assign_attrs(units="raw")
    load = 0.0035 * np.nansum(np.rint(raw) ** 1.2, axis=(1, 2))
    res = calibrate_movie(lazy, load, objective="relative", method="power")
    _assert_same_calibration(res, _reference_calibration(
        raw, load, objective="relative", area=rec.attrs["sensel_area_mm2"]))


def test_first_alignment_on_a_decimated_raw_sum_finds_the_lag():
    """A 4 kHz raw sum averaged to 2 kHz (4 x the 500 Hz load cell) keeps the known lag."""
    import xarray as xr

    from tactilecal.calibration._movie import _decimated
    from tactilecal.dynamic import estimate_lag

    def two_steps(t):
        return 1 / (1 + np.exp(-(t - 3) / 0.2)) + 0.5 / (1 + np.exp(-(t - 6) / 0.2))

    t = np.arange(40_000) / 4000.0
    t_ref = np.arange(0.0, 9.0, 1 / 500)
    true_lag_s = 0.37  # added to the load cell's stamps, it puts them on the sensor's clock
    ref = xr.DataArray(two_steps(t_ref + true_lag_s), dims="time", coords={"time": t_ref})
    total, at = _decimated(two_steps(t), t, 4 * 500.0)
    assert len(total) == 20_000 and at[1] - at[0] == pytest.approx(1 / 2000)
    sensor = xr.DataArray(total, dims="time", coords={"time": at})
    assert estimate_lag(sensor, ref) == pytest.approx(true_lag_s, abs=1.25e-4)  # 1/2 frame
    head, at_head = total[:100], at[:100]
    assert _decimated(head, at_head, 4 * 500.0) == (head, at_head)  # 2 kHz already
