"""No command replaces a file it did not write (issue 31): every command that writes, refused.

The commands that write are found by walking the parser: each declares its outputs with
``cli._outputs.add_output``. An existing output is refused without ``--overwrite``; with it,
still refused when it is an input of the command or is not an output of that command (here
a Tekscan export in its place). The file is left as it was.
"""

import argparse

import numpy as np
import pytest

from tactilecal.cli import build_parser, main
from tactilecal.dynamic import CorrectionFilter
from tactilecal.io import write_tekscan
from tactilecal.simulate import deadweight_session, make_sensor

WRITERS = {"analyze", "apply", "calibrate", "compare", "convert", "demo", "equilibrate", "movie",
           "plot", "report", "simulate deadweight", "simulate ramp-hold", "simulate uniform",
           "simulate sweep",
           "simulate blind", "dynamic fit", "dynamic apply", "dynamic evaluate"}


def _leaves(parser, prefix=()):
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for name, sub in action.choices.items():
                yield from _leaves(sub, (*prefix, name))
            return
    yield " ".join(prefix), parser


def test_every_command_that_writes_declares_its_outputs():
    leaves = dict(_leaves(build_parser()))
    declared = {name for name, parser in leaves.items() if parser.get_default("outputs")}
    assert declared == WRITERS
    for name, parser in leaves.items():  # an output argument not declared would escape
        dests = {a.dest for a in parser._actions}
        outputs = {entry[0] for entry in parser.get_default("outputs") or ()}
        assert not ({"out", "outdir"} & dests) - outputs, name
        assert ("overwrite" in dests) == (name in WRITERS), name


@pytest.fixture(scope="module")
def inputs(tmp_path_factory):
    """Small valid inputs of every kind the writing commands read."""
    folder = tmp_path_factory.mktemp("inputs")
    session = deadweight_session(make_sensor("5051", seed=0), n_patches=3, seed=1)
    manifest = session.write(folder / "session")
    rec = folder / "session" / session.manifest_rows()[0]["file"]
    assert main(["-q", "calibrate", str(manifest), "--method", "linear", "--out",
                 str(folder / "cal.json")]) == 0
    CorrectionFilter.from_model(("log10", {"A": 0.11}), fs_hz=100.0,
                                band_hz=(1.0, 20.0)).to_json(folder / "FILTER.json")
    for name in ("sensor", "reference"):  # the refusal comes before they are read
        (folder / f"{name}.csv").write_text("Time (s),Force (N)\n0,1\n0.01,2\n")
    return {"REC": rec, "MANIFEST": manifest, "CAL": folder / "cal.json",
            "FILTER": folder / "FILTER.json", "SENSOR": folder / "sensor.csv",
            "REF": folder / "reference.csv"}


# command -> (argv with OUT, the output's suffix or "/" for a folder)
COMMANDS = {
    "analyze": ("analyze REC --out OUT", ".csv"),
    "apply": ("apply CAL REC --out OUT", ".nc"),
    "calibrate": ("calibrate MANIFEST --out OUT", ".json"),
    "compare": ("compare CAL --out OUT", "/"),
    "convert": ("convert REC OUT", ".nc"),
    "demo": ("demo --out OUT", "/"),
    "equilibrate": ("equilibrate REC --out OUT", ".json"),
    "movie": ("movie REC --out OUT", ".gif"),
    "plot": ("plot CAL --out OUT", "/"),
    "report": ("report CAL --out OUT", ".html"),
    "simulate deadweight": ("simulate deadweight OUT", "/"),
    "simulate ramp-hold": ("simulate ramp-hold OUT", "/"),
    "simulate uniform": ("simulate uniform OUT", "/"),
    "simulate sweep": ("simulate sweep OUT", "/"),
    "simulate blind": ("simulate blind OUT", "/"),
    "dynamic fit": ("dynamic fit SENSOR REF --out OUT", ".json"),
    "dynamic apply": ("dynamic apply FILTER SENSOR --out OUT", ".csv"),
    "dynamic evaluate": ("dynamic evaluate FILTER SENSOR REF --out OUT", "/"),
}


def test_the_table_covers_every_writer():
    assert set(COMMANDS) == WRITERS


def _argv(command, inputs, out):
    return [str(inputs[w]) if w in inputs else str(out) if w == "OUT" else w
            for w in COMMANDS[command][0].split()]


def _victim(inputs, tmp_path, suffix):
    """A Tekscan export where the output goes (a folder holding one, for a folder)."""
    export = inputs["REC"].read_bytes()
    if suffix == "/":
        (tmp_path / "out").mkdir()
        (tmp_path / "out" / "data.asf").write_bytes(export)
        return tmp_path / "out", tmp_path / "out" / "data.asf", export
    path = tmp_path / f"victim{suffix}"
    path.write_bytes(export)
    return path, path, export


@pytest.mark.parametrize("command", sorted(COMMANDS))
def test_an_existing_output_is_refused_with_and_without_overwrite(command, inputs, tmp_path,
                                                                  capsys):
    out, victim, before = _victim(inputs, tmp_path, COMMANDS[command][1])
    argv = _argv(command, inputs, out)
    assert main(argv) == 1
    err = capsys.readouterr().err
    expected = ("holds 1 files; expected a new or empty folder (add --overwrite"
                if out.is_dir() else "exists; expected a new path (add --overwrite to replace it)")
    assert expected in err and len(err.strip().splitlines()) == 1, err
    assert main([*argv, "--overwrite"]) == 1
    err = capsys.readouterr().err
    assert ("data.asf, a Tekscan export, not" in err or "holds files but no" in err
            if out.is_dir() else "is a Tekscan export, not" in err), err
    assert victim.read_bytes() == before


@pytest.mark.parametrize("command", ["analyze", "equilibrate", "convert"])
def test_an_input_as_output_is_refused_even_with_overwrite(command, inputs, capsys):
    argv = _argv(command, inputs, inputs["REC"])
    before = inputs["REC"].read_bytes()
    assert main([*argv, "--overwrite"]) == 1
    assert f"is the input {inputs['REC']}" in capsys.readouterr().err
    assert inputs["REC"].read_bytes() == before


def test_overwrite_replaces_an_own_earlier_output(inputs, tmp_path, capsys):
    out = tmp_path / "cal.json"
    argv = ["-q", "calibrate", str(inputs["MANIFEST"]), "--method", "linear", "--out", str(out)]
    assert main(argv) == 0
    assert main(argv) == 1 and "exists" in capsys.readouterr().err
    assert main([*argv, "--overwrite"]) == 0
    argv = ["-q", "simulate", "deadweight", str(tmp_path / "session"), "--patches", "2"]
    assert main(argv) == 0
    assert main([*argv, "--overwrite", "--seed", "3"]) == 0


def test_python_writers_refuse_an_existing_file_by_default(inputs, tmp_path):
    from tactilecal import load
    from tactilecal.io import read_tekscan

    data = read_tekscan(inputs["REC"])
    out = tmp_path / "copy.csv"
    write_tekscan(data, out)
    with pytest.raises(ValueError, match=r"copy.csv exists; expected a new path \(pass "
                                         r"overwrite=True to replace it\)"):
        write_tekscan(data, out)
    cal = load(inputs["CAL"])
    with pytest.raises(ValueError, match=r"copy.csv is a Tekscan export, not a JSON file"):
        cal.to_json(out, overwrite=True)
    assert np.array_equal(read_tekscan(out).values, data.values, equal_nan=True)
