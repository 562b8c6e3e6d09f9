"""read_tekscan at scale (issue 16): exact values, block boundaries, the lazy dask read.

Known truths: a float written with ``repr`` (or with 17 significant digits) reads back as the
same float; the lazy read of a file equals its eager read; every file is built here except
the real exports, which have their own fixtures.
"""

import re

import numpy as np
import pytest
import xarray as xr

from tactilecal.io import _tekscan_index, _tekscan_read, read_tekscan


def _movie(tmp_path, values, *, units="raw", newline="\n", sep=",", fmt=None, name="m.csv",
           raw_sums=False):
    """Write ``values`` (frames, rows, cols; NaN as B) in the I-Scan layout with times."""
    fmt = fmt or (lambda v: repr(float(v)))
    n, rows, cols = values.shape
    lines = [f"ROWS {rows}", f"COLS {cols}", f"UNITS {units}", "SECONDS_PER_FRAME 0.01",
             "ASCII_DATA @@", ""]
    for k in range(n):
        total = f",,,Raw Sum=,,{np.nansum(values[k]):.0f}" if raw_sums else ""
        lines.append(f"Frame {k + 1}, {k * 0.01:.2f},, 1/1/2020 1:00:00.00PM{total}")
        for row in values[k]:
            lines.append(sep.join("B" if np.isnan(v) else fmt(v) for v in row))
        lines.append("")
    lines.append("@@")
    path = tmp_path / name
    path.write_bytes((newline.join(lines) + newline).encode())
    return path


def _raw_values(n=12, rows=5, cols=7, seed=0):
    rng = np.random.default_rng(seed)
    values = rng.integers(0, 256, size=(n, rows, cols)).astype(float)
    values[:, 0, :2] = np.nan
    return values


def test_decimals_written_with_repr_read_back_exactly(tmp_path):
    values = np.random.default_rng(1).normal(0, 1e3, size=(20, 10, 30))
    values[:, 3, 4] = np.nan
    data = read_tekscan(_movie(tmp_path, values, units="kPa"))
    np.testing.assert_array_equal(data.values, values)


def test_seventeen_digit_exponents_read_back_exactly(tmp_path):
    """6000 values of 17 significant digits: more than the kernel leaves to Python at once."""
    values = np.random.default_rng(2).lognormal(0, 30, size=(20, 10, 30))
    path = _movie(tmp_path, values, units="kPa", fmt=lambda v: f"{v:.16e}")
    np.testing.assert_array_equal(read_tekscan(path).values, values)


@pytest.mark.parametrize("token", ["+5", "-0", ".5", "5.", "1E+02", "2.5E-3", " 5", "5\t",
                                   "12345678901234567890", "3.14159265358979323846",
                                   "1e-400", "0e500", "0.1", "007.50", "-.5e1"])
def test_each_accepted_number_reads_as_python_float(tmp_path, token):
    text = f"ROWS 1\nCOLS 3\nUNITS kPa\nASCII_DATA @@\nFrame 1\n1,{token},2\n@@\n"
    (tmp_path / "t.csv").write_text(text)
    value = read_tekscan(tmp_path / "t.csv").values[0, 0, 1]
    assert value == float(token) and np.signbit(value) == np.signbit(float(token))


@pytest.mark.parametrize("newline", ["\n", "\r\n"])
@pytest.mark.parametrize("block_bytes", [1, 37, 1000])
def test_blocks_smaller_than_a_line_or_a_frame_read_the_same(tmp_path, monkeypatch,
                                                             newline, block_bytes):
    values = _raw_values()
    path = _movie(tmp_path, values, newline=newline, raw_sums=True)
    whole = read_tekscan(path)
    monkeypatch.setattr(_tekscan_read, "PLAIN_MAX_BYTES", 0)  # the numba reader, not NumPy's
    monkeypatch.setattr(_tekscan_index, "BLOCK_BYTES", block_bytes)
    data = read_tekscan(path)
    np.testing.assert_array_equal(data.values, values)
    assert data.identical(whole)


def test_lazy_read_equals_eager_read_on_simulated_files(tmp_path):
    values = _raw_values(n=10)
    path = _movie(tmp_path, values, raw_sums=True)
    eager = read_tekscan(path)
    for chunks in (1, 3, 10, 50):
        lazy = read_tekscan(path, chunks=chunks)
        assert lazy.chunks[0] == tuple(np.diff(np.r_[0:10:chunks, 10]))
        assert lazy.identical(eager)
        assert lazy.compute().identical(eager)


@pytest.mark.parametrize("fixture, chunks", [("iscan_csv", 50), ("fscan_asf", 64),
                                             ("fscan_right_asf", 1000)])
def test_lazy_read_equals_eager_read_on_real_exports(request, fixture, chunks):
    path = request.getfixturevalue(fixture)
    lazy, eager = read_tekscan(path, chunks=chunks), read_tekscan(path)
    assert lazy.chunks is not None and lazy.identical(eager)


def test_lazy_read_is_one_task_per_block_without_data_in_the_graph(iscan_csv):
    lazy = read_tekscan(iscan_csv, chunks=100)
    graph = dict(lazy.data.__dask_graph__())
    tasks = [key for key in graph if str(key[0] if isinstance(key, tuple) else key)
             .startswith("read_tekscan-")]
    assert len(tasks) == 4  # 309 frames in blocks of 100
    import pickle

    assert len(pickle.dumps(graph)) < 50_000  # offsets and line numbers only: no values


def test_structural_fault_raises_when_indexing_with_the_eager_message(iscan_csv, tmp_path):
    lines = iscan_csv.read_bytes().decode().split("\n")[:9268 + 10] + ["@@"]
    path = tmp_path / "broken.csv"
    path.write_bytes("\n".join(lines).encode())
    message = rf"frame 309 of {re.escape(str(path))} \(line 9268\) has 10 rows of values"
    for chunks in (None, 20):
        with pytest.raises(ValueError, match=message):
            read_tekscan(path, chunks=chunks)


def _broken_movie(tmp_path, frame, row, value):
    values = _raw_values(n=6)
    path = _movie(tmp_path, values, raw_sums=True)
    lines = path.read_text().split("\n")
    at = lines.index(f"Frame {frame + 1}, {frame * 0.01:.2f},, 1/1/2020 1:00:00.00PM,,,Raw "
                     f"Sum=,,{np.nansum(values[frame]):.0f}") + 1 + row
    cells = lines[at].split(",")
    original, cells[3] = float(cells[3]), value
    lines[at] = ",".join(cells)
    path.write_text("\n".join(lines))
    return path, at + 1, original


@pytest.mark.parametrize("value, message", [
    ("x", r"value 4: 'x' is not a finite number; expected a number or 'B'"),
    ("1e999", r"value 4: '1e999' is not a finite number"),
    ("300", r"value 4: 300; expected a whole number 0..255 \(UNITS raw\)"),
])
def test_bad_value_in_a_block_raises_when_that_block_is_computed(tmp_path, value, message):
    path, line, _ = _broken_movie(tmp_path, frame=4, row=2, value=value)
    lazy = read_tekscan(path, chunks=2)  # frame 5 is in the third block
    assert lazy.isel(frame=slice(0, 4)).values.shape == (4, 5, 7)
    with pytest.raises(ValueError, match=rf"line {line} of {re.escape(str(path))}, {message}"):
        lazy.compute()
    with pytest.raises(ValueError, match=rf"line {line} of .*m.csv, {message}"):
        read_tekscan(path)


def test_raw_sum_mismatch_raises_when_its_block_is_computed(tmp_path):
    path, _, original = _broken_movie(tmp_path, frame=3, row=1, value="0")
    if original == 0:
        path, _, _ = _broken_movie(tmp_path, frame=3, row=1, value="1")
    lazy = read_tekscan(path, chunks=3)
    with pytest.raises(ValueError, match=r"frame 4 of .*m.csv \(line \d+\): Raw Sum in the "
                                         r"frame line is \d+; expected \d+, the sum of"):
        lazy.compute()


def test_file_changed_after_indexing_raises_when_computed(tmp_path):
    path = _movie(tmp_path, _raw_values(n=4))
    lazy = read_tekscan(path, chunks=2)
    path.write_bytes(path.read_bytes().replace(b"Frame 3", b"Frame 3\n0,0,0,0,0,0,0"))
    with pytest.raises(ValueError, match=r"m.csv changed since it was indexed"):
        lazy.compute()


@pytest.mark.parametrize("chunks, error, message", [
    (0, ValueError, r"chunks is 0; expected at least 1 frame per block"),
    (2.5, TypeError, r"chunks is 2.5; expected a whole number of frames per block"),
    (True, TypeError, r"chunks is True; expected a whole number"),
])
def test_bad_chunks_is_an_error(tmp_path, chunks, error, message):
    with pytest.raises(error, match=message):
        read_tekscan(_movie(tmp_path, _raw_values(n=2)), chunks=chunks)


def test_lazy_read_writes_to_netcdf_like_the_eager_read(tmp_path):
    path = _movie(tmp_path, _raw_values(n=5), raw_sums=True)
    read_tekscan(path, chunks=2).to_netcdf(tmp_path / "lazy.nc", engine="h5netcdf")
    back = xr.load_dataarray(tmp_path / "lazy.nc", engine="h5netcdf")
    assert back.identical(read_tekscan(path))


@pytest.mark.parametrize("frame_line, time_s", [
    ("Frame 1, 0.5,, 12 févr. 2019 18:21,,,Raw Sum=,,8", 0.5),  # not ASCII: parsed by regex
    ("Frame 1,0.5", 0.5), ("Frame\t1 , 15 ,x", 15.0), ("Frame 1", 0.0),
    ("Frame 1,, 5", 0.0), ("Frame 1 ", 0.0), ("Frame 01, 5e-1,,,Raw Sum = ,, 8.", 0.5),
])
def test_frame_line_forms_give_number_time_and_raw_sum(tmp_path, frame_line, time_s):
    text = f"ROWS 1\nCOLS 3\nUNITS raw\nASCII_DATA @@\n{frame_line}\n1,2,5\n@@\n"
    (tmp_path / "f.csv").write_bytes(text.encode())
    data = read_tekscan(tmp_path / "f.csv")
    assert data.frame.values.tolist() == [1] and data.time.values.tolist() == [time_s]


@pytest.mark.parametrize("frame_line, match", [
    ("Frame\t1 , 1_5 ,x", r"the frame time is '1_5'; expected a number"),  # was read as 15
    ("Frame 1, nan", r"the frame time is 'nan'; expected a number"),  # was read as no time
    ("Frame 1x, 2", r"'Frame 1x, 2'; expected 'Frame N' optionally"),  # was read as frame 1
    ("Frame 1 -5", r"'Frame 1 -5'; expected 'Frame N' optionally"),
    ("Frame 1, 0,,,Raw Sum=,,8x", r"Raw Sum is '8x'; expected the sum"),
    ("Frame 1, 0,, févr.,,,Raw Sum=,,x", r"Raw Sum is 'x'; expected the sum"),
])
def test_frame_line_forms_once_misread_are_errors(tmp_path, frame_line, match):
    text = f"ROWS 1\nCOLS 3\nUNITS raw\nASCII_DATA @@\n{frame_line}\n1,2,5\n@@\n"
    (tmp_path / "f.csv").write_bytes(text.encode())
    with pytest.raises(ValueError, match=r"line 5 of .*f.csv: " + match):
        read_tekscan(tmp_path / "f.csv")


def test_raw_sum_of_a_frame_line_outside_ascii_is_checked(tmp_path):
    text = "ROWS 1\nCOLS 2\nUNITS raw\nASCII_DATA @@\nFrame 1, 0,, févr.,,,Raw Sum=,,4\n1,2\n@@\n"
    (tmp_path / "f.csv").write_bytes(text.encode())
    with pytest.raises(ValueError, match=r"frame 1 of .*f.csv \(line 5\): Raw Sum in the frame "
                                         r"line is 4; expected 3"):
        read_tekscan(tmp_path / "f.csv")


def test_frame_number_beyond_int64_is_an_error(tmp_path):
    text = f"ROWS 1\nCOLS 1\nASCII_DATA @@\nFrame {2**64}\n1\n@@\n"
    (tmp_path / "f.csv").write_text(text)
    with pytest.raises(ValueError, match=rf"line 4 of .*f.csv: frame number {2**64}; "
                                         r"expected at most 2\*\*63 - 1"):
        read_tekscan(tmp_path / "f.csv")


def test_f_inside_a_row_is_reported_before_an_earlier_bad_value(tmp_path):
    """As before issue 16 (pandas read the F as a comment): the row holding F is named."""
    text = "ROWS 2\nCOLS 3\nUNITS raw\nASCII_DATA @@\nFrame 1\n1,x,3\n1,F,3\n@@\n"
    (tmp_path / "f.csv").write_text(text)
    with pytest.raises(ValueError, match=r"line 7 of .*f.csv, value 2: 'F' is not a finite"):
        read_tekscan(tmp_path / "f.csv")


def test_lazy_read_limits_the_block_not_the_file(tmp_path, monkeypatch):
    """The eager read refuses more than MAX_VALUES values; the lazy one only a bigger block."""
    import tactilecal._validate as validate

    path = _movie(tmp_path, _raw_values(n=6))  # 6 frames of 35 values
    monkeypatch.setattr(validate.check_size, "__kwdefaults__", {"limit": 100})
    with pytest.raises(ValueError, match=r"m.csv: 210 values; expected at most 100"):
        read_tekscan(path)
    assert read_tekscan(path, chunks=2).shape == (6, 5, 7)
    with pytest.raises(ValueError, match=r"m.csv: a block of 3 frames \(chunks\): 105 values; "
                                         r"expected at most 100"):
        read_tekscan(path, chunks=3)


def test_rows_wider_than_the_slow_number_buffer_read_exactly(tmp_path):
    """5000 values of 20 significant digits in one row: all converted by Python's float."""
    tokens = [f"{1 + i / 7:.19f}" for i in range(5000)]
    text = f"ROWS 1\nCOLS 5000\nUNITS kPa\nASCII_DATA @@\nFrame 1\n{','.join(tokens)}\n@@\n"
    (tmp_path / "wide.csv").write_text(text)
    values = read_tekscan(tmp_path / "wide.csv").values.ravel()
    assert values.tolist() == [float(t) for t in tokens]


def test_eager_read_reports_faults_in_file_order_whatever_block_finds_them(tmp_path,
                                                                          monkeypatch):
    """Not-a-number before out-of-range (as before issue 16), and the first of each kind."""
    values = _raw_values(n=8)
    path = _movie(tmp_path, values)
    lines = path.read_text().split("\n")
    rows = [i for i, line in enumerate(lines) if line[:1].isdigit() or line[:1] == "B"]
    for i, token in ((rows[3], "300"), (rows[25], "x"), (rows[33], "y")):
        cells = lines[i].split(",")
        cells[4] = token
        lines[i] = ",".join(cells)
    path.write_text("\n".join(lines))
    monkeypatch.setattr(_tekscan_index, "BLOCK_BYTES", 100)  # about one frame a block
    with pytest.raises(ValueError, match=rf"line {rows[25] + 1} of .*m.csv, value 5: 'x'"):
        read_tekscan(path)
    lines[rows[25]] = lines[rows[25]].replace("x", "7")
    lines[rows[33]] = lines[rows[33]].replace("y", "7")
    path.write_text("\n".join(lines))
    with pytest.raises(ValueError, match=rf"line {rows[3] + 1} of .*m.csv, value 5: 300;"):
        read_tekscan(path)


def test_lazy_read_of_a_relative_path_computes_from_another_working_directory(tmp_path,
                                                                              monkeypatch):
    """A dask worker may run in another folder: the blocks open the file by its full path."""
    values = _raw_values(n=6)
    (tmp_path / "data").mkdir()
    _movie(tmp_path / "data", values)
    monkeypatch.chdir(tmp_path / "data")
    lazy = read_tekscan("m.csv", chunks=4)
    assert lazy.attrs["source"] == "m.csv"  # messages keep the name as given
    monkeypatch.chdir(tmp_path)
    np.testing.assert_array_equal(lazy.values, values)


def test_eager_read_does_not_import_distributed(iscan_csv):
    """dask.compute with a named scheduler imports ``distributed`` (seconds) to find a client."""
    import subprocess
    import sys

    code = ("import sys, tactilecal.io as tio\n"
            f"assert tio.read_tekscan({str(iscan_csv)!r}).shape == (309, 28, 28)\n"
            "print('distributed' in sys.modules)\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True)
    assert out.stdout.split() == ["False"]
