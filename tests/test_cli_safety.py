"""CLI safety on hostile input (issue 11): one line, exit 1, nothing replaced or left behind."""

import json
import os

import numpy as np
import pytest
import xarray as xr

from tactilecal.cli import main
from tactilecal.io import write_tekscan


@pytest.fixture(scope="module")
def session(tmp_path_factory):
    folder = tmp_path_factory.mktemp("session")
    assert main(["-q", "simulate", "deadweight", str(folder), "--patches", "12"]) == 0
    cal = folder / "cal.json"
    assert main(["-q", "calibrate", str(folder / "manifest.csv"), "--out", str(cal)]) == 0
    return folder, cal


def _raw_recording(path, value):
    data = xr.DataArray(np.full((4, 3, 3), float(value)), dims=("frame", "row", "col"),
                        coords={"frame": np.arange(1, 5), "time": ("frame", np.arange(4) * 0.1)},
                        attrs={"units": "raw", "sensel_area_mm2": 1.6129, "row_spacing_mm": 1.27,
                               "col_spacing_mm": 1.27, "seconds_per_frame": 0.1})
    write_tekscan(data, path)
    return path


def _one_line_error(capsys, *needles):
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "Traceback" not in err, err
    for needle in needles:
        assert needle in err, err
    return err


def test_quiet_after_the_subcommand_is_accepted(tmp_path, capsys):
    short = ["--hold", "0.5", "--ramp", "0.5"]  # a short session: what is said is the point
    assert main(["simulate", "ramp-hold", str(tmp_path / "rh"), *short, "--quiet"]) == 0
    assert capsys.readouterr().err == ""
    assert main(["simulate", "ramp-hold", str(tmp_path / "rh2"), *short, "-q", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)


def test_unwritable_output_names_the_path_given(session, capsys):
    folder, _ = session
    target = "/dev/null/cal.json"  # a file where a folder should be: fails even for root
    # the output is written after the fit, whatever its method: power is the quick one
    assert main(["-q", "calibrate", str(folder / "manifest.csv"), "--method", "power",
                 "--out", target]) == 1
    err = _one_line_error(capsys, target)
    assert "/dev/null/.cal.json" not in err


def test_output_that_is_an_input_is_refused(session, tmp_path, capsys):
    folder, cal = session
    rec = _raw_recording(tmp_path / "rec.csv", 100)
    before = rec.read_bytes()
    assert main(["-q", "apply", str(cal), str(rec), "--out", str(rec)]) == 1
    _one_line_error(capsys, f"--out {rec} is the input")
    assert rec.read_bytes() == before


@pytest.mark.parametrize(("argv", "flag"), [
    (["dynamic", "apply", "f.json", "x.nc", "--out", "y.nc", "--chunk-frames", "0"],
     "--chunk-frames"),
    (["simulate", "deadweight", "out", "--saturated-share", "1.5"], "--saturated-share"),
    (["analyze", "x.csv", "--threshold-kpa", "nan"], "--threshold-kpa"),
    (["simulate", "ramp-hold", "out", "--frame-rate", "-100"], "--frame-rate"),
])
def test_impossible_flag_value_is_one_line_naming_the_flag(argv, flag, capsys):
    assert main(argv) == 1
    _one_line_error(capsys, f"argument {flag}")


def test_unknown_method_is_refused_before_reading_the_manifest(tmp_path, capsys):
    assert main(["calibrate", str(tmp_path / "missing.csv"), "--method", "abc"]) == 1
    _one_line_error(capsys, "--method 'abc'; expected one of")


@pytest.mark.parametrize("argv", [["simulate", "deadweight", "{f}", "--patches", "3"],
                                  ["demo", "--out", "{f}"]])
def test_output_folder_that_is_a_file_is_an_error(tmp_path, argv, capsys):
    existing = tmp_path / "existing"
    existing.write_text("keep me")
    assert main(["-q", *[a.format(f=existing) for a in argv]]) == 1
    _one_line_error(capsys, f"{existing} is a text file; expected a folder")
    assert existing.read_text() == "keep me"


def test_analyze_names_its_own_input(tmp_path, capsys):
    assert main(["analyze", str(tmp_path / "nope.csv")]) == 1
    _one_line_error(capsys, "RECORDING", "nope.csv does not exist")


def test_all_255_recording_is_flagged_saturated(session, tmp_path, capsys):
    _, cal = session
    rec = _raw_recording(tmp_path / "sat.csv", 255)
    assert main(["-q", "analyze", str(rec), "--cal", str(cal), "--json"]) == 0
    captured = capsys.readouterr()
    overview = json.loads(captured.out)["overview"]
    assert overview["saturated_frames"] == 4 and overview["peak_force_is_lower_bound"] is True
    assert "4 of 4 frames have saturated sensels" in captured.err


def test_unsaturated_recording_is_not_flagged(session, tmp_path, capsys):
    _, cal = session
    rec = _raw_recording(tmp_path / "ok.csv", 100)
    assert main(["-q", "analyze", str(rec), "--cal", str(cal), "--json"]) == 0
    captured = capsys.readouterr()
    assert json.loads(captured.out)["overview"]["saturated_frames"] == 0
    assert "saturated" not in captured.err


def test_applied_recording_keeps_saturation_recognisable(session, tmp_path, capsys):
    _, cal = session
    rec = _raw_recording(tmp_path / "sat.csv", 255)
    out = tmp_path / "sat.nc"
    assert main(["-q", "apply", str(cal), str(rec), "--out", str(out)]) == 0
    assert "4 of 4 frames have saturated sensels" in capsys.readouterr().err
    assert main(["-q", "analyze", str(out), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["overview"]["saturated_frames"] == 4


def test_temp_file_of_a_killed_writer_is_removed_on_the_next_write(tmp_path, capsys):
    import subprocess
    import sys

    from tactilecal._atomic import write_text_atomic

    dead = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"],
                          capture_output=True, text=True, check=True)
    pid = int(dead.stdout)  # a process that has ended
    stale = tmp_path / f".out.json.tmp{pid}.abcd.json"
    stale.write_text("half")
    alive = tmp_path / f".out.json.tmp{os.getpid()}.efgh.json"  # a writer still running
    alive.write_text("busy")
    write_text_atomic(tmp_path / "out.json", "{}")
    assert not stale.exists() and alive.exists()
    assert f"removed {stale}" in capsys.readouterr().err
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted([alive.name, "out.json"])


def test_failed_write_leaves_no_temp_file(tmp_path):
    from tactilecal._atomic import atomic_path

    with pytest.raises(RuntimeError), atomic_path(tmp_path / "x.nc") as tmp:
        tmp.write_text("partial")
        raise RuntimeError("writer failed")
    assert list(tmp_path.iterdir()) == []


@pytest.mark.slow  # end to end: a command through every figure of a report
def test_report_of_a_saturated_recording_says_its_forces_are_lower_bounds(session, tmp_path):
    _, cal = session
    rec = _raw_recording(tmp_path / "sat.csv", 255)
    out = tmp_path / "r.html"
    assert main(["-q", "report", str(rec), str(cal), "--out", str(out)]) == 0
    assert "4 of 4 frames hold sensels at saturation" in out.read_text()


@pytest.mark.slow  # end to end: a command through every figure of a report
def test_report_cof_threshold_flag(session, tmp_path):
    _, cal = session
    rec = _raw_recording(tmp_path / "r.csv", 40)
    out = tmp_path / "r.html"
    assert main(["-q", "report", str(rec), str(cal), "--out", str(out),
                 "--cof-min-force-n", "1.5"]) == 0
    assert "<td>centre of force drawn where force is at least</td><td>1.5 N</td>" in \
        out.read_text()


def test_report_refuses_a_negative_cof_threshold(tmp_path, capsys):
    rec = _raw_recording(tmp_path / "r.csv", 40)
    out = tmp_path / "r.html"
    assert main(["-q", "report", str(rec), "--out", str(out), "--cof-min-force-n", "-1"]) == 1
    assert not out.exists()
    assert "--cof-min-force-n: '-1'; expected a finite number >= 0" in capsys.readouterr().err


def test_library_warnings_are_one_line_naming_the_command(tmp_path, capsys):
    # a calibration made on one sensor type applied to a recording of another warns (the
    # one-weight manifest that warned in Zvyagin's fit is now refused at calibrate's door)
    folder = tmp_path / "one"
    assert main(["-q", "simulate", "deadweight", str(folder), "--patches", "6"]) == 0
    cal = tmp_path / "cal.json"
    assert main(["-q", "calibrate", str(folder / "manifest.csv"), "--out", str(cal)]) == 0
    recording = next(p for p in folder.glob("*.csv") if p.name != "manifest.csv")
    other = tmp_path / "other.csv"
    other.write_text(recording.read_text().replace("SENSOR_TYPE 5051", "SENSOR_TYPE 5051-X"))
    capsys.readouterr()
    assert main(["-q", "apply", str(cal), str(other), "--out", str(tmp_path / "o.nc")]) == 0
    err = capsys.readouterr().err
    warning_lines = [line for line in err.splitlines() if ": warning: " in line]
    assert warning_lines and all(line.startswith("tactilecal apply: warning: ")
                                 for line in warning_lines)
    assert "_check_sensor(" not in err and "warnings.warn" not in err  # no library source


def test_cli_errors_name_the_flags_the_user_typed(tmp_path, capsys):
    folder = tmp_path / "s"
    assert main(["-q", "simulate", "deadweight", str(folder), "--patches", "6"]) == 0
    manifest = str(folder / "manifest.csv")
    assert main(["-q", "calibrate", manifest, "--method", "power-2pt", "--pair", "1,1"]) == 1
    err = capsys.readouterr().err
    assert "--pair [1, 1] is invalid; expected two different indices" in err
    assert "pair=" not in err
