"""``tactilecal info`` on the real exports and on simulated files with a known answer."""

import json

import numpy as np
import pytest
import xarray as xr

from tactilecal.cli import main
from tactilecal.io import write_tekscan


def _info_json(capsys, path):
    assert main(["info", str(path), "--json"]) == 0
    return json.loads(capsys.readouterr().out)


def test_real_iscan(capsys, iscan_csv):
    out = _info_json(capsys, iscan_csv)
    assert (out["sensor_type"], out["catalogue_sensor"]) == ("6900", "6900")
    assert out["catalogue_match"] == "SENSOR_TYPE '6900'"
    assert (out["rows"], out["cols"], out["frames"]) == (28, 28, 309)
    assert out["duration_s"] == pytest.approx(31.1) and out["units"] == "raw"
    assert out["sensel_area_mm2"] == pytest.approx(1.6129) and out["calibration"] == {}
    # B rows 0,1,13,14,26,27 (6 x 28) + B cols 0,1,13,14,26,27 in the other 22 rows (6 x 22)
    assert out["blank_sensels"] == 6 * 28 + 6 * 22 == 300
    assert out["max_raw"] == 100 and out["saturated_frames"] == 0


def test_real_fscan(capsys, fscan_asf):
    out = _info_json(capsys, fscan_asf)
    assert (out["rows"], out["cols"], out["frames"], out["units"]) == (60, 21, 205, "kPa")
    assert out["duration_s"] == pytest.approx(204 * 0.032)
    cal = out["calibration"]
    assert cal["saturation_pressure_kPa"] == pytest.approx(1514.73)
    assert cal["calibration_point_1_raw_sum"] == 4798
    assert cal["calibration_point_1_loaded_cells"] == 240
    assert out["max_value"] == 760
    assert out["max_raw"] == pytest.approx(128, abs=0.1)  # 760 kPa / 5.94 kPa per count
    assert out["saturated_frames"] == 0


def test_text_output(capsys, fscan_asf):
    assert main(["info", str(fscan_asf)]) == 0
    text = capsys.readouterr().out
    assert "frames: 205" in text and "units: kPa" in text
    assert "  calibration_mode_1: Walk" in text and "saturated_frame_numbers: none" in text


def test_simulated_truth(capsys, tmp_path):
    rng = np.random.default_rng(11)
    values = rng.integers(1, 200, size=(12, 5, 6)).astype(float)
    values[:, 0, :] = np.nan  # 6 blank sensels
    values[:, 1, 2] = 0.0  # 2 never-loaded sensels
    values[:, 4, 5] = 0.0
    values[[3, 7, 8], 2, 2] = 255.0  # 3 saturated frames
    data = xr.DataArray(values, dims=("frame", "row", "col"),
                        coords={"frame": np.arange(1, 13), "time": ("frame", np.arange(12) * 0.01)},
                        attrs={"units": "raw", "sensor_type": "XYZ"})
    path = tmp_path / "sim.csv"
    write_tekscan(data, path)
    out = _info_json(capsys, path)
    assert out["blank_sensels"] == 6 and out["never_loaded_sensels"] == 2
    assert out["saturated_frames"] == 3 and out["saturated_frame_numbers"] == [4, 8, 9]
    assert out["max_raw"] == 255 and out["catalogue_sensor"] is None
    assert out["duration_s"] == pytest.approx(0.11)


def test_info_names_the_catalogue_entry_a_knee_export_matched(capsys, tmp_path):
    values = np.zeros((2, 22, 34))
    values[:, :3, :3] = np.nan  # part of the B outline
    data = xr.DataArray(values, dims=("frame", "row", "col"),
                        coords={"frame": [1, 2], "time": ("frame", [0.0, 0.01])},
                        attrs={"units": "raw", "sensor_type": "KNEE", "row_spacing_mm": 2.0,
                               "col_spacing_mm": 2.0, "sensel_area_mm2": 4.0})
    write_tekscan(data, tmp_path / "knee.csv")
    out = _info_json(capsys, tmp_path / "knee.csv")
    assert out["catalogue_sensor"] == "4010N"
    assert out["catalogue_match"] == "geometry 22 x 34 sensels at 2 x 2 mm"


def test_bad_file_exits_1_with_the_reason(capsys, tmp_path):
    path = tmp_path / "empty.csv"
    path.write_text("")
    assert main(["info", str(path)]) == 1
    assert "tactilecal info: error: " in capsys.readouterr().err
    # info reads any recording (Tekscan export, NetCDF, Zarr): the file is none of them
    with pytest.raises(ValueError, match=r"empty.csv: not a recording: .*expected one of these"):
        from tactilecal.cli._cmd_info import run

        run(type("Args", (), {"file": str(path), "json": False})())


def test_calibrated_power_law_file(capsys, tmp_path):
    scale, exponent = 0.9, 1.164  # pressure_kPa = scale x raw^exponent
    raw = np.random.default_rng(4).integers(0, 200, size=(6, 4, 4)).astype(float)
    raw[2, 1, 1] = 255.0  # frame 3 saturates
    data = xr.DataArray(scale * raw**exponent, dims=("frame", "row", "col"),
                        coords={"frame": np.arange(1, 7), "time": ("frame", np.arange(6) * 0.1)},
                        attrs={"units": "kPa", "scale_factor": scale, "exponent": exponent,
                               "saturation_pressure": scale * 255**exponent,
                               "saturation_pressure_unit": "kPa", "sensel_area_mm2": 1.6129})
    path = tmp_path / "cal.csv"
    write_tekscan(data, path)
    out = _info_json(capsys, path)
    assert out["max_raw"] == 255
    assert out["max_raw_source"] == "inverted header calibration (header-power-2pt)"
    assert out["saturated_frame_numbers"] == [3]
    assert out["calibration"]["exponent"] == exponent


def test_closed_pipe_is_not_a_traceback(iscan_csv):
    """``tactilecal info F --json | head -0``: the reader has gone before anything is written."""
    import subprocess
    import sys

    proc = subprocess.Popen([sys.executable, "-m", "tactilecal", "info", str(iscan_csv),
                             "--json"], stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    proc.stdout.close()  # the child's first write meets a closed pipe (EPIPE)
    with proc.stderr:
        stderr = proc.stderr.read().decode()
    assert proc.wait(timeout=120) == 1
    assert "Traceback" not in stderr and "BrokenPipeError" not in stderr, stderr
    assert "Broken pipe" not in stderr, stderr  # a closed pipe is no error to report


def test_info_on_a_calibrated_export_imports_no_fit_or_plot_library(fscan_asf):
    """Its largest raw reading comes from the header's law, not from a calibration result."""
    import subprocess
    import sys

    code = ("import sys; from tactilecal.cli import main; "
            f"assert main(['info', {str(fscan_asf)!r}, '--json']) == 0; "
            "print(sorted(m for m in sys.modules if m.split('.')[0] in "
            "('scipy', 'dask', 'numba', 'matplotlib') or m.startswith('tactilecal.calibration')), "
            "file=sys.stderr)")
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True)
    assert '"max_raw_source": "inverted header calibration' in run.stdout
    assert run.stderr.strip() == "[]", run.stderr
