"""One result base for every saved thing: tags, tactilecal.load, legacy files, reprs."""

import json
import warnings

import numpy as np
import pandas as pd
import pytest

import tactilecal
from tactilecal.calibration import (
    CalibrationResult,
    Equilibration,
    NonWorkingSensels,
    ValidationResult,
    calibrate,
    equilibrate,
    find_dead_sensels,
    points_from_frames,
    validate,
)
from tactilecal.calibration.methods.zvyagin import ZvyaginResult
from tactilecal.dynamic import CorrectionFilter, Evaluation
from tactilecal.simulate import deadweight_session, make_sensor

PLAIN = (float, int, bool, str, type(None))


@pytest.fixture(scope="module")
def session():
    sensor = make_sensor("5051", seed=1, n_dead=3)
    return deadweight_session(sensor, n_patches=40, seed=2)


@pytest.fixture(scope="module")
def points(session):
    return points_from_frames(session.raw, session.load_N)


@pytest.fixture(scope="module")
def calibrations(points):
    with warnings.catch_warnings():  # a linear law on a power-law sensor does not fit
        warnings.simplefilter("ignore", UserWarning)
        return {method: calibrate(points, method=method)
                for method in ("power", "linear", "lut", "polynomial", "zvyagin")}


def _equilibration():
    gains = np.array([[0.9, 1.0, 1.1], [1.0, 1.2, np.nan]])
    frames = [np.nan_to_num(level * gains[None] ** -1, nan=0.0) for level in (40.0, 80.0)]
    return equilibrate(frames)


def _filters():
    log = CorrectionFilter.from_model(("log10", {"A": 0.11}), fs_hz=4000, band_hz=(1, 140))
    f_hz = np.linspace(1.0, 100.0, 12)
    measured = CorrectionFilter.from_response(f_hz, 1.0 + 0.002 * f_hz, fs_hz=1000)
    return [log, measured]


def _write_and_load(obj, tmp_path, name):
    path = tmp_path / name
    obj.to_json(path)
    return path, tactilecal.load(path)


# ---------------------------------------------------------------- round trips
@pytest.mark.parametrize("method", ["power", "linear", "lut", "polynomial", "zvyagin"])
def test_calibration_round_trips_through_load(calibrations, tmp_path, method):
    cal = calibrations[method]
    path, back = _write_and_load(cal, tmp_path, "cal.json")
    assert isinstance(back, CalibrationResult)
    assert json.loads(path.read_text())["format"] == "tactilecal-calibration/1"
    assert back.params == cal.params
    np.testing.assert_array_equal(back.force_table(), cal.force_table())
    pd.testing.assert_frame_equal(back.points, cal.points, check_dtype=False)
    assert back.to_dict() == cal.to_dict()


def test_equilibration_round_trips_through_load(tmp_path):
    eq = _equilibration()
    path, back = _write_and_load(eq, tmp_path, "eq.json")
    assert isinstance(back, Equilibration)
    assert json.loads(path.read_text())["format"] == "tactilecal-equilibration/1"
    np.testing.assert_array_equal(back.gain, eq.gain)  # NaN (no gain) where it was NaN
    assert back.levels == eq.levels


def _dead():
    frames = np.full((3, 5, 6), 20.0)
    frames[:, 2, 2] = frames[:, 1, 4] = 0.0  # two sensels that never respond
    return find_dead_sensels(frames)


def test_non_working_sensels_round_trip_through_load(tmp_path):
    dead = _dead()
    assert dead.sensels == [[1, 4], [2, 2]]
    _, back = _write_and_load(dead, tmp_path, "dead.json")
    assert isinstance(back, NonWorkingSensels)
    np.testing.assert_array_equal(back.mask, dead.mask)
    np.testing.assert_array_equal(back.evidence_frames[dead.mask],
                                  dead.evidence_frames[dead.mask])
    assert back.n_frames == dead.n_frames


@pytest.mark.parametrize("k", [0, 1])
def test_filter_round_trips_through_load(tmp_path, k):
    filt = _filters()[k]
    path, back = _write_and_load(filt, tmp_path, "FILTER.json")
    assert isinstance(back, CorrectionFilter)
    assert back.model == filt.model and back.params == filt.params
    np.testing.assert_allclose(back.taps, filt.taps, rtol=0, atol=1e-15)
    # save() and to_json() write the same file
    filt.to_json(tmp_path / "saved.json")
    assert (tmp_path / "saved.json").read_text() == path.read_text()


def test_validation_round_trips_through_load(calibrations, points, tmp_path):
    out = validate(calibrations["power"], points)
    path, back = _write_and_load(out, tmp_path, "validation.json")
    assert isinstance(back, ValidationResult)
    assert json.loads(path.read_text())["format"] == "tactilecal-validation/1"
    assert back.metrics == out.metrics
    assert back.points == out.points


# ---------------------------------------------------------------- validation values
def test_validation_holds_plain_python_values():
    from importlib.resources import files

    from tactilecal.calibration import load_points

    manifest = files("tactilecal") / "data" / "demo" / "session-a" / "manifest.csv"
    points = load_points(manifest)  # file names, labels, frames from a manifest
    out = validate(calibrate(points[:40]), points[40:])
    assert 0.0 <= out.metrics["within_5pct"] <= 1.0
    values = list(out.metrics.values()) + [v for row in out.points for v in row.values()]
    assert all(type(v) in PLAIN for v in values), {type(v) for v in values}
    json.dumps(out.to_dict())  # plain Python: the standard library serialises it
    assert isinstance(out.summary(), str) and "within 5 %" in out.summary()


# ---------------------------------------------------------------- files without the tag
def test_files_without_the_format_tag_are_refused(calibrations, points, tmp_path):
    cal = calibrations["zvyagin"].to_dict()
    eq = _equilibration().to_dict()
    val = validate(calibrations["power"], points).to_dict()
    for name, data, cls in (("cal.json", cal, CalibrationResult),
                            ("eq.json", eq, Equilibration),
                            ("val.json", val, ValidationResult)):
        del data["format"]
        (tmp_path / name).write_text(json.dumps(data))
        with pytest.raises(ValueError, match=f"{name} has no key 'format'; expected a "):
            tactilecal.load(tmp_path / name)
        with pytest.raises(ValueError, match=f"{name} has no key 'format'; expected "
                                             f"{cls.DESCRIPTION}"):
            cls.from_json(tmp_path / name)


def test_non_working_sensels_need_their_shape():
    old = {"format": "tactilecal-non-working-sensels/1", "sensels": [[1, 2], [3, 0]],
           "n_frames": 7, "evidence_frames": [4, 6]}
    with pytest.raises(ValueError, match=r"lacks the keys \['shape'\]"):
        NonWorkingSensels.from_dict(old)


def test_filter_file_of_an_earlier_version_loads(tmp_path):
    """FILTER.json always carried the tag: a file without "format" is not a filter."""
    data = _filters()[0].to_dict()
    (tmp_path / "FILTER.json").write_text(json.dumps(data, default=np.ndarray.tolist))
    assert CorrectionFilter.from_json(tmp_path / "FILTER.json").params == {"A": 0.11}


# ---------------------------------------------------------------- bad files
def _json(tmp_path, data, name="x.json"):
    path = tmp_path / name
    path.write_text(data if isinstance(data, str) else json.dumps(data))
    return path


@pytest.mark.parametrize(("data", "match"), [
    ("{not json", r"x.json: not valid JSON"),
    ("[1, 2]", r"x.json: JSON list; expected an object"),
    ({"format": "tactilecal-spline/1"}, r"key 'format' of .*x.json is 'tactilecal-spline/1', "
                                        r"a kind this tactilecal does not know"),
    ({"format": "calibration v2"}, r"key 'format' of .*x.json is 'calibration v2'; expected "
                                   r"'tactilecal-<kind>/<version>'"),
    ({"format": 3}, r"key 'format' of .*x.json is 3; expected 'tactilecal-<kind>/"),
    ({"a": 1}, r"x.json has no key 'format'; expected a tactilecal result JSON"),
    ({"format": "tactilecal-calibration/1", "model": "power"},
     r"x.json lacks the keys \['method', 'params', "),
    ({"format": "tactilecal-calibration/2"}, r"key 'format' of .*x.json is "
                                             r"'tactilecal-calibration/2', newer than"),
    ({"format": "tactilecal-validation/1", "points": []}, r"x.json lacks the keys "
                                                          r"\['summary'\]"),
])
def test_load_bad_file_is_one_line_naming_file_and_key(tmp_path, data, match):
    with pytest.raises(ValueError, match=match) as err:
        tactilecal.load(_json(tmp_path, data))
    assert "\n" not in str(err.value)


def test_a_file_of_another_kind_is_refused_naming_both_tags(calibrations, tmp_path):
    path = tmp_path / "eq.json"
    _equilibration().to_json(path)
    with pytest.raises(ValueError, match=r"key 'format' of .*eq.json is "
                                         r"'tactilecal-equilibration/1'; expected "
                                         r"'tactilecal-calibration/1'"):
        CalibrationResult.from_json(path)
    calibrations["power"].to_json(tmp_path / "cal.json")
    with pytest.raises(ValueError, match=r"key 'format' of .*cal.json is "
                                         r"'tactilecal-calibration/1'; expected "
                                         r"'tactilecal-equilibration/1'"):
        Equilibration.from_json(tmp_path / "cal.json")
    with pytest.raises(ValueError, match=r"cal.json: not a tactilecal dynamic filter"):
        CorrectionFilter.from_json(tmp_path / "cal.json")


def test_zvyagin_details_that_cannot_be_read_name_the_key(calibrations, tmp_path):
    data = calibrations["zvyagin"].to_dict()
    del data["diagnostics"]["patches"]
    with pytest.raises(ValueError, match=r"key 'diagnostics' of .*z.json: the Zvyagin "
                                         r"intermediates cannot be read \(KeyError"):
        CalibrationResult.from_json(_json(tmp_path, data, "z.json"))


# ---------------------------------------------------------------- Zvyagin on the result
def test_zvyagin_result_is_the_calibrations_method_result(calibrations, tmp_path):
    cal = calibrations["zvyagin"]
    res = cal.method_result
    assert isinstance(res, ZvyaginResult)
    assert (res.A0, res.b0) == (cal.params["A"], cal.params["b"])
    # p_s (eq. 16) in kPa is the calibration's saturation pressure; MPa kept beside it
    assert res.p_s_kPa == pytest.approx(cal.saturation_pressure_kPa, rel=1e-12)
    assert res.p_s_MPa == pytest.approx(res.p_s_kPa / 1000.0, rel=1e-12)
    cal.to_json(tmp_path / "z.json")
    back = CalibrationResult.from_json(tmp_path / "z.json").method_result
    assert back.summary() == res.summary()
    np.testing.assert_array_equal(back.usable, res.usable)
    assert calibrations["power"].method_result is None


def test_zvyagin_diagnostics_are_its_intermediates(calibrations):
    cal = calibrations["zvyagin"]
    assert set(cal.diagnostics) == set(cal.method_result.to_details())


# ---------------------------------------------------------------- text and reprs
def _everything(calibrations, points):
    return [*calibrations.values(), calibrations["zvyagin"].method_result, _equilibration(),
            _dead(), *_filters(), validate(calibrations["power"], points)]


def test_every_repr_is_short_and_every_summary_is_text(calibrations, points):
    for obj in _everything(calibrations, points):
        text = repr(obj)
        assert len(text) < 1000, (type(obj).__name__, len(text))
        assert text.startswith(f"<{type(obj).__name__} ")
        assert isinstance(obj.summary(), str) and obj.summary()
        html = obj._repr_html_()
        assert html.startswith("<table>") and type(obj).__name__ in html


def test_a_point_and_an_evaluation_have_short_reprs(points):
    # a point holds a 256-bin histogram, an evaluation its per-frequency errors and records:
    # both were dataclass reprs of every value (1342 and 8154 characters before)
    f_hz = np.arange(1.0, 400.0)
    evaluation = Evaluation.from_dict({
        "format": "tactilecal-dynamic-evaluation/1", "lag_s": 0.5, "clock": "fitted",
        "static_factor": 1.0, "fs_hz": 4000.0, "band_hz": [1.0, 140.0], "rms_before_N": 8.0,
        "rms_after_N": 2.0, "timing_error_s": 0.0, "above_band_share": 0.0,
        **{k: f_hz.tolist() for k in ("f_hz", "error_before_pct", "error_after_pct",
                                      "phase_before_deg", "phase_after_deg")}})
    for obj, shown in ((points[0], f"load_N={points[0].load_N:.6g}"),
                       (evaluation, "improvement=4, clock='fitted', lag_s=0.5")):
        text = repr(obj)
        assert len(text) < 1000 and text.startswith(f"<{type(obj).__name__} ") and shown in text
        assert obj._repr_html_().startswith("<table>")


def test_repr_of_a_long_table_is_cut():
    """A lookup table with 200 knots still has a short repr."""
    knots = np.r_[0.0, np.linspace(1.0, 255.0, 199)]
    frames = np.random.default_rng(3).integers(1, 255, size=(400, 6, 6)).astype(float)
    load = 0.004 * (frames ** 1.2).sum(axis=(1, 2))
    cal = calibrate(points_from_frames(frames, load), method="lut", knots=knots.tolist())
    assert len(cal.params["force_N"]) == 200
    assert len(repr(cal)) < 1000


# ---------------------------------------------------------------- the report reads tags
def test_report_tells_inputs_apart_by_their_tag(calibrations, tmp_path):
    from tactilecal.report import load_input

    calibrations["power"].to_json(tmp_path / "cal.json")
    _filters()[0].to_json(tmp_path / "FILTER.json")
    _equilibration().to_json(tmp_path / "eq.json")
    kind, obj, _ = load_input(tmp_path / "cal.json")
    assert kind == "calibration" and obj.params == calibrations["power"].params
    kind, obj, _ = load_input(tmp_path / "FILTER.json")
    assert kind == "filter" and obj == _filters()[0]  # the filter itself, equal by value
    with pytest.raises(ValueError, match=r"eq.json is an equilibration JSON \(format "
                                         r"'tactilecal-equilibration/1'\); expected a "
                                         r"calibration, a validation, a dynamic filter or an "
                                         r"evaluation of one"):
        load_input(tmp_path / "eq.json")


def test_every_saved_kind_compares_by_value_and_ignores_the_creation_time(calibrations,
                                                                         points):
    """``==`` of two equal results is True, never an error about arrays or DataFrames."""
    from tactilecal._result import _KINDS

    made = {"calibration": calibrations["zvyagin"], "equilibration": _equilibration(),
            "validation": validate(calibrations["power"], points)}
    for kind, result in made.items():
        twin = type(result).from_dict(result.to_dict())
        twin.created = "another time" if hasattr(twin, "created") else None
        assert twin == result and not (twin != result), kind
    other = calibrate(points[:30], method="power")
    assert other != calibrations["power"]
    assert calibrations["power"] != "a calibration"
    for cls in _KINDS.values():  # every kind: the base's equality, not a dataclass's
        assert cls.__eq__ is _KINDS["calibration"].__eq__, cls


def test_every_saved_kind_names_the_subpackage_that_defines_it():
    """``tactilecal.load`` imports only the file's subpackage: the map must miss no kind."""
    import tactilecal.analysis  # noqa: F401  (every subpackage with saved kinds)
    from tactilecal import _KIND_MODULES
    from tactilecal._result import _KINDS

    assert set(_KINDS) == set(_KIND_MODULES)
    for kind, cls in _KINDS.items():
        assert cls.__module__.startswith(_KIND_MODULES[kind] + "."), kind


def test_an_equilibration_loads_without_importing_dynamic_or_numba(tmp_path):
    """numba's import alone (about 55 MB) was half the memory bound of a read."""
    import subprocess
    import sys

    path = tmp_path / "eq.json"
    _equilibration().to_json(path)
    code = ("import sys, tactilecal\n"
            f"eq = tactilecal.load({str(path)!r})\n"
            "print(type(eq).__name__, *[m in sys.modules for m in "
            "('tactilecal.dynamic', 'tactilecal.analysis', 'numba')])")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True)
    assert out.stdout.split() == ["Equilibration", "False", "False", "False"]


def test_a_gain_table_of_floats_ints_and_nulls_reads_as_before(tmp_path):
    """Rows of floats and nulls are checked in NumPy, others value by value: same array."""
    rows = [[0.5, None, 2.0], [1, 3, None], [None, None, None], [1e-300, 1e300, 7]]
    path = tmp_path / "eq.json"
    path.write_text(json.dumps({"format": "tactilecal-equilibration/1", "gain": rows}))
    expected = np.array([[np.nan if v is None else v for v in row] for row in rows])
    np.testing.assert_array_equal(tactilecal.load(path).gain, expected)
    for bad, match in ((0.0, "0.0"), (-2, "-2"), (float("inf"), "inf"), (float("nan"), "nan"),
                       (True, "True")):
        rows[3][1] = bad
        path.write_text(json.dumps({"format": "tactilecal-equilibration/1", "gain": rows}))
        with pytest.raises(ValueError, match=rf"key 'gain' of .*eq.json, row 3 col 1 is "
                                             rf"{match}"):
            tactilecal.load(path)
