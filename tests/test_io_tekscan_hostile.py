"""read_tekscan on hostile input (issue 11): sizes, values, header numbers, frame times.

Every file is built here, so these run on a fresh machine without ``../shared``. Each test is
named after the input class it covers; each error must name the file and the line or key.
"""

import subprocess
import sys
import tracemalloc

import numpy as np
import pytest

from tactilecal.io import read_tekscan

HEADER = {"ROWS": "2", "COLS": "3", "ROW_SPACING": "0.127 centimeters",
          "COL_SPACING": "0.127 centimeters", "SENSEL_AREA": "0.016129 cm2",
          "NOISE_THRESHOLD": "3", "SECONDS_PER_FRAME": "0.1", "START_FRAME": "1",
          "END_FRAME": "3", "UNITS": "raw"}
ROWS = [["0,5,B", "4,0,9"], ["0,0,B", "10,255,0"], ["7,0,B", "0,0,0"]]


def _file(tmp_path, header=None, rows=None, times=None, drop=(), newline="\n"):
    """A 3-frame, 2 x 3 I-Scan movie; ``header`` updates keys, ``drop`` removes them."""
    keys = {**HEADER, **(header or {})}
    lines = [f"{k} {v}" for k, v in keys.items() if k not in drop] + ["ASCII_DATA @@", ""]
    for n, frame in enumerate(rows or ROWS, start=1):
        time = "" if times is None else f", {times[n - 1]},,"
        lines += [f"Frame {n}{time}", *frame, ""]
    path = tmp_path / "hostile.csv"
    path.write_bytes(newline.join(lines + ["@@", ""]).encode())
    return path


def _line_of(path, text):
    return path.read_text().splitlines().index(text) + 1


def test_the_template_reads(tmp_path):
    data = read_tekscan(_file(tmp_path, times=[0, 0.1, 0.21]))
    assert data.shape == (3, 2, 3) and data.time.values.tolist() == [0, 0.1, 0.21]


@pytest.mark.parametrize("cols", ["100000000", "99999999999999999999"])
def test_huge_cols_is_an_error_before_allocating(tmp_path, cols):
    path = _file(tmp_path, {"COLS": cols})
    # the first read loads numba's kernels (about 20-35 MB, once per process, traced too):
    # the bound is on what the read itself allocates, measured on the second read
    with pytest.raises(ValueError, match=rf"hostile.csv.* has 3 values; expected {cols} \(COLS"):
        read_tekscan(path)
    tracemalloc.start()
    with pytest.raises(ValueError, match=rf"hostile.csv.* has 3 values; expected {cols} \(COLS"):
        read_tekscan(path)
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    assert peak < 10e6


def test_cols_smaller_than_the_rows_is_an_error(tmp_path):
    path = _file(tmp_path, {"COLS": "2"})
    with pytest.raises(ValueError, match=r"hostile.csv \(line 1\d\) has 3 values; expected 2"):
        read_tekscan(path)


@pytest.mark.parametrize("value", ["256", "-1", "0.5", "1e308"])
def test_raw_value_outside_0_255_is_an_error(tmp_path, value):
    rows = [["0,5,B", f"4,{value},9"], *ROWS[1:]]
    path = _file(tmp_path, rows=rows)
    line = _line_of(path, f"4,{value},9")
    with pytest.raises(ValueError, match=rf"line {line} of .*hostile.csv, value 2: .*; expected "
                                         r"a whole number 0..255 \(UNITS raw\)"):
        read_tekscan(path)


def test_file_without_units_and_values_above_255_is_an_error(tmp_path):
    rows = [["0,5,B", "4,300,9"], *ROWS[1:]]
    with pytest.raises(ValueError, match=r"value 2: 300; expected a whole number 0..255: the "
                                         "file has no UNITS line"):
        read_tekscan(_file(tmp_path, rows=rows, drop=("UNITS",)))


def test_calibrated_values_are_not_read_as_raw(tmp_path):
    rows = [["0,5.5,B", "4,300,9"], *ROWS[1:]]
    data = read_tekscan(_file(tmp_path, {"UNITS": "KPa"}, rows=rows))
    assert data.attrs["units"] == "kPa" and np.nanmax(data.values) == 300


def test_underscore_inside_a_value_is_an_error(tmp_path):
    rows = [["0,5,B", "4,1_0,9"], *ROWS[1:]]
    path = _file(tmp_path, rows=rows)
    with pytest.raises(ValueError, match=rf"line {_line_of(path, '4,1_0,9')} of .*hostile.csv: "
                                         r".* has '_' inside a value"):
        read_tekscan(path)


@pytest.mark.parametrize("row", ["4,0\r,9", "4,\r0,9", "4\r,0,9"])
def test_lone_carriage_return_inside_a_row_is_an_error(tmp_path, row):
    rows = [["0,5,B", row], *ROWS[1:]]
    path = _file(tmp_path, rows=rows)
    with pytest.raises(ValueError, match=r"line 1\d of .*hostile.csv: a carriage return"):
        read_tekscan(path)


def test_crlf_line_ends_still_read(tmp_path):
    assert read_tekscan(_file(tmp_path, newline="\r\n")).shape == (3, 2, 3)


@pytest.mark.parametrize(("key", "value"), [
    ("SECONDS_PER_FRAME", "0"), ("SECONDS_PER_FRAME", "-0.1"), ("SECONDS_PER_FRAME", "1e308"),
    ("NOISE_THRESHOLD", "-5"), ("NOISE_THRESHOLD", "300"), ("SENSEL_AREA", "-3 mm2"),
    ("SENSEL_AREA", "0 mm2"), ("ROW_SPACING", "0 mm"), ("COL_SPACING", "-1 mm"),
    ("SATURATION_PRESSURE", "-5 kPa")])
def test_impossible_header_number_is_an_error_naming_key_and_line(tmp_path, key, value):
    path = _file(tmp_path, {key: value})
    line = _line_of(path, f"{key} {value}")
    with pytest.raises(ValueError, match=rf"line {line} of .*hostile.csv: {key} \("):
        read_tekscan(path)


@pytest.mark.parametrize(("key", "value"), [("SENSEL_AREA", "1e308 cm2"),
                                            ("ROW_SPACING", "1e308 m")])
def test_header_number_beyond_float_range_in_project_units_is_an_error(tmp_path, key, value):
    path = _file(tmp_path, {key: value})
    line = _line_of(path, f"{key} {value}")
    with pytest.raises(ValueError, match=rf"line {line} of .*hostile.csv: {key} '{value}': "
                                         r"1e\+308 c?m2? is beyond the largest number in mm"):
        read_tekscan(path)


@pytest.mark.parametrize(("key", "value", "which"), [("START_FRAME", "2", "first"),
                                                     ("END_FRAME", "5", "last")])
def test_start_or_end_frame_disagreeing_with_the_frames_is_an_error(tmp_path, key, value,
                                                                    which):
    path = _file(tmp_path, {key: value})
    with pytest.raises(ValueError, match=rf"line \d+ of .*hostile.csv: {key} is '{value}' but "
                                         rf"the {which} frame is"):
        read_tekscan(path)


@pytest.mark.parametrize(("times", "frame"), [([0, 0.1, 0.1], 3), ([0, 0.2, 0.1], 3),
                                              ([0, -1, 0.2], 2)])
def test_frame_times_that_repeat_or_go_backwards_are_an_error(tmp_path, times, frame):
    path = _file(tmp_path, times=times)
    line = _line_of(path, f"Frame {frame}, {times[frame - 1]},,")
    match = (rf"line {line} of .*hostile.csv: frame {frame} has the time .* s, not after frame "
             rf"{frame - 1}'s .* s; expected increasing frame times" if times[frame - 1] >= 0 else
             rf"line {line} of .*hostile.csv: frame {frame} has the time -1 s; expected a finite "
             r"time >= 0 s")
    with pytest.raises(ValueError, match=match):
        read_tekscan(path)


@pytest.mark.parametrize("time", ["inf", "nan", "-inf", "1e999", "1_0", "-"])
def test_frame_time_not_a_finite_number_is_an_error(tmp_path, time):
    path = _file(tmp_path, times=[0, time, 0.2])
    line = _line_of(path, f"Frame 2, {time},,")
    with pytest.raises(ValueError, match=rf"line {line} of .*hostile.csv: the frame time is "):
        read_tekscan(path)


@pytest.mark.parametrize("layout", ["F-Scan (no times)", "I-Scan (times)"])
def test_a_time_on_some_frame_lines_only_is_an_error(tmp_path, layout):
    """F-Scan ``Frame 96, -5`` (issue 31): one frame line with a time among lines without."""
    times = None if layout.startswith("F") else [0, 0.1, 0.2]
    path = _file(tmp_path, times=times)
    text = path.read_text()
    old = "Frame 2" if times is None else "Frame 2, 0.1,,"
    new = "Frame 2, -5" if times is None else "Frame 2"
    path.write_text(text.replace(old + "\n", new + "\n"))
    has, other = ("a time", "none") if times is None else ("no time", "one")
    with pytest.raises(ValueError, match=rf"line {_line_of(path, new)} of .*hostile.csv: frame 2 "
                                         rf"has {has} in its frame line but frame 1 has {other}"):
        read_tekscan(path)


@pytest.mark.parametrize("times", [None, [0, 0.1, 0.2]])
def test_a_deleted_frame_block_is_an_error_in_either_layout(tmp_path, times):
    path = _file(tmp_path, times=times)
    lines = path.read_text().split("\n")
    start = next(k for k, line in enumerate(lines) if line.startswith("Frame 2"))
    path.write_text("\n".join(lines[:start] + lines[start + 4:]))
    with pytest.raises(ValueError, match=r"line \d+ of .*hostile.csv: frame 3 follows frame 1 "
                                         r"\(frames missing or out of order\); expected frame 2"):
        read_tekscan(path)


@pytest.mark.parametrize(("start", "end", "key"), [("1", "4", "END_FRAME"),
                                                    ("0", "2", "START_FRAME")])
def test_a_frame_count_that_disagrees_with_the_header_is_an_error(tmp_path, start, end, key):
    path = _file(tmp_path, {"START_FRAME": start, "END_FRAME": end})
    with pytest.raises(ValueError, match=rf"line \d+ of .*hostile.csv: {key} is '\d' but the "
                                         r"(first|last) frame is \d \(3 frames: frames missing"):
        read_tekscan(path)


def test_a_single_frame_with_a_movie_range_is_an_error(tmp_path):
    path = tmp_path / "single.csv"
    path.write_text("ROWS 1\nCOLS 2\nUNITS raw\nSTART_FRAME 1\nEND_FRAME 309\nASCII_DATA @@\n"
                    "1,2\n@@\n")
    with pytest.raises(ValueError, match=r"line 5 of .*single.csv: END_FRAME is '309' but the last "
                                         r"frame is 1 \(1 frames"):
        read_tekscan(path)


def test_uneven_increasing_frame_times_read(tmp_path):
    """I-Scan 6.10I steps 0.10 / 0.11 s between frames: not an error for the reader."""
    data = read_tekscan(_file(tmp_path, times=[0, 0.1, 0.21]))
    assert np.diff(data.time.values) == pytest.approx([0.1, 0.11])


def test_file_without_units_is_read_as_raw_and_says_so(tmp_path):
    data = read_tekscan(_file(tmp_path, drop=("UNITS",)))
    assert data.attrs["units"] == "raw" and "no UNITS line" in data.attrs["units_note"]


@pytest.mark.parametrize("chunks", [None, 1])
def test_single_frame_raw_value_outside_0_255_is_an_error(tmp_path, chunks):
    """Found by the property tests: the NumPy reader skipped the check for a single frame."""
    path = tmp_path / "single.csv"
    path.write_text("ROWS 2\nCOLS 1\nUNITS raw\nASCII_DATA @@\n256\n0\n@@\n")
    with pytest.raises(ValueError, match=r"line 5 of .*single.csv, value 1: 256; expected a "
                                         r"whole number 0..255"):
        read_tekscan(path, chunks=chunks).compute()


def test_a_line_of_40_mb_without_end_is_refused_before_it_is_held(tmp_path):
    """Memory of a read stays bounded whatever the file (issue 31): 32 MiB a line at most."""
    path = tmp_path / "line.csv"
    with open(path, "wb") as out:
        out.write(b"ROWS 1\nCOLS 3\nASCII_DATA @@\nFrame 1\n")
        out.write(b"1," * (20 * 2**20))
    match = r"line 5 of .*line.csv: more than 33554432 bytes without a line end; expected rows"
    tracemalloc.start()
    with pytest.raises(ValueError, match=match):
        read_tekscan(path)
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    assert peak < 4 * 2**20  # read a MiB at a time, never held


def test_a_line_without_end_is_refused_without_importing_numba(tmp_path):
    """The check runs before either reader: numba's import alone is half the bound."""
    path = tmp_path / "line.csv"
    with open(path, "wb") as out:
        out.write(b"ROWS 1\nCOLS 3\nASCII_DATA @@\nFrame 1\n" + b"1," * (20 * 2**20))
    code = ("import sys; from tactilecal.io import read_tekscan\n"
            f"try:\n    read_tekscan({str(path)!r})\n"
            "except ValueError as exc:\n    print(exc)\n"
            "print('numba' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True).stdout.splitlines()
    assert "more than 33554432 bytes without a line end" in out[0] and out[1] == "False"


@pytest.mark.parametrize("chunks", [None, 2])
@pytest.mark.parametrize("newline", ["\n", "\r\n"])
def test_an_over_long_line_after_frames_is_refused_naming_its_line(tmp_path, monkeypatch,
                                                                   chunks, newline):
    """The limit applies anywhere in the data, eager or lazy; the line is counted exactly."""
    from tactilecal.io import _tekscan_layout

    limit = 40 + len(newline) - 1  # the CR of CR LF is a byte of its line
    monkeypatch.setattr(_tekscan_layout, "max_line_bytes", lambda cols: limit)
    monkeypatch.setattr(_tekscan_layout, "_LINE_STEP", 7)  # pieces smaller than a line
    rows = [list(frame) for frame in ROWS]
    rows[2][1] = "0," * 20 + "0"  # 41 bytes: one over the limit
    path = _file(tmp_path, rows=rows, newline=newline)
    line = _line_of(path, rows[2][1])
    with pytest.raises(ValueError, match=rf"^line {line} of .*hostile.csv: more than {limit} "
                                         r"bytes without a line end; expected rows of 3 values"):
        read_tekscan(path, chunks=chunks)
    rows[2][1] = "0," * 19 + "00"  # 40 bytes: as long as allowed, refused for its values
    path = _file(tmp_path, rows=rows, newline=newline)
    with pytest.raises(ValueError, match=rf"\(line {line}\) has 20 values; expected 3"):
        read_tekscan(path, chunks=chunks)
