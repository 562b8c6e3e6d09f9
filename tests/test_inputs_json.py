"""Calibration, equilibration and FILTER.json files with impossible or mistyped values.

Every file is written by tactilecal itself, then one key is changed; the error must name the
file and the key (issue 11). Nothing is read as something else (A = nan used to give zeros).
"""

import json

import numpy as np
import pytest

from tactilecal.calibration import (
    CalibrationResult,
    Equilibration,
    calibrate,
    equilibrate,
    points_from_frames,
)
from tactilecal.dynamic import CorrectionFilter


def _power_json(tmp_path):
    frames = np.zeros((3, 4, 4))
    for k, level in enumerate((20, 60, 120)):
        frames[k, 1:3, 1:3] = level
    result = calibrate(points_from_frames(frames, [4 * 0.0035 * v ** 1.2 for v in (20, 60, 120)],
                                          sensel_area_mm2=1.6129), method="power")
    path = tmp_path / "cal.json"
    result.to_json(path)
    return path


def _edit(path, change):
    data = json.loads(path.read_text())
    change(data)
    path.write_text(json.dumps(data))
    return path


def test_untouched_calibration_reads(tmp_path):
    cal = CalibrationResult.from_json(_power_json(tmp_path))
    assert cal.params["b"] == pytest.approx(1.2, rel=1e-6)


@pytest.mark.parametrize(("key", "value", "error", "match"), [
    ("A", -1.0, ValueError, r"key 'params.A' of .*cal.json is -1.0; expected a finite number > 0"),
    ("A", None, TypeError, r"key 'params.A' of .*cal.json is None"),
    ("b", -3.0, ValueError, r"key 'params.b' of .*cal.json is -3.0"),
    ("b", 0.0, ValueError, r"key 'params.b' of .*cal.json is 0.0"),
    ("b", "1.2", TypeError, r"key 'params.b' of .*cal.json is '1.2' \(str\); expected a number"),
])
def test_impossible_power_law_is_an_error_naming_the_key(tmp_path, key, value, error, match):
    path = _edit(_power_json(tmp_path), lambda d: d["params"].update({key: value}))
    with pytest.raises(error, match=match):
        CalibrationResult.from_json(path)


def test_calibration_with_nan_a_is_an_error(tmp_path):
    """JSON has no NaN, but Python's json module writes and reads one: it must not mean 0."""
    path = _edit(_power_json(tmp_path), lambda d: d["params"].update(A=float("nan")))
    with pytest.raises(ValueError, match=r"key 'params.A' of .*cal.json is nan"):
        CalibrationResult.from_json(path)


@pytest.mark.parametrize(("key", "value", "error", "match"), [
    ("sensel_area_mm2", -3.0, ValueError, r"key 'sensel_area_mm2' of .*cal.json is -3.0"),
    ("sensel_area_mm2", "big", TypeError, r"key 'sensel_area_mm2' of .*cal.json is 'big'"),
    ("params", [1, 2], TypeError, r"key 'params' of .*cal.json is \[1, 2\] \(list\)"),
    ("points", {"a": 1}, TypeError, r"key 'points' of .*cal.json is \{'a': 1\} \(dict\)"),
    ("model", "spline", ValueError, r"key 'model' of .*cal.json is 'spline'; expected one of"),
    ("model", 3, TypeError, r"key 'model' of .*cal.json is 3 \(int\)"),
])
def test_mistyped_calibration_key_is_an_error_naming_it(tmp_path, key, value, error, match):
    path = _edit(_power_json(tmp_path), lambda d: d.update({key: value}))
    with pytest.raises(error, match=match):
        CalibrationResult.from_json(path)


def test_calibration_json_in_utf16_reads(tmp_path):
    path = _power_json(tmp_path)
    path.write_bytes(path.read_text().encode("utf-16"))
    assert CalibrationResult.from_json(path).model == "power"


def _equilibration_json(tmp_path):
    frames = np.full((2, 3, 3), 100.0)
    frames[:, 0, 0] = 80.0
    path = tmp_path / "eq.json"
    equilibrate([frames]).to_json(path)
    return path


@pytest.mark.parametrize(("value", "error", "match"), [
    (-1.0, ValueError, r"key 'gain' of .*eq.json, row 0 col 0 is -1.0"),
    ("x", TypeError, r"key 'gain' of .*eq.json, row 0 col 0 is 'x'"),
])
def test_impossible_gain_is_an_error_naming_the_cell(tmp_path, value, error, match):
    path = _edit(_equilibration_json(tmp_path), lambda d: d["gain"][0].__setitem__(0, value))
    with pytest.raises(error, match=match):
        Equilibration.from_json(path)


def test_ragged_gain_table_is_an_error(tmp_path):
    path = _edit(_equilibration_json(tmp_path), lambda d: d["gain"][0].pop())
    with pytest.raises(ValueError, match=r"key 'gain' of .*eq.json is not a table"):
        Equilibration.from_json(path)


def _filter_json(tmp_path):
    path = tmp_path / "FILTER.json"
    CorrectionFilter.from_model(("log10", {"A": 0.11}), fs_hz=4000, band_hz=(1, 140)).to_json(path)
    return path


def test_untouched_filter_reads(tmp_path):
    assert CorrectionFilter.from_json(_filter_json(tmp_path)).params == {"A": 0.11}


@pytest.mark.parametrize(("key", "value", "error", "match"), [
    ("fs_hz", 0, ValueError, r"key 'fs_hz' of .*FILTER.json is 0"),
    ("fs_hz", "4000", TypeError, r"key 'fs_hz' of .*FILTER.json is '4000'"),
    ("band_hz", [140, 1], ValueError, r"key 'band_hz' of .*FILTER.json is \[140, 1\]; expected "
                                      "low < high"),
    ("band_hz", [1, 3000], ValueError, r"key 'band_hz' of .*FILTER.json is 3000"),
    ("n_taps", 0, ValueError, r"key 'n_taps' of .*FILTER.json is 0"),
    ("params", {"A": "x"}, TypeError, r"key 'params.A' of .*FILTER.json is 'x'"),
    ("outside", "wrap", ValueError, r"key 'outside' of .*FILTER.json is 'wrap'"),
])
def test_impossible_filter_key_is_an_error_naming_it(tmp_path, key, value, error, match):
    path = _edit(_filter_json(tmp_path), lambda d: d.update({key: value}))
    with pytest.raises(error, match=match):
        CorrectionFilter.from_json(path)


@pytest.mark.parametrize("value", [-3.5, "abc", [1, 2], {"gain": 1}])
def test_filter_with_a_malformed_rational_model_is_an_error_naming_the_key(tmp_path, value):
    """Found by the fuzz test: a 'rational' key on a log filter was read without a check."""
    path = _edit(_filter_json(tmp_path), lambda d: d.update(rational=value))
    with pytest.raises((TypeError, ValueError), match=r"key 'rational' of .*FILTER.json"):
        CorrectionFilter.from_json(path)
