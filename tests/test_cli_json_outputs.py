"""Every JSON a command writes or prints is a saved result that ``tactilecal.load`` reads back.

One reader for every kind, found by the ``format`` tag: a calibration from ``calibrate``, an
equilibration from ``equilibrate``, a validation printed by ``validate --json``, a filter
from ``dynamic fit`` (written and printed) and a blind test from ``dynamic evaluate --out``.
"""

import json

import pytest

import tactilecal
from tactilecal.calibration import CalibrationResult, Equilibration, ValidationResult
from tactilecal.cli import main
from tactilecal.dynamic import CorrectionFilter, Evaluation
from tactilecal.io import write_timeseries
from tactilecal.simulate import deadweight_session, make_sensor, random_sine_sets, sine_sweep

FAST = {"fs_sensor_hz": 1000.0, "fs_reference_hz": 1250.0}


@pytest.fixture(scope="module")
def written(tmp_path_factory):
    """Run every JSON-writing command once; return ``{name: (path or printed text)}``."""
    folder = tmp_path_factory.mktemp("json")
    session = deadweight_session(make_sensor("5051", seed=0), n_patches=8, seed=1)
    manifest = session.write(folder / "session")
    rec = folder / "session" / session.manifest_rows()[0]["file"]
    sweep = sine_sweep(seed=0, step_hz=2, cycles_high=10, **FAST)
    blind = random_sine_sets(seed=5, **FAST)
    for name, series in (("sweep_s", sweep.sensor), ("sweep_r", sweep.reference),
                         ("blind_s", blind.sensor), ("blind_r", blind.reference)):
        write_timeseries(series, folder / f"{name}.csv")
    out = {}

    def run(name, argv):
        assert main(["-q", *map(str, argv)]) == 0, name

    run("calibrate", ["calibrate", manifest, "--method", "power", "--out",
                      folder / "cal.json"])
    out["calibrate"] = folder / "cal.json"
    run("equilibrate", ["equilibrate", rec, "--out", folder / "eq.json"])
    out["equilibrate"] = folder / "eq.json"
    # a given model (auto's choice on this sweep): auto's cross-validated choice, and its
    # model choice read back by tactilecal.load, are tests/test_dynamic_family.py's
    run("dynamic fit", ["dynamic", "fit", folder / "sweep_s.csv", folder / "sweep_r.csv",
                        "--model", "log10", "--out", folder / "FILTER.json"])
    out["dynamic fit"] = folder / "FILTER.json"
    run("dynamic evaluate", ["dynamic", "evaluate", folder / "FILTER.json",
                             folder / "blind_s.csv", folder / "blind_r.csv", "--out",
                             folder / "blind"])
    out["dynamic evaluate"] = folder / "blind" / "evaluation.json"
    return folder, manifest, out


@pytest.mark.parametrize(("command", "cls"), [
    ("calibrate", CalibrationResult), ("equilibrate", Equilibration),
    ("dynamic fit", CorrectionFilter), ("dynamic evaluate", Evaluation)])
def test_a_written_json_loads_as_its_kind(written, command, cls):
    path = written[2][command]
    loaded = tactilecal.load(path)
    assert type(loaded) is cls
    assert loaded == cls.from_json(path)  # one reader, equal by value


@pytest.mark.parametrize(("argv", "cls"), [
    (["calibrate", "MANIFEST", "--method", "power", "--json"], CalibrationResult),
    (["validate", "CAL", "MANIFEST", "--json"], ValidationResult),
    (["dynamic", "fit", "SWEEP_S", "SWEEP_R", "--model", "log10", "--out", "F2", "--json"],
     CorrectionFilter),  # a given model, as the fixture's: auto is not the point here
])
def test_a_printed_json_loads_as_its_kind(written, argv, cls, capsys, tmp_path):
    folder, manifest, out = written
    names = {"MANIFEST": manifest, "CAL": out["calibrate"], "SWEEP_S": folder / "sweep_s.csv",
             "SWEEP_R": folder / "sweep_r.csv", "F2": tmp_path / "F2.json"}
    capsys.readouterr()
    assert main(["-q", *(str(names.get(a, a)) for a in argv)]) == 0
    printed = capsys.readouterr().out
    path = tmp_path / "printed.json"
    path.write_text(printed)
    loaded = tactilecal.load(path)
    assert type(loaded) is cls
    assert json.loads(printed)["format"] == cls.format_tag()
