"""``tactilecal analyze``: table, JSON, CSV, exit codes."""

import json
import re

import numpy as np
import pandas as pd
import pytest

from tactilecal.cli import main


def test_analyze_real_fscan_text_and_csv(fscan_asf, tmp_path, capsys):
    out = tmp_path / "summary.csv"
    assert main(["-q", "analyze", str(fscan_asf), "--out", str(out)]) == 0
    text = capsys.readouterr().out
    # numbers for people: four significant digits (tactilecal._text.number), 924.359 N
    assert re.search(r"peak_force_N +924.4\n", text) and re.search(r"peak_force_frame +9\n", text)
    assert re.search(r"saturated_frames +0\n", text)
    table = pd.read_csv(out)
    assert list(table.columns) == ["frame", "time_s", "force_N", "contact_area_mm2",
                                   "cof_row_mm", "cof_col_mm", "peak_kPa", "mean_kPa",
                                   "saturated_sensels"]
    assert len(table) == 205 and table.frame.iloc[0] == 1
    np.testing.assert_allclose(table.time_s.iloc[-1], 204 * 0.032)


def test_analyze_json_with_threshold(fscan_asf, capsys):
    assert main(["-q", "analyze", str(fscan_asf), "--json", "--threshold-kpa", "50"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["threshold_kPa"] == 50.0 and len(data["frames"]) == 205
    full = data["overview"]
    assert full["peak_force_N"] == pytest.approx(924.359, abs=1e-3)
    # a threshold removes light sensels from the area but never the force
    assert full["max_contact_area_mm2"] < 9909.66


def test_analyze_exit_codes(iscan_csv, tmp_path, capsys):
    assert main(["-q", "analyze", str(iscan_csv)]) == 1
    assert "units are 'raw'; give a calibration" in capsys.readouterr().err
    assert main(["-q", "analyze", str(tmp_path / "none.csv")]) == 1
    assert "does not exist" in capsys.readouterr().err
    with pytest.raises(SystemExit) as usage:
        main(["analyze"])
    assert usage.value.code == 2


def test_analyze_cal_on_a_calibrated_recording_is_an_error(fscan_asf, tmp_path, capsys):
    """Issue 31: the calibration was ignored silently (the F-Scan export is in kPa)."""
    from tactilecal.calibration import calibrate, points_from_frames

    frames = np.zeros((3, 4, 4))
    for k, level in enumerate((20, 60, 120)):
        frames[k, 1:3, 1:3] = level
    cal = tmp_path / "cal.json"
    calibrate(points_from_frames(frames, [4 * 0.0035 * v ** 1.2 for v in (20, 60, 120)],
                                 sensel_area_mm2=1.6129), method="power").to_json(cal)
    assert main(["-q", "analyze", str(fscan_asf), "--cal", str(cal)]) == 1
    err = capsys.readouterr().err
    assert "footPress_FrasP01L.asf: units are 'kPa', already calibrated; expected a raw " \
           "recording with a calibration" in err and len(err.strip().splitlines()) == 1


def test_analyze_regions_and_steps(fscan_asf, tmp_path, capsys):
    out = tmp_path / "regions.csv"
    assert main(["-q", "analyze", str(fscan_asf), "--region", "heel=40:60,0:21",
                 "--region", "fore=0:40,0:21", "--steps", "--json", "--out", str(out)]) == 0
    data = json.loads(capsys.readouterr().out)
    regions = {r["region"]: r for r in data["regions"]}
    assert set(regions) == {"heel", "fore"} and regions["heel"]["sensels"] == 20 * 21
    # the two boxes cover the insole: their impulses add up to the whole walk's
    whole = sum(r["impulse_N_s"] for r in regions.values())
    assert sum(r["share_of_impulse"] for r in regions.values()) == pytest.approx(1.0)
    assert whole == pytest.approx(2592.0, abs=1.0)
    assert sum(s["complete"] for s in data["steps"]) == 5
    table = pd.read_csv(out)
    np.testing.assert_allclose(table["force_N [heel]"] + table["force_N [fore]"],
                               table["force_N"], rtol=1e-12)


def test_analyze_split_contacts_text(fscan_asf, capsys):
    assert main(["-q", "analyze", str(fscan_asf), "--split-contacts", "--gap-mm", "30"]) == 0
    text = capsys.readouterr().out
    assert re.search(r"contact 1 +1260 +924.4 .* 100.0 %", text)


@pytest.mark.parametrize(("argv", "message"), [
    (["--region", "heel"], r"argument --region: 'heel'; expected NAME=SPEC"),
    (["--region", "a=0:2,0:2", "--region", "a=2:4,0:2"], r"--region names \['a', 'a'\] repeat"),
    (["--gap-mm", "10"], "--gap-mm is given without --split-contacts"),
    (["--region", "a=0:99,0:2"], r"region 'a': box \(0, 99, 0, 2\) is empty or outside the 60 "
                                 "x 21 sensels"),
])
def test_analyze_bad_regions_exit_1_with_one_line(fscan_asf, argv, message, capsys):
    assert main(["-q", "analyze", str(fscan_asf), *argv]) == 1
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and re.search(message, err), err
