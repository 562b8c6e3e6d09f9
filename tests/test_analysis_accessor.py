"""The ``.tactile`` xarray accessor delegates to the analysis functions, number for number."""

import inspect
import re
import subprocess
import sys

import numpy as np
import pytest
import xarray as xr

from tactilecal import analysis
from tactilecal.analysis import _maps, _regions, _units
from tactilecal.calibration import calibrate, points_from_frames

AREA_MM2 = 6.0


def patch(unit="kPa"):
    """Frames 0..3: a 3 x 4 patch at rows k..k+2, cols 2..5, 50 (k + 1) (in ``unit``)."""
    p = np.zeros((4, 10, 8))
    for k in range(4):
        p[k, k:k + 3, 2:6] = 50.0 * (k + 1)
    p[:, 0, 7] = np.nan  # outside the sensor
    return xr.DataArray(
        p, dims=("frame", "row", "col"),
        coords={"frame": np.arange(1, 5), "time": ("frame", np.arange(4) * 0.01)},
        attrs={"units": unit, "sensel_area_mm2": AREA_MM2, "row_spacing_mm": 2.0,
               "col_spacing_mm": 3.0, "source": "patch"},
    )


@pytest.fixture(scope="module")
def raw_and_cal():
    raw = patch("raw")
    frames = raw.values[:, 1:, :7]  # the NaN-free part, for the points
    load_N = 0.004 * (frames ** 1.2).sum(axis=(1, 2))  # a known power law, A = 0.004 N
    cal = calibrate(points_from_frames(frames, load_N, sensel_area_mm2=AREA_MM2),
                    method="power", objective="l2")
    np.testing.assert_allclose([cal.params["A"], cal.params["b"]], [0.004, 1.2], rtol=1e-6)
    return raw, cal


CASES = [  # accessor method, the function it runs, keyword arguments
    ("force", _maps.total_force, {}),
    ("area", _maps.contact_area, {"threshold_kPa": 60.0}),
    ("centre", _maps.centre_of_force, {}),
    ("peak", _maps.peak_pressure, {}),
    ("mean_pressure", _maps.mean_pressure, {"threshold_kPa": 60.0}),
    ("pressure_map", _units.pressure_map_kPa, {}),
    ("force_map", _units.force_map_N, {}),
    ("frame_summary", _maps.summary, {"threshold_kPa": 60.0}),
    ("max_window_load", _regions.max_window_load, {"window": (2, 2)}),
    ("profile", _regions.profile, {}),
]


@pytest.mark.parametrize(("method", "function", "kwargs"), CASES)
def test_accessor_matches_the_function_on_pressure(method, function, kwargs):
    rec = patch("kPa")
    xr.testing.assert_identical(getattr(rec.tactile, method)(**kwargs),
                                function(rec, **kwargs))


@pytest.mark.parametrize(("method", "function", "kwargs"), CASES)
def test_accessor_matches_the_function_on_raw(raw_and_cal, method, function, kwargs):
    raw, cal = raw_and_cal
    xr.testing.assert_identical(getattr(raw.tactile, method)(calibration=cal, **kwargs),
                                function(raw, calibration=cal, **kwargs))


@pytest.mark.parametrize(("method", "function", "kwargs"), CASES)
def test_a_method_carries_its_functions_signature_and_docstring(method, function, kwargs):
    got = getattr(analysis.TactileAccessor, method)
    want = list(inspect.signature(function).parameters)[1:]  # all but the recording
    assert list(inspect.signature(got).parameters) == ["self", *want]
    doc = inspect.getdoc(got)
    assert doc.splitlines()[0] == inspect.getdoc(function).splitlines()[0]
    assert "recording :" not in doc
    # its examples call the method, never the function
    examples = doc.split("\nExamples\n")[1]
    assert f".tactile.{method}(" in examples
    assert not re.search(rf"(?<![.\w]){function.__name__}\(", examples)


def test_calibrate_is_apply(raw_and_cal, tmp_path):
    raw, cal = raw_and_cal
    xr.testing.assert_identical(raw.tactile.calibrate(cal), cal.apply(raw))
    xr.testing.assert_identical(raw.tactile.calibrate(cal, units="N"), cal.apply(raw, units="N"))
    path = tmp_path / "cal.json"
    cal.to_json(path)
    xr.testing.assert_identical(raw.tactile.calibrate(path), cal.apply(raw))
    # known truth: the patch's force at frame k is the law over its 12 sensels
    force = raw.tactile.calibrate(cal).tactile.force()
    np.testing.assert_allclose(force, 12 * 0.004 * (50.0 * np.arange(1, 5)) ** 1.2, rtol=1e-6)


def test_raw_without_calibration_says_so():
    with pytest.raises(ValueError, match="patch: units are 'raw'; give a calibration"):
        patch("raw").tactile.force()


def _run(code):
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True)
    return out.stdout.split()


def test_registration_without_slowing_import_tactilecal():
    # either order of the imports registers it (isort puts tactilecal first), and the
    # analysis is imported on the first use of .tactile only; each order in a new
    # interpreter, and in the first, import tactilecal alone (before xarray is imported)
    # does not load xarray (it would cost ~30 times the import)
    use = ("a = xarray.DataArray([[[50.0]]], dims=('frame', 'row', 'col'), "
           "attrs={'units': 'kPa', 'sensel_area_mm2': 2.0}); "
           "print('tactilecal.analysis' in sys.modules, float(a.tactile.force()[0]), "
           "'tactilecal.analysis' in sys.modules)")
    orders = {"import sys, tactilecal; print('xarray' in sys.modules); import xarray": ["False"],
              "import sys, xarray, tactilecal": [],
              "import sys, tactilecal.analysis, xarray": []}
    for imports, alone in orders.items():
        analysis_first = imports.endswith("analysis, xarray")
        # one registration (xarray warns when an accessor is registered again), one factory
        code = (f"import warnings; warnings.simplefilter('error'); {imports}; {use}; "
                "import tactilecal.analysis; print(xarray.DataArray.tactile.__name__)")
        assert _run(code) == [*alone, str(analysis_first), "0.1", "True", "_tactile"], imports


def test_frames_are_the_files_numbers_positions_only_where_a_parameter_says_so():
    """One convention (issue 31): plot_pressure_map(frame=9) took a position, titled +1."""
    rec = patch().assign_coords(frame=np.arange(10, 14))  # the file's frames 10..13
    summary = rec.tactile.frame_summary()
    assert analysis.peak_frame(summary) == 13  # the last frame carries the most force
    by_number = rec.tactile.plot_pressure_map(frame=11)
    by_position = rec.tactile.plot_pressure_map(position=1)
    assert by_number.get_title() == by_position.get_title() == "frame 11"
    np.testing.assert_array_equal(by_number.images[0].get_array(),
                                  by_position.images[0].get_array())
    np.testing.assert_array_equal(by_number.images[0].get_array().filled(np.nan),
                                  rec.sel(frame=11).values)
    rows, _ = rec.tactile.plot_profiles(frame=13)
    rows_by_position, _ = rec.tactile.plot_profiles(position=3)
    np.testing.assert_array_equal(rows.lines[0].get_xdata(), rows_by_position.lines[0].get_xdata())
    with pytest.raises(ValueError, match=r"frame=9 is not a frame of the recording \(frames "
                                         r"10..13\); expected one of its frame numbers"):
        rec.tactile.plot_pressure_map(frame=9)
    with pytest.raises(ValueError, match=r"frame=11 and position=1; expected one of them"):
        rec.tactile.plot_pressure_map(frame=11, position=1)
    with pytest.raises(ValueError, match=r"no frame given; expected frame="):
        rec.tactile.plot_profiles()


def test_a_calibration_is_never_silently_ignored_on_a_calibrated_recording(raw_and_cal):
    _, cal = raw_and_cal
    with pytest.raises(ValueError, match=r"patch: units are 'kPa', already calibrated; expected "
                                         r"a raw recording with a calibration"):
        patch("kPa").tactile.force(calibration=cal)
    with pytest.raises(ValueError, match=r"already calibrated"):
        patch("kPa").tactile.frame_table(calibration=cal)
