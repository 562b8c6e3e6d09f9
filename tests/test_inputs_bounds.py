"""Encodings and bounds of every reader: what an independent fuzz found (issue 31).

Valid input in the encodings Windows software writes is read; NUL, undefined cp1252 bytes and
a lone CR are errors; cells, header lines, JSON strings, numbers and nesting are bounded; every
message names the file and stays under 300 characters whatever the input held.
"""

import json
import os
import re
import signal

import numpy as np
import pytest

import tactilecal
from tactilecal import TactilecalError
from tactilecal._errors import MAX_MESSAGE
from tactilecal.calibration import equilibrate, load_points
from tactilecal.dynamic import read_record
from tactilecal.io import read_netcdf, read_tekscan, read_timeseries, write_tekscan
from tactilecal.simulate import deadweight_session, make_sensor

HEADER = ("DATA_TYPE MOVIE\nSENSOR_TYPE 6900\nROWS 2\nCOLS 3\nSENSITIVITY S-21\n"
          "START_FRAME 1\nEND_FRAME 2\nUNITS raw\nASCII_DATA @@\n")
DATA = "Frame 1, 0,,,Raw Sum=,,6\nB,1,2\n3,0,0\nFrame 2, 0.1,,,Raw Sum=,,0\nB,0,0\n0,0,0\n@@\n"


def _export(tmp_path, header=HEADER, data=DATA, newline="\n", encoding="utf-8"):
    path = tmp_path / "e.csv"
    path.write_bytes((header + data).replace("\n", newline).encode(encoding))
    return path


@pytest.fixture
def plain(tmp_path):
    return read_tekscan(_export(tmp_path / "..", newline="\r\n"))


@pytest.mark.parametrize("encoding", ["utf-8-sig", "utf-16", "utf-16-le-bom", "utf-16-be-bom"])
@pytest.mark.parametrize("newline", ["\n", "\r\n"])
def test_bom_and_utf16_exports_read_as_the_plain_file(tmp_path, plain, encoding, newline):
    bom = {"utf-16-le-bom": b"\xff\xfe", "utf-16-be-bom": b"\xfe\xff"}.get(encoding, b"")
    codec = {"utf-16-le-bom": "utf-16-le", "utf-16-be-bom": "utf-16-be"}.get(encoding, encoding)
    path = tmp_path / "e.csv"
    path.write_bytes(bom + (HEADER + DATA).replace("\n", newline).encode(codec))
    data = read_tekscan(path)
    assert data.drop_attrs().identical(plain.drop_attrs())
    assert data.attrs["source"] == str(path) and data.attrs["sensitivity"] == "S-21"
    assert read_tekscan(path, chunks=1).compute().drop_attrs().identical(plain.drop_attrs())


def test_utf16_export_with_an_error_names_the_original_file_and_line(tmp_path):
    path = _export(tmp_path, data=DATA.replace("3,0,0", "3,x,0"), encoding="utf-16")
    with pytest.raises(TactilecalError, match=r"line 12 of .*e.csv, value 2: 'x' is not a finite"):
        read_tekscan(path)


@pytest.mark.parametrize(("where", "old", "new", "line"), [
    ("header value", "S-21", "S\x00-21", 5),
    ("frame line", "Frame 2, 0.1", "Frame 2\x00, 0.1", 13),
    ("row of values", "3,0,0", "3,0\x00,0", 12),
])
def test_a_nul_byte_anywhere_in_an_export_is_an_error(tmp_path, where, old, new, line):
    path = _export(tmp_path, (HEADER + DATA).replace(old, new), data="")
    with pytest.raises(TactilecalError, match=rf"line {line} of .*e.csv: a NUL byte"):
        read_tekscan(path)


@pytest.mark.parametrize("byte", [0x81, 0x8D, 0x8F, 0x90, 0x9D])
def test_bytes_undefined_in_cp1252_are_errors(tmp_path, byte):
    path = tmp_path / "e.csv"
    path.write_bytes((HEADER + DATA).encode().replace(b"S-21", b"S" + bytes([byte]) + b"21"))
    with pytest.raises(TactilecalError, match=rf"line 5 of .*e.csv: byte 0x{byte:02x} is not "
                                              r"text \(UTF-8 or Windows cp1252\)"):
        read_tekscan(path)


def test_cp1252_header_reads(tmp_path):
    path = tmp_path / "e.csv"
    path.write_bytes((HEADER.replace("S-21", "S-21 \u00e9t\u00e9") + DATA).encode("cp1252"))
    assert read_tekscan(path).attrs["sensitivity"] == "S-21 \u00e9t\u00e9"


def test_a_lone_cr_inside_a_header_line_is_an_error_not_a_line_break(tmp_path):
    path = _export(tmp_path, HEADER.replace("SENSITIVITY S-21", "SENSITIVITY S\r-21"))
    with pytest.raises(TactilecalError, match=r"line 5 of .*e.csv: a carriage return \(CR\) "
                                              "inside the line"):
        read_tekscan(path)


@pytest.mark.parametrize("unit", ["mm", "cm2", "s", "kg"])
def test_a_unit_that_is_no_pressure_or_force_is_refused_as_the_recordings(tmp_path, unit):
    path = _export(tmp_path, HEADER.replace("UNITS raw", f"UNITS {unit}"))
    with pytest.raises(TactilecalError, match=rf"line 8 of .*e.csv: UNITS is '{unit}', a "
                                              r"\w+; expected the unit of the values"):
        read_tekscan(path)


def test_an_8_mib_header_value_is_refused_without_being_echoed(tmp_path):
    path = _export(tmp_path, HEADER.replace("S-21", "x" * 2**23))
    with pytest.raises(TactilecalError, match=r"line 5 of .*e.csv: a header line of 8388620 "
                                              r"characters; expected at most 131072") as info:
        read_tekscan(path)
    assert len(str(info.value)) <= MAX_MESSAGE


@pytest.mark.parametrize("key", ["ROWS", "SECONDS_PER_FRAME", "ROW_SPACING", "UNITS"])
def test_a_long_bad_header_value_is_cut_in_the_message(tmp_path, key):
    header = HEADER if key in HEADER else HEADER.replace("ROWS 2", f"ROWS 2\n{key} 1")
    lines = [f"{key} {'9' * 100_000}x" if line.startswith(key + " ") else line
             for line in header.split("\n")]
    path = _export(tmp_path, "\n".join(lines))
    with pytest.raises(TactilecalError, match=rf"{key}.* of .*e.csv|of .*e.csv: {key}") as info:
        read_tekscan(path)
    assert len(str(info.value)) <= MAX_MESSAGE and "9" * 100 not in str(info.value)


def test_a_header_without_ascii_data_is_bounded(tmp_path):
    path = tmp_path / "e.csv"
    path.write_bytes(b"ROWS 2\n" * (3 * 2**21))  # 21 MiB of header lines, no data
    with pytest.raises(TactilecalError, match=r"e.csv has no 'ASCII_DATA @@' line in its first "
                                              r"16777216 bytes"):
        read_tekscan(path)


def test_every_error_message_is_capped():
    error = TactilecalError("line 3 of f.csv: ROWS is '" + "9" * 10**6 + "'; expected an integer")
    assert len(str(error)) == MAX_MESSAGE
    assert str(error).startswith("line 3 of f.csv") and str(error).endswith("expected an integer")


# ----------------------------------------------------------------------------- CSV files
@pytest.fixture(scope="module")
def session(tmp_path_factory):
    folder = tmp_path_factory.mktemp("session")
    session = deadweight_session(make_sensor("5051", seed=0), n_patches=1, seed=3)
    session.write(folder)
    row = session.manifest_rows()[0]
    return folder, row["file"]


def test_a_manifest_cell_over_128_kib_is_an_error_naming_the_line(session):
    folder, recording = session
    path = folder / "big.csv"
    path.write_text(f"file,frame,mass_kg,label\n{recording},,2,{'x' * 200_000}\n")
    with pytest.raises(TactilecalError, match=r"line 2 of .*big.csv: field larger than field "
                                              r"limit \(131072\); expected cells of at most"):
        load_points(path)


@pytest.mark.parametrize("target", ["/dev/null", "folder"])
def test_a_manifest_naming_a_device_or_a_folder_names_the_manifest_line(session, target):
    folder, _ = session
    name = "/dev/null" if target == "/dev/null" else str(folder)
    path = folder / "m.csv"
    path.write_text(f"file,frame,mass_kg\n{name},1,2\n")
    what = "is not a regular file" if target == "/dev/null" else "is a folder without Zarr"
    with pytest.raises(TactilecalError, match=rf"^m.csv line 2: .* {what}"):
        load_points(path)


def test_a_loadcell_cell_over_128_kib_is_an_error_naming_the_line(tmp_path):
    path = tmp_path / "lc.csv"
    path.write_text("Time (s),Load (N)\n0,1\n0.1," + "1" * 200_000 + "\n")
    with pytest.raises(TactilecalError, match=r"line 3 of .*lc.csv: field larger than field "
                                              r"limit \(131072\)") as info:
        read_timeseries(path)
    assert len(str(info.value)) <= MAX_MESSAGE


@pytest.mark.parametrize("encoding", ["utf-16", "utf-8-sig"])
def test_a_nul_in_a_utf16_or_bom_csv_is_an_error(tmp_path, encoding):
    path = tmp_path / "lc.csv"
    path.write_bytes("Time (s),Load (N)\n0,1\n0.1,2\x00\n".encode(encoding))
    with pytest.raises(TactilecalError, match=r"line 3 of .*lc.csv: a NUL"):
        read_timeseries(path)


def test_a_folder_or_device_is_not_read_as_an_empty_csv(tmp_path):
    for path in ("/dev/null", tmp_path):
        with pytest.raises(TactilecalError, match=r"is not a regular file .*; expected a CSV"):
            read_timeseries(path)


# ----------------------------------------------------------------------------- JSON files
@pytest.fixture
def eq_json(tmp_path):
    path = tmp_path / "eq.json"
    equilibrate([np.full((1, 2, 2), 50.0)]).to_json(path)
    return path


@pytest.mark.parametrize("depth", [40, 100_000])
def test_deeply_nested_json_is_an_error_naming_the_file(eq_json, depth):
    data = json.loads(eq_json.read_text())
    eq_json.write_text(json.dumps(data)[:-1] + ', "x": ' + "[" * depth + "]" * depth + "}")
    with pytest.raises(TactilecalError, match=r"line 1 of .*eq.json: arrays or objects nested "
                                              r"more than 32 deep"):
        tactilecal.load(eq_json)


def test_a_bracket_inside_a_string_does_not_count_as_nesting(eq_json):
    data = json.loads(eq_json.read_text())
    data["provenance"] = {"note": "[" * 100}
    eq_json.write_text(json.dumps(data))
    assert tactilecal.load(eq_json).provenance["note"] == "[" * 100


def test_a_number_of_5004_digits_is_an_error_naming_the_file(eq_json):
    text = eq_json.read_text().replace('"levels": [', '"levels": [' + "9" * 5004 + ", ", 1)
    eq_json.write_text(text)
    with pytest.raises(TactilecalError, match=r"line \d+ of .*eq.json: a number of 5004 "
                                              r"characters \('99999.*; expected at most 400"):
        tactilecal.load(eq_json)


def test_an_integer_beyond_float64_is_an_error_naming_the_key(eq_json):
    data = json.loads(eq_json.read_text())
    data["gain"][0][0] = 10**350
    eq_json.write_text(json.dumps(data))
    with pytest.raises(TactilecalError, match=r"key 'gain' of .*eq.json, row 0 col 0 is "
                                              r"1000.*; expected a finite number > 0") as info:
        tactilecal.load(eq_json)
    assert len(str(info.value)) <= MAX_MESSAGE


def test_a_nul_character_in_a_json_string_is_an_error(eq_json):
    data = json.loads(eq_json.read_text())
    data["provenance"] = {"note": "a\x00b"}
    eq_json.write_text(json.dumps(data))
    with pytest.raises(TactilecalError, match=r"line 1 of .*eq.json: a NUL character"):
        tactilecal.load(eq_json)


def test_a_json_string_over_128_kib_is_an_error(eq_json):
    data = json.loads(eq_json.read_text())
    data["provenance"] = {"note": "x" * 200_000}
    eq_json.write_text(json.dumps(data))
    with pytest.raises(TactilecalError, match=r"eq.json: a string of 200000 characters; expected "
                                              r"at most 131072"):
        tactilecal.load(eq_json)


def test_a_device_is_no_json(tmp_path):
    with pytest.raises(TactilecalError, match=r"/dev/null is not a regular file"):
        tactilecal.load("/dev/null")


def _lut_calibration(tmp_path):
    from tactilecal.calibration import calibrate, points_from_frames

    frames = np.zeros((4, 4, 4))
    for k, level in enumerate((20, 60, 120, 200)):
        frames[k, 1:3, 1:3] = level
    cal = calibrate(points_from_frames(frames, [4 * 0.0035 * v ** 1.2 for v in (20, 60, 120, 200)],
                                       sensel_area_mm2=1.6129), method="lut")
    path = tmp_path / "cal.json"
    cal.to_json(path)
    data = json.loads(path.read_text())
    data["params"]["force_N"][1] = [1.0, 2.0]
    path.write_text(json.dumps(data))
    return path


def test_a_list_inside_params_force_n_names_the_file_and_key(tmp_path):
    """numpy's "inhomogeneous shape" used to reach the user without the file's name."""
    with pytest.raises(TactilecalError, match=r"key 'params.force_N' of \S*cal.json, entry 1 "
                                              r"is \[1.0, 2.0\] \(list\); expected a number"):
        tactilecal.load(_lut_calibration(tmp_path))


def test_writing_and_reading_a_bom_export_round_trips(tmp_path, plain):
    out = tmp_path / "w.csv"
    write_tekscan(plain, out)
    out.write_bytes(b"\xef\xbb\xbf" + out.read_bytes())
    assert read_tekscan(out).drop_attrs().identical(plain.drop_attrs())


# ------------------------------------------------------------ paths that are no regular file
READERS = [read_tekscan, read_timeseries, read_netcdf, tactilecal.load, load_points,
           read_record]


def _timed_out(signum, frame):
    raise TimeoutError("the reader waited on a named pipe")


@pytest.mark.parametrize("kind", ["folder", "device", "fifo"])
@pytest.mark.parametrize("reader", READERS, ids=lambda f: f.__name__)
def test_every_reader_refuses_a_path_that_is_no_regular_file(tmp_path, reader, kind):
    """A folder, a device or a named pipe is named as such: never read as an empty file, never
    a bare OSError, and a pipe is not opened (the read would wait for a writer forever)."""
    path = {"folder": tmp_path, "device": "/dev/null", "fifo": tmp_path / "pipe"}[kind]
    if kind == "fifo":
        os.mkfifo(path)
    previous = signal.signal(signal.SIGALRM, _timed_out)
    signal.alarm(10)  # a reader that opens the pipe fails the test instead of hanging it
    try:
        with pytest.raises(TactilecalError, match=rf"^{re.escape(str(path))} is not a regular "
                                                  r"file \(a (folder|device)"):
            reader(path)
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, previous)


def test_header_law_given_a_path_says_to_read_the_file_first(tmp_path):
    from tactilecal.calibration import header_calibration
    from tactilecal.io import header_law

    for function in (header_law, header_calibration):
        with pytest.raises(TypeError, match=r"not the path .*x.csv; read it with "
                                            r"tactilecal.io.read_tekscan first"):
            function(tmp_path / "x.csv")
