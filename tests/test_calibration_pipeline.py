"""The library owns the calibration pipeline: ``calibrate(manifest, equilibration=, mask=)``.

The CLI (``tactilecal calibrate --equilibration --mask-dead`` then ``tactilecal apply``) and
the Python API must give the same numbers for every method; and the preprocessing must be
recorded where ``apply`` finds it.
"""

import json

import numpy as np
import pytest

from tactilecal.calibration import (
    METHODS,
    Equilibration,
    calibrate,
    equilibrate,
    find_dead_sensels,
    load_points,
)
from tactilecal.calibration._manifest import load_frames
from tactilecal.cli import main
from tactilecal.io import read_netcdf, read_tekscan, write_tekscan
from tactilecal.simulate import deadweight_session, make_sensor, uniform_load

RTOL = 1e-12  # same arithmetic on both sides: only the JSON round trip (exact) in between


@pytest.fixture(scope="module")
def session(tmp_path_factory):
    root = tmp_path_factory.mktemp("pipeline")
    sensor = make_sensor("5051", n_dead=10, seed=0)
    manifest = deadweight_session(sensor, n_patches=10, saturated_share=0.1,
                                  seed=1).write(root / "cal")
    # gains measured while every sensel worked (same seed: same gains, no dead sensel), so
    # that the dead sensels are not already NaN after equilibration and --mask-dead acts
    before = make_sensor("5051", n_dead=0, seed=0)
    uniform, _ = uniform_load(before, [150.0, 400.0], frames_per_level=3, seed=3)
    eq_path = root / "eq.json"
    equilibrate([uniform[:3], uniform[3:]]).to_json(eq_path)
    raw, _ = uniform_load(sensor, [150.0, 400.0], frames_per_level=3, seed=4)
    recording = manifest.parent / "rec.csv"
    write_tekscan(raw, recording)
    return {"root": root, "manifest": manifest, "eq": eq_path, "recording": recording}


def _cli(session, method, capsys):
    root = session["root"]
    cal, out = root / f"cal-{method}.json", root / f"out-{method}.nc"
    assert main(["-q", "calibrate", str(session["manifest"]), "--method", method,
                 "--equilibration", str(session["eq"]), "--mask-dead", "--out", str(cal)]) == 0
    assert main(["-q", "apply", str(cal), str(session["recording"]), "--out", str(out)]) == 0
    capsys.readouterr()
    return json.loads(cal.read_text()), read_netcdf(out)


def _assert_same_params(cli, python):
    assert set(cli) == set(python)
    for name, value in python.items():
        np.testing.assert_allclose(np.ravel(cli[name]), np.ravel(value), rtol=RTOL,
                                   err_msg=name)


@pytest.mark.parametrize("method", METHODS)
def test_cli_and_python_give_the_same_numbers(session, method, capsys):
    assert "zvyagin" in METHODS
    cli_cal, cli_out = _cli(session, method, capsys)
    result = calibrate(session["manifest"], method=method, equilibration=session["eq"],
                       mask="detect")
    _assert_same_params(cli_cal["params"], result.params)
    for key in ("equilibration", "non_working_sensels"):
        assert cli_cal[key] == json.loads(json.dumps(result.to_dict()[key])), key
    applied = result.apply(read_tekscan(session["recording"]))
    assert cli_out.attrs["units"] == applied.attrs["units"] == "kPa"
    # the recording has loaded sensels: the comparison is not of NaN and zeros only
    assert np.nansum(applied.values) > 0
    # apply stores float32 (attribute stored_dtype): the float64 values rounded to 24 bits
    assert cli_out.attrs["stored_dtype"] == "float32"
    np.testing.assert_allclose(cli_out.values, applied.values.astype(np.float32), rtol=0)


def test_preprocessing_is_recorded_and_applied(session):
    eq = Equilibration.from_json(session["eq"])
    dead = find_dead_sensels(load_frames(session["manifest"], equilibration=eq))
    assert dead.mask.any()  # the simulated sensor's dead sensels under the pads
    by_path = calibrate(session["manifest"], method="power", equilibration=session["eq"],
                        mask="detect")
    by_hand = calibrate(load_points(session["manifest"], equilibration=eq, mask=dead.mask),
                        method="power")
    _assert_same_params(by_path.params, by_hand.params)
    assert by_path.non_working.sensels == dead.sensels
    assert dead.report() in by_path.summary()  # the line the CLI prints
    np.testing.assert_array_equal(by_path.equilibration.gain, eq.gain)
    # apply: gains first, then the dead sensels become NaN, then the law
    raw = read_tekscan(session["recording"])
    expected = by_hand.predict_sensel_force(eq.apply(raw.values))
    expected[:, dead.mask] = np.nan
    np.testing.assert_allclose(by_path.predict_sensel_force(raw), expected, rtol=RTOL)
    assert np.isnan(by_path.apply(raw).values[:, dead.mask]).all()


def test_mask_kinds_agree(session):
    eq = Equilibration.from_json(session["eq"])
    dead = find_dead_sensels(load_frames(session["manifest"], equilibration=eq))
    results = [calibrate(session["manifest"], method="power", equilibration=eq, mask=mask)
               for mask in ("detect", dead, dead.mask)]
    for other in results[1:]:
        _assert_same_params(results[0].params, other.params)
        assert other.non_working.sensels == dead.sensels
    plain = calibrate(session["manifest"], method="power")
    assert plain.equilibration is None and plain.non_working is None


def test_pipeline_errors(session):
    points = load_points(session["manifest"])
    with pytest.raises(ValueError, match="equilibration= and mask= act on frames"):
        calibrate(points, equilibration=session["eq"])
    with pytest.raises(ValueError, match="equilibration= and mask= act on frames"):
        calibrate(points, mask="detect")
    with pytest.raises(TypeError, match="equilibration is a int; expected an Equilibration"):
        calibrate(session["manifest"], equilibration=3)
    with pytest.raises(TypeError, match="progress is a bool; expected None or a callable"):
        calibrate(session["manifest"], progress=True)
    with pytest.raises(TypeError, match="mask is 'dead'; expected 'detect'"):
        calibrate(session["manifest"], mask="dead")
    with pytest.raises(TypeError, match="mask is a bool; expected 'detect'"):
        calibrate(session["manifest"], mask=True)
    with pytest.raises(ValueError, match=r"mask has shape \(2, 2\); expected \(44, 44\)"):
        calibrate(session["manifest"], mask=np.zeros((2, 2), bool))
    with pytest.raises(ValueError, match=r"method='nope' is unknown"):
        calibrate(session["root"] / "missing.csv", method="nope")  # before reading a file
    with pytest.raises(ValueError, match=r"manifest.csv: point=99 is invalid"):
        calibrate(session["manifest"], method="linear", point=99)


def test_validate_reads_a_manifest_with_the_recorded_gains(session):
    from tactilecal.calibration import validate

    result = calibrate(session["manifest"], method="power", equilibration=session["eq"])
    eq = Equilibration.from_json(session["eq"])
    by_path = validate(result, session["manifest"])
    by_hand = validate(result, load_points(session["manifest"], equilibration=eq))
    without = validate(result, load_points(session["manifest"]))
    predicted = [p["predicted_N"] for p in by_path.points]
    np.testing.assert_allclose(predicted, [p["predicted_N"] for p in by_hand.points],
                               rtol=RTOL)
    # the gains matter (5 % spread): without them the predictions differ
    assert not np.allclose(predicted, [p["predicted_N"] for p in without.points],
                           rtol=1e-6)


def test_movie_takes_the_equilibration_as_a_path_too(tmp_path):
    from tactilecal.calibration import calibrate_movie
    from tactilecal.simulate import ramp_hold

    sensor = make_sensor("9500", seed=0)
    rh = ramp_hold(sensor, seed=2, hold_s=1.0, ramp_s=1.0, lead_s=0.5)
    # 25.8 mm2 sensels: 10 and 25 kPa read mid-range (150 kPa would saturate)
    uniform, _ = uniform_load(sensor, [10.0, 25.0], frames_per_level=3, seed=3)
    eq = equilibrate([uniform[:3], uniform[3:]])
    eq.to_json(tmp_path / "eq.json")
    by_path = calibrate_movie(rh.raw, rh.loadcell, lag_s=0.37, equilibration=tmp_path / "eq.json",
                              method="power")
    by_object = calibrate_movie(rh.raw, rh.loadcell, lag_s=0.37, equilibration=eq, method="power")
    _assert_same_params(by_path.params, by_object.params)
    assert by_path.equilibration == by_object.equilibration
    with pytest.raises(TypeError, match="equilibration is a list; expected an Equilibration"):
        calibrate_movie(rh.raw, rh.loadcell, lag_s=0.37, equilibration=[1.0], method="power")


def test_calibration_records_its_inputs_and_sensor_and_apply_checks_it(tmp_path):
    import hashlib
    import warnings
    from pathlib import Path

    import tactilecal
    from tactilecal import calibrate, load, read_tekscan
    from tactilecal.simulate import deadweight_session, make_sensor

    manifest = deadweight_session(make_sensor("5051", seed=1), n_patches=8, seed=2).write(
        tmp_path / "s")
    cal = calibrate(manifest, method="power")
    prov = cal.provenance
    files = sorted(p for p in (tmp_path / "s").iterdir() if p.suffix == ".csv")
    assert sorted(i["path"] for i in prov["inputs"]) == sorted(str(p.resolve()) for p in files)
    for entry in prov["inputs"]:
        assert entry["sha256"] == hashlib.sha256(Path(entry["path"]).read_bytes()).hexdigest()
    rec = read_tekscan(files[0] if files[0].name != "manifest.csv" else files[1])
    assert prov["sensor_type"] == rec.attrs["sensor_type"]
    assert prov["tactilecal_version"] == tactilecal.__version__
    cal.to_json(tmp_path / "cal.json")
    assert json.loads((tmp_path / "cal.json").read_text())["provenance"] == json.loads(
        json.dumps(prov)) and load(tmp_path / "cal.json").provenance == prov
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        cal.apply(rec)  # the same sensor type: no warning
    other = rec.assign_attrs(sensor_type="6900")
    with pytest.warns(UserWarning, match="is from a 6900 sensor, the calibration was made on "
                                         f"a {prov['sensor_type']}: check that it applies"):
        cal.apply(other)


def test_a_damaged_provenance_is_a_one_line_error_naming_file_and_key(tmp_path):
    import json

    from tactilecal import load
    from tactilecal.simulate import deadweight_session, make_sensor

    manifest = deadweight_session(make_sensor("5051", seed=1), n_patches=6, seed=2).write(
        tmp_path / "s")
    data = calibrate(manifest, method="power").to_dict()
    data["provenance"] = float("nan")
    (tmp_path / "cal.json").write_text(json.dumps(data))
    with pytest.raises(TypeError, match=r"key .provenance. of .*cal.json is nan \(float\); "
                                        r"expected an object"):
        load(tmp_path / "cal.json")



def test_every_static_output_names_its_inputs_by_their_bytes(session, tmp_path, capsys,
                                                            assert_names_by_bytes):
    """equilibrate JSON, validate, apply NetCDF and the analyze CSV's sidecar (issue 15)."""
    from tactilecal import load
    from tactilecal.calibration import validate

    raw, _ = uniform_load(make_sensor("5051", seed=0), [150.0, 400.0], frames_per_level=2,
                          seed=3)
    levels = [tmp_path / "u150.csv", tmp_path / "u400.csv"]
    write_tekscan(raw[:2], levels[0])
    write_tekscan(raw[2:], levels[1])
    eq = tmp_path / "eq.json"
    assert main(["-q", "equilibrate", *map(str, levels), "--out", str(eq)]) == 0
    assert_names_by_bytes(json.loads(eq.read_text())["provenance"], levels)
    assert load(eq).provenance == json.loads(eq.read_text())["provenance"]

    cal_path, nc = tmp_path / "cal.json", tmp_path / "p.nc"
    assert main(["-q", "calibrate", str(session["manifest"]), "--method", "power",
                 "--out", str(cal_path)]) == 0
    cal = load(cal_path)
    assert_names_by_bytes(validate(cal, session["manifest"]).provenance,
                          [i["path"] for i in cal.provenance["inputs"]])
    assert main(["-q", "apply", str(cal_path), str(session["recording"]), "--out",
                 str(nc)]) == 0
    applied = json.loads(read_netcdf(nc).attrs["provenance"])
    assert_names_by_bytes(applied, [session["recording"]])
    assert applied["options"] == {"units": "kPa"}
    table = tmp_path / "summary.csv"
    assert main(["-q", "analyze", str(nc), "--out", str(table)]) == 0
    capsys.readouterr()
    side = json.loads((tmp_path / "summary.provenance.json").read_text())
    assert_names_by_bytes(side, [nc])
    assert side["options"] == {"cal": None, "threshold_kPa": 0.0}


def test_a_file_changed_since_it_was_hashed_is_hashed_again(tmp_path):
    """The digest is kept per (path, size, mtime): a rewritten file never keeps its old one."""
    import hashlib
    import os

    from tactilecal._provenance import file_provenance

    path = tmp_path / "rec.csv"
    path.write_bytes(b"frame 1")
    assert file_provenance(path)["sha256"] == hashlib.sha256(b"frame 1").hexdigest()
    path.write_bytes(b"frame 2")  # same size
    later = path.stat().st_mtime_ns + 10 ** 9
    os.utime(path, ns=(later, later))
    assert file_provenance(path)["sha256"] == hashlib.sha256(b"frame 2").hexdigest()


def test_a_provenance_attribute_takes_numpy_options():
    """A NetCDF/Zarr output's provenance text: NumPy numbers in the options are numbers."""
    from tactilecal._provenance import provenance_attr

    prov = {"tactilecal_version": "x", "options": {"chunk_frames": np.int64(8192),
                                                   "threshold_kPa": np.float32(0.5)}}
    text = provenance_attr(prov)  # json.dumps refused np.int64 before
    assert "\n" not in text
    assert json.loads(text)["options"] == {"chunk_frames": 8192, "threshold_kPa": 0.5}
