"""read_tekscan on hostile input (issue 11): sizes, values, header numbers, frame times.

Every file is built here, so these run on a fresh machine without ``../shared``. Each test is
named after the input class it covers; each error must name the file and the line or key.
"""

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
    with pytest.raises(ValueError, match=rf"frame {frame} of .*hostile.csv \(line \d+\): time "
                                         r".* does not come after"):
        read_tekscan(_file(tmp_path, times=times))


@pytest.mark.parametrize("time", ["inf", "nan"])
def test_frame_time_not_finite_is_an_error(tmp_path, time):
    path = _file(tmp_path, times=[0, time, 0.2])
    match = r"frame 2 of .*hostile.csv \(line \d+\): time .*; expected a finite time"
    if time == "nan":  # NaN reads as "no time in the frame line"; then the index time is used
        assert read_tekscan(path).time.values[1] == pytest.approx(0.1)
        return
    with pytest.raises(ValueError, match=match):
        read_tekscan(path)


def test_uneven_increasing_frame_times_read(tmp_path):
    """I-Scan 6.10I steps 0.10 / 0.11 s between frames: not an error for the reader."""
    data = read_tekscan(_file(tmp_path, times=[0, 0.1, 0.21]))
    assert np.diff(data.time.values) == pytest.approx([0.1, 0.11])


def test_file_without_units_is_read_as_raw_and_says_so(tmp_path):
    data = read_tekscan(_file(tmp_path, drop=("UNITS",)))
    assert data.attrs["units"] == "raw" and "no UNITS line" in data.attrs["units_note"]
