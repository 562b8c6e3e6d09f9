"""read_tekscan bad input: each error names the file and line and what was expected."""

import re

import numpy as np
import pytest

from tactilecal.io import read_tekscan


def _lines(path):
    return path.read_bytes().decode().split("\n")


def _save(tmp_path, lines, name="broken.csv"):
    path = tmp_path / name
    path.write_bytes("\n".join(lines).encode())
    return path


def _edit(tmp_path, source, line_no, new=None):
    """Copy ``source`` replacing 1-based ``line_no`` (None: delete it)."""
    lines = _lines(source)
    if new is None:
        del lines[line_no - 1]
    else:
        lines[line_no - 1] = new
    return _save(tmp_path, lines, "broken" + source.suffix)


def test_truncated_last_frame(iscan_csv, tmp_path):
    lines = _lines(iscan_csv)[:9268 + 10]  # frame 309 header is line 9268; keep 10 rows
    lines.append("@@")
    path = _save(tmp_path, lines)
    with pytest.raises(ValueError, match=rf"frame 309 of {re.escape(str(path))} \(line 9268\) "
                                         r"has 10 rows of values; expected 28 \(ROWS\) "
                                         r"\(truncated file\?\)"):
        read_tekscan(path)


def test_truncated_file_without_terminator(iscan_csv, tmp_path):
    path = _save(tmp_path, _lines(iscan_csv)[:5000])
    with pytest.raises(ValueError, match=r"broken.csv ends at line 5000 without the '@@' "
                                         r"terminator; expected '@@' after the last frame"):
        read_tekscan(path)


def test_frame_missing_a_row_in_the_middle(fscan_asf, tmp_path):
    path = _edit(tmp_path, fscan_asf, 100)  # a row of frame 2 (line 93 is "Frame 2")
    with pytest.raises(ValueError, match=r"frame 2 of .*broken.asf \(line 93\) has 59 rows "
                                         r"of values; expected 60 \(ROWS\)$"):
        read_tekscan(path)


@pytest.mark.parametrize("row, n", [("B,B,5,0", 4), ("B," * 28 + "B", 29)])
def test_row_with_wrong_number_of_values(iscan_csv, tmp_path, row, n):
    path = _edit(tmp_path, iscan_csv, 63, row)  # frame 2 is line 58, its row 4 is line 63
    with pytest.raises(ValueError, match=rf"row 4 of the frame on line 58 of .*broken.csv "
                                         rf"\(line 63\) has {n} values; expected 28 \(COLS\)"):
        read_tekscan(path)


@pytest.mark.parametrize("token", ["x", "", "nan", "1.2.3", "Foo", '"7"', "inf", "-Inf"])
def test_non_numeric_value(iscan_csv, tmp_path, token):
    row = "B,B,0,0," + token + ",0,0,0,0,0,0,0,0,B,B,0,0,0,0,0,0,0,0,0,0,0,B,B"
    path = _edit(tmp_path, iscan_csv, 33, row)
    with pytest.raises(ValueError, match=rf"line 33 of .*broken.csv, value 5: "
                                         rf"{re.escape(repr(token))} is not a finite number; "
                                         r"expected a number or 'B' \(no sensel\)"):
        read_tekscan(path)


@pytest.mark.parametrize("key, line", [("ROWS", 9), ("COLS", 10)])
def test_missing_rows_or_cols(iscan_csv, tmp_path, key, line):
    path = _edit(tmp_path, iscan_csv, line)
    with pytest.raises(ValueError, match=rf"broken.csv has no {key} line in its header "
                                         rf"\(lines 1-25\); expected '{key} <number of sensel"):
        read_tekscan(path)


@pytest.mark.parametrize("content", [b"", b"\r\n  \n"])
def test_empty_file(tmp_path, content):
    path = tmp_path / "empty.asf"
    path.write_bytes(content)
    with pytest.raises(ValueError, match=r"empty.asf is empty; expected a Tekscan ASCII"):
        read_tekscan(path)


@pytest.mark.parametrize("line, new, match", [
    # header values and units
    (23, "UNITS furlongs", r"unknown unit 'furlongs' in UNITS on line 23 of .*broken.csv; "
                           r"expected one of raw, kPa"),
    (11, "ROW_SPACING 0.127 leagues", r"unknown unit 'leagues' in ROW_SPACING on line 11"),
    (13, "SENSEL_AREA 0.016129", r"line 13 of .*: SENSEL_AREA has no unit; expected"),
    (11, "ROW_SPACING wide", r"line 11 of .*: ROW_SPACING is 'wide'; expected a number"),
    (9, "ROWS 28.5", r"line 9 of .*broken.csv: ROWS is '28.5'; expected an integer"),
    # structure: header, frame lines, rows, terminator
    (26, "ASCII DATA", r"broken.csv has no 'ASCII_DATA @@' line \(after 9297 lines\); expected"),
    (3, "12,0,0", r"line 3 of .*: '12,0,0' is not a header line; expected 'KEY value' lines"),
    (5, "ROWS 28", r"line 9 of .*: ROWS appears twice in the header \(first on line 5\)"),
    (58, "Frame 1, 0.1,,,,,Raw Sum=,,307",
     r"line 58 of .*: frame 1 follows frame 1 \(a frame repeated\); expected frame 2: frames "
     "are numbered one by one"),
    (58, "Frame 3, 0.1,,,,,Raw Sum=,,307",
     r"line 58 of .*: frame 3 follows frame 1 \(frames missing or out of order\); expected "
     "frame 2"),
    (58, "Frame 2, soon,,", r"line 58 of .*broken.csv: the frame time is 'soon'; expected a "
                            "number"),
    (58, "Frame 2, nan,,", r"line 58 of .*broken.csv: the frame time is 'nan'; expected a "
                           "number"),
    (58, "Frame 2, 0.1,, 12/2/2019 6:21:52.44PM,,,Raw Sum=,,abc",
     r"line 58 of .*broken.csv: Raw Sum is 'abc'; expected the sum of the frame's readings"),
    (58, "Frame 2, 0.1,, 12/2/2019 6:21:52.44PM,,,Raw Sum=,,",
     r"line 58 of .*broken.csv: Raw Sum is ''; expected the sum of the frame's readings"),
    (58, "Frame 2, 0.1,, 12/2/2019 6:21:52.44PM,,,Raw Sum=,,nan",
     r"line 58 of .*broken.csv: Raw Sum is 'nan'; expected the sum of the frame's readings"),
    (58, "Frame 2 0.1", r"line 58 of .*broken.csv: 'Frame 2 0.1'; expected 'Frame N' optionally"),
    (58, "Frame 2, 0.1,, 12/2/2019 6:21:52.44PM,,,Raw Sum=,,306",
     r"frame 2 of .*broken.csv \(line 58\): Raw Sum in the frame line is 306; expected 307, "
     r"the sum of"),
    (58, "Frames: 2", r"line 58 of .*: 'Frames: 2'; expected 'Frame N' optionally followed"),
    (57, "garbage", r"line 57 of .*: 'garbage'; expected a 'Frame N' line, a row of values"),
    (28, "", r"line 29 of .*: a row of values before the first 'Frame N' line; expected"),
    (9297, "@@ end", r"line 9297 of .*: '@@ end'; expected '@@' \(end of data\)"),
    (9298, "junk", r"line 9298 of .*: 'junk' after the '@@' terminator on line 9297; expected"),
])
def test_edited_line_errors(iscan_csv, tmp_path, line, new, match):
    with pytest.raises(ValueError, match=match):
        read_tekscan(_edit(tmp_path, iscan_csv, line, new))


@pytest.mark.parametrize("new, match", [
    ("CALIBRATION_POINT_1 75 (stone) 4798 (Raw Sum)\r",
     r"unknown unit 'stone' in CALIBRATION_POINT_1 on line 18 of .*broken.asf"),
    ("CALIBRATION_POINT_1 heavy\r", r"line 18 of .*: CALIBRATION_POINT_1 is 'heavy'; "
                                    r"expected '<load> \(<unit>\) <raw sum> \(Raw Sum\)"),
])
def test_bad_calibration_point(fscan_asf, tmp_path, new, match):
    with pytest.raises(ValueError, match=match):
        read_tekscan(_edit(tmp_path, fscan_asf, 18, new))


def test_single_frame_with_wrong_row_count(tmp_path):
    path = _save(tmp_path, ["ROWS 3", "COLS 2", "ASCII_DATA @@", "1,2", "3,4", "@@"])
    with pytest.raises(ValueError, match=r"broken.csv has 2 rows of values and no 'Frame N' "
                                         r"line; expected 3 rows \(ROWS\) for a single frame"):
        read_tekscan(path)


@pytest.mark.parametrize("long_line", [33, 29])  # 29: the first row of the first frame
def test_long_row_balanced_by_a_short_row(iscan_csv, tmp_path, long_line):
    lines = _lines(iscan_csv)
    lines[long_line - 1] += ",0"
    lines[40 - 1] = lines[40 - 1][:-2]  # same number of commas in the file as before
    path = _save(tmp_path, lines)
    with pytest.raises(ValueError, match=rf"\(line {long_line}\) has 29 values; expected 28"):
        read_tekscan(path)


@pytest.mark.parametrize("row", ["3, B", "3,B ", "3,\tB\t", " 3, B", "3 , B "])
def test_spaces_around_b_read_like_spaces_around_numbers(tmp_path, row):
    path = _save(tmp_path, ["ROWS 2", "COLS 2", "ASCII_DATA @@", "Frame 1", "1,2", row, "@@"])
    np.testing.assert_array_equal(read_tekscan(path).values, [[[1, 2], [3, np.nan]]])
    with_number = path.read_text().replace(row, row.replace("B", "0"))
    path.write_text(with_number)
    np.testing.assert_array_equal(read_tekscan(path).values, [[[1, 2], [3, 0]]])
