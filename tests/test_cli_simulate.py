"""``tactilecal simulate deadweight`` and ``tactilecal simulate ramp-hold``."""

import csv
import json
import subprocess
import sys

import numpy as np
import pytest

from tactilecal import read_tekscan, read_timeseries
from tactilecal.cli import main


def test_deadweight_writes_session_and_manifest(tmp_path, capsys):
    out = tmp_path / "dw"
    assert main(["simulate", "deadweight", str(out), "--patches", "6", "--seed", "1"]) == 0
    printed = capsys.readouterr().out
    assert str(out / "manifest.csv") in printed and "recordings" in printed
    with (out / "manifest.csv").open(newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert len(rows) == 6 and list(rows[0]) == ["file", "frame", "mass_kg", "pad_mass_g",
                                                "label"]
    for row in rows:
        data = read_tekscan(out / row["file"])
        assert data.dims == ("frame", "row", "col") and data.shape[1:] == (44, 44)
        assert data.values.max() > 0
    assert json.loads((out / "truth.json").read_text())["sensor"]["A_N"] == 0.0035


def test_deadweight_is_deterministic_and_json(tmp_path, capsys):
    for name in ("a", "b"):
        assert main(["-q", "simulate", "deadweight", str(tmp_path / name), "--patches", "3",
                     "--seed", "4", "--json"]) == 0
    summary = json.loads(capsys.readouterr().out.split("}\n{")[0] + "}")
    assert summary["recordings"] == 3 and summary["sensor"] == "5051"
    with (tmp_path / "a" / "manifest.csv").open(newline="") as fh:
        rows = list(csv.DictReader(fh))
    for row in rows:
        assert (tmp_path / "a" / row["file"]).read_bytes() == \
            (tmp_path / "b" / row["file"]).read_bytes()


def test_deadweight_model_9500_scales_A_N(tmp_path, capsys):
    assert main(["simulate", "deadweight", str(tmp_path), "--patches", "4", "--model", "9500",
                 "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["A_N"] == pytest.approx(0.0035 * 5.08 ** 2 / 1.27 ** 2)
    assert summary["saturated_patches"] == 0


def test_ramp_hold_writes_recording_and_loadcell(tmp_path, capsys):
    out = tmp_path / "rh"
    assert main(["simulate", "ramp-hold", str(out), "--hold", "0.3", "--ramp", "0.2"]) == 0
    assert "loadcell" in capsys.readouterr().out
    assert (out / "loadcell.csv").read_text().startswith("Time (s),Load (N)\n")
    rec = read_tekscan(out / "recording.csv")
    lc = read_timeseries(out / "loadcell.csv")
    assert rec.attrs["seconds_per_frame"] == pytest.approx(0.01)
    assert np.diff(lc["time"].values).mean() == pytest.approx(0.002)
    assert lc.values.max() == pytest.approx(889.6, abs=3)


def test_errors(tmp_path, capsys):
    assert main(["simulate", "deadweight", str(tmp_path), "--model", "nope"]) == 1
    assert "tactilecal simulate: error: unknown sensor 'nope'" in capsys.readouterr().err
    assert main(["simulate", "deadweight", str(tmp_path), "--patches", "0"]) == 1
    assert "argument --patches: '0'; expected a finite number > 0" in capsys.readouterr().err
    with pytest.raises(SystemExit) as exc:
        main(["simulate"])
    assert exc.value.code == 2


def test_deadweight_saturated_share(tmp_path, capsys):
    assert main(["simulate", "deadweight", str(tmp_path), "--patches", "8",
                 "--saturated-share", "0.25", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["saturated_patches"] == 2
    with (tmp_path / "manifest.csv").open(newline="") as fh:
        rows = list(csv.DictReader(fh))
    saturated = [read_tekscan(tmp_path / r["file"]).values.max() == 255 for r in rows]
    assert sum(saturated) == 2


def test_simulate_blind_writes_records_that_read_back_with_their_truth(tmp_path, capsys):
    out = tmp_path / "blind"
    assert main(["-q", "simulate", "blind", str(out), "--A", "0.2", "--seed", "3", "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    truth = json.loads((out / "truth.json").read_text())
    assert truth["A"] == summary["A"] == 0.2 and truth["log_base"] == "10"
    assert len(truth["sets"]["f_hz"]) == summary["sets"] == 20
    reference = read_timeseries(out / "reference.csv")
    sensor = read_timeseries(out / "sensor.csv")
    assert reference.size == summary["reference_samples"] and sensor.size == summary[
        "sensor_samples"]
    assert reference.attrs["units"] == sensor.attrs["units"] == "N"
    # 5 kHz load cell, 4 kHz sensor (Gillis 2013, Table 4.2)
    assert np.diff(reference["time"].values[:2])[0] == pytest.approx(1 / 5000)
    assert np.diff(sensor["time"].values[:2])[0] == pytest.approx(1 / 4000)
    assert main(["-q", "simulate", "sweep", str(tmp_path / "s"), "--A", "-1"]) == 1


def test_building_the_parser_does_not_load_the_sensor_catalogue():
    # every command builds the parser: simulate's runs import the catalogue when they run
    code = ("import sys; from tactilecal.cli import build_parser; build_parser(); "
            "print('tactilecal.sensors' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True)
    assert out.stdout.split() == ["False"]


def test_simulate_uniform_then_equilibrate_recovers_the_gains(tmp_path, capsys):
    folder = tmp_path / "uni"
    assert main(["-q", "simulate", "uniform", str(folder), "--model", "9500",
                 "--pressures-kpa", "80,200", "--frames", "4", "--json"]) == 0
    written = json.loads(capsys.readouterr().out)
    assert sorted(p.name for p in folder.iterdir()) == ["truth.json", "uniform-1-80kPa.csv",
                                                         "uniform-2-200kPa.csv"]
    assert written["pressures_kPa"] == [80.0, 200.0] and written["frames_per_level"] == 4
    truth = json.loads((folder / "truth.json").read_text())
    assert main(["-q", "equilibrate", str(folder / "uniform-1-80kPa.csv"),
                 str(folder / "uniform-2-200kPa.csv"), "--out", str(tmp_path / "eq.json")]) == 0
    from tactilecal.calibration import Equilibration

    gain = Equilibration.from_json(tmp_path / "eq.json").gain
    alive = ~np.isnan(gain)
    # a sensel reading `gain` times its ideal reading is equalised by about 1 / gain
    ratio = gain[alive] * np.asarray(truth["sensor"]["gain"])[alive]
    assert np.std(ratio) / np.mean(ratio) < 0.03  # 5 % gain spread, read noise 0.5
    assert main(["-q", "simulate", "uniform", str(folder), "--pressures-kpa", "80,-1"]) == 1
    assert "'80,-1'; expected comma-separated positive pressures in kPa" in \
        capsys.readouterr().err
