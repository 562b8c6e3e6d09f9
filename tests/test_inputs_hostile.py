"""Manifests and load-cell CSVs on hostile input (issue 11): encodings, shapes, numbers.

Files are built here (fresh machine, no ``../shared``); each error names file and line.
"""

import numpy as np
import pytest

from tactilecal.calibration import load_points
from tactilecal.io import read_timeseries
from tactilecal.simulate import deadweight_session, make_sensor


@pytest.fixture(scope="module")
def patch_file(tmp_path_factory):
    """One simulated dead-weight recording, ``a.csv``, in its own folder."""
    folder = tmp_path_factory.mktemp("patch")
    session = deadweight_session(make_sensor("5051", seed=0), n_patches=1, seed=3)
    manifest = session.write(folder)
    row = session.manifest_rows()[0]
    return folder / row["file"], int(row["frame"]) if row["frame"] else 1, manifest


def _manifest(folder, text, encoding="utf-8", name="m.csv"):
    path = folder / name
    path.write_bytes(text.encode(encoding))
    return path


@pytest.mark.parametrize("encoding", ["utf-8-sig", "utf-16", "cp1252"])
def test_manifest_in_windows_encodings_reads(patch_file, encoding):
    recording, frame, _ = patch_file
    text = f"file,frame,mass_kg,label\n{recording.name},{frame},2,pad é\n"
    points = load_points(_manifest(recording.parent, text, encoding))
    assert points[0].load_N == pytest.approx(2 * 9.80665) and points[0].label == "pad é"


@pytest.mark.parametrize(("row", "match"), [
    ("{f},{n},2,", r"m.csv has 4 values; expected 3|line 2 of .*m.csv has 4 values; expected 3"),
    ("{f},{n},1_0", r"m.csv line 2: mass_kg is '1_0'; expected a number"),
    ("{f},{n},nan", r"m.csv line 2: mass_kg is 'nan'; expected a number"),
    ("{f},{n},1e308", r"m.csv line 2: mass_kg is 1e\+308; expected a finite number >= 0 and "
                      r"<= 1e\+09"),
    ("{f},{n},-2", r"m.csv line 2: mass_kg is -2.0; expected a finite number >= 0"),
    ("{f},{n},0", r"m.csv line 2: the load in N is 0.0; expected a finite number > 0"),
    ("{f},1.5,2", r"m.csv line 2: frame is 1.5; expected a whole number"),
])
def test_manifest_bad_value_names_the_line(patch_file, row, match):
    recording, frame, _ = patch_file
    text = "file,frame,mass_kg\n" + row.format(f=recording.name, n=frame) + "\n"
    with pytest.raises(ValueError, match=match):
        load_points(_manifest(recording.parent, text))


def test_manifest_pad_mass_nan_is_an_error(patch_file):
    recording, frame, _ = patch_file
    text = f"file,frame,mass_kg,pad_mass_g\n{recording.name},{frame},2,nan\n"
    with pytest.raises(ValueError, match=r"m.csv line 2: pad_mass_g is 'nan'"):
        load_points(_manifest(recording.parent, text))


def test_manifest_lone_carriage_return_is_an_error(patch_file):
    recording, frame, _ = patch_file
    text = f"file,frame,mass_kg\n{recording.name},{frame}\r,2\n"
    with pytest.raises(ValueError, match=r"line 2 of .*m.csv: a carriage return"):
        load_points(_manifest(recording.parent, text))


def test_manifest_with_nul_bytes_is_an_error(patch_file):
    recording, _, _ = patch_file
    path = _manifest(recording.parent, "file,frame,mass_kg\n", "utf-16-le")  # no BOM
    with pytest.raises(ValueError, match=r"line 1 of .*m.csv: a NUL byte"):
        load_points(path)


def _loadcell(tmp_path, text, encoding="utf-8"):
    path = tmp_path / "lc.csv"
    path.write_bytes(text.encode(encoding))
    return path


@pytest.mark.parametrize("encoding", ["utf-8-sig", "utf-16", "cp1252"])
def test_loadcell_in_windows_encodings_reads(tmp_path, encoding):
    series = read_timeseries(_loadcell(tmp_path, "Time (µs),Load (N)\n0,1\n500,2\n", encoding))
    np.testing.assert_allclose(series.time.values, [0.0, 5e-4])
    assert series.values.tolist() == [1.0, 2.0]


@pytest.mark.parametrize(("text", "match"), [
    ("t,x\n0,1\n1,2,3\n2,4\n", r"line 3 of .*lc.csv has 3 values; expected 2"),
    ("t,x\n0,1\n1\r,2\n", r"line 3 of .*lc.csv: a carriage return"),
    ("t,x\n0,1\n1,1_0\n", r"line 3 of .*lc.csv, column 'x': '1_0'; expected a finite number"),
    ("t,x\n0,1\n1,nan\n", r"line 3 of .*lc.csv, column 'x': 'nan'; expected a finite number"),
    ("t,x\n0,1\n0,2\n", r"line 3 of .*lc.csv: time 0 s follows 0 s"),
])
def test_loadcell_bad_row_names_file_and_line(tmp_path, text, match):
    with pytest.raises(ValueError, match=match):
        read_timeseries(_loadcell(tmp_path, text))


@pytest.mark.parametrize(("text", "match"), [
    ("\nTime (ms),Load (N)\n10,0\n2,0\n", r"line 4 of .*lc.csv: time 0.002 s follows 0.01 s"),
    ("\nTime (ms),Load (N)\n..0,0\n2,0\n", r"line 3 of .*lc.csv, column 'Time \(ms\)': '..0'"),
    ("\n\nt,x\n0,1\n\n1,1_0\n", r"line 6 of .*lc.csv, column 'x': '1_0'; expected a finite"),
])
def test_loadcell_lines_are_counted_past_blank_lines(tmp_path, text, match):
    """Found by the property tests: IndexError and KeyError after a leading blank line."""
    with pytest.raises(ValueError, match=match):
        read_timeseries(_loadcell(tmp_path, text))
