"""read_timeseries: load-cell CSVs with unit hints, column choice and bad input."""

import numpy as np
import pytest

from tactilecal._units import G_STANDARD, unit_from_column
from tactilecal.io import read_timeseries

LBF_N = 0.45359237 * G_STANDARD


def _csv(tmp_path, text, name="lc.csv"):
    path = tmp_path / name
    path.write_text(text)
    return path


def test_known_ramp_recovered_in_newtons_and_seconds(tmp_path):
    rng = np.random.default_rng(42)
    t_ms = np.arange(0, 2000, 0.2)  # 5000 Hz
    load_lbf = 120 + 20 * np.sin(2 * np.pi * 3 * t_ms / 1000) + rng.normal(0, 0.1, t_ms.size)
    pairs = zip(t_ms.tolist(), load_lbf.tolist(), strict=True)
    lines = ["Time (ms),Load (lbf),Other"] + [f"{t!r},{v!r},x" for t, v in pairs]
    data = read_timeseries(_csv(tmp_path, "\n".join(lines) + "\n\n"))
    assert data.dims == ("time",) and data.dtype == np.float64
    np.testing.assert_allclose(data.time.values, t_ms / 1000, rtol=1e-12)
    np.testing.assert_allclose(data.values, load_lbf * LBF_N, rtol=1e-12)
    assert data.attrs == {"units": "N", "source": str(tmp_path / "lc.csv"),
                          "column": "Load (lbf)", "time_column": "Time (ms)"}


@pytest.mark.parametrize("header, factor, units", [
    ("Force (N)", 1.0, "N"), ("Force [kN]", 1000.0, "N"), ("Load (lb)", LBF_N, "N"),
    ("Mass (kg)", G_STANDARD, "N"), ("Pressure (kPa)", 1.0, "kPa"),
    ("Pressure (MPa)", 1000.0, "kPa"), ("Displacement (mm)", 1.0, "mm"),
    ("load", 1.0, "unknown"),
])
def test_unit_hints(tmp_path, header, factor, units):
    data = read_timeseries(_csv(tmp_path, f"time,{header}\n0,1.5\n0.1,2\n"))
    np.testing.assert_allclose(data.values, np.array([1.5, 2.0]) * factor)
    assert data.attrs["units"] == units and data.time.values.tolist() == [0.0, 0.1]


def test_columns_by_name_and_index(tmp_path):
    path = _csv(tmp_path, "idx,Force (N),Time (s),Load (kN)\n1,10,0,1\n2,20,1,2\n3,30,2,3\n")
    by_name = read_timeseries(path, time_col="Time (s)", value_col="Load (kN)")
    by_index = read_timeseries(path, time_col=2, value_col=-1)
    from_cli = read_timeseries(path, time_col="2", value_col="3")
    assert by_name.identical(by_index) and by_name.identical(from_cli)
    numeric_name = _csv(tmp_path, "t,0,1\n0,5,7\n1,6,8\n", name="n.csv")
    assert read_timeseries(numeric_name, value_col="1").values.tolist() == [7.0, 8.0]
    assert by_name.values.tolist() == [1000.0, 2000.0, 3000.0]


def test_unit_from_column():
    assert unit_from_column("Time (ms)") == "ms" and unit_from_column("F [lbf]") == "lbf"
    assert unit_from_column("Force") is None


@pytest.mark.parametrize("text, kwargs, match", [
    ("t,F\n0,1\n1,2\n", {"value_col": "G"},
     r"value_col='G' is not a column of .*lc.csv; expected one of \['t', 'F'\]"),
    ("t,F\n0,1\n1,2\n", {"time_col": 5}, r"time_col=5 is out of range for .*2 columns"),
    ("t,F\n0,1\n1,abc\n2,3\n", {}, r"line 3 of .*lc.csv, column 'F': 'abc'; expected a finite"),
    ("t,F\n0,1\n1,\n2,3\n", {}, r"line 3 of .*, column 'F': an empty cell; expected a finite"),
    ("t,F\n0,1\n1,nan\n", {}, r"line 3 of .*, column 'F': 'nan'; expected a finite number"),
    ("t,F\n0,1\n\n2,x\n", {}, r"line 4 of .*, column 'F': 'x'; expected"),  # blank skipped
    ("t,F\n0,1\n\n2,3\n2,4\n", {}, r"line 5 of .*: time 2 s follows 2 s"),
    ("t,F\n0,1\n1\n", {}, r"line 3 of .* has 1 values; expected 2, one per column"),
    ("t,F\n0,1\n1,inf\n", {}, r"line 3 of .*, column 'F': 'inf'; expected a finite"),
    ("t,F\n0,1\n", {}, r"lc.csv has 1 data rows; expected at least 2"),
    ("", {}, r"lc.csv is empty; expected a header row"),
    ("t,F\n0,1\n1,2\n1,3\n", {}, r"line 4 of .*: time 1 s follows 1 s; expected strictly incr"),
    ("t (ms),F (furlong)\n0,1\n1,2\n", {},
     r"unknown unit 'furlong' in column 'F \(furlong\)' of .*lc.csv"),
    ("t (N),F\n0,1\n1,2\n", {}, r"time column 't \(N\)' of .* is in 'N'; expected a time"),
])
def test_bad_input(tmp_path, text, kwargs, match):
    with pytest.raises(ValueError, match=match):
        read_timeseries(_csv(tmp_path, text), **kwargs)


def test_blank_lines_carry_no_data(tmp_path):
    data = read_timeseries(_csv(tmp_path, "t (s),F (N)\n0,1\n\n0.5,2\n\n\n"))
    assert data.values.tolist() == [1.0, 2.0] and data.time.values.tolist() == [0.0, 0.5]


@pytest.mark.parametrize("blank", [",", " , ", ",,\t", " "])
def test_lines_of_commas_and_spaces_carry_no_data_either(tmp_path, blank):
    """A spreadsheet's empty row (commas only) is no row, as the row check has it: pandas
    read it as a row of NaN, and the file failed with a message naming no line."""
    text = f"t (s),F (N),note\n0,1,a\n{blank}\n0.5,2,b\n{blank}\n1.5,3.25,c\n{blank}\n"
    data = read_timeseries(_csv(tmp_path, text))
    assert data.values.tolist() == [1.0, 2.0, 3.25]
    assert data.time.values.tolist() == [0.0, 0.5, 1.5]
    with pytest.raises(ValueError, match=r"line 6 of .*: time 0.5 s follows 0.5 s"):
        read_timeseries(_csv(tmp_path, text.replace("1.5,3.25", "0.5,3.25")))


def test_byte_order_mark(tmp_path):
    path = tmp_path / "bom.csv"
    path.write_bytes(b"\xef\xbb\xbfTime (s),Force (N)\r\n0,1\r\n1,2\r\n")
    data = read_timeseries(path)
    assert data.attrs["time_column"] == "Time (s)" and data.values.tolist() == [1.0, 2.0]


def test_write_timeseries_round_trips_exactly(tmp_path):
    from tactilecal import write_timeseries
    from tactilecal.simulate import sine_sweep

    sweep = sine_sweep(f_stop_hz=5, seed=0)
    for series in (sweep.reference, sweep.sensor):
        path = write_timeseries(series, tmp_path / "s.csv", overwrite=True)
        back = read_timeseries(path)
        np.testing.assert_array_equal(back["time"].values, series["time"].values)
        np.testing.assert_array_equal(back.values, series.values)
        assert back.attrs["units"] == series.attrs["units"] == "N"
        assert path.read_text().splitlines()[0] == "Time (s),force (N)"


def test_write_timeseries_refuses_what_it_cannot_read_back(tmp_path):
    import xarray as xr

    from tactilecal.io import write_timeseries

    out = tmp_path / "s.csv"
    out.write_text("previous,table")

    def series(values, times, **attrs):
        return xr.DataArray(values, dims="time", coords={"time": times},
                            attrs={"source": "lc", **attrs})

    with pytest.raises(ValueError, match=r"lc: value at position 1 is nan; expected finite"):
        write_timeseries(series([1.0, np.nan], [0.0, 1.0]), out, overwrite=True)
    with pytest.raises(ValueError, match=r"lc: time 0.5 s at position 2 follows 1 s; expected"):
        write_timeseries(series([1.0, 2.0, 3.0], [0.0, 1.0, 0.5]), out, overwrite=True)
    with pytest.raises(ValueError, match=r"lc: 1 samples; expected at least 2"):
        write_timeseries(series([1.0], [0.0]), out, overwrite=True)
    with pytest.raises(ValueError, match=r"dims \('a', 'b'\) without a 'time' coordinate"):
        write_timeseries(xr.DataArray(np.zeros((2, 2)), dims=("a", "b")), out, overwrite=True)
    assert out.read_text() == "previous,table"  # never replaced by a failed write
    with pytest.raises(ValueError, match=r"s.csv exists; expected a new path"):
        write_timeseries(series([1.0, 2.0], [0.0, 1.0]), out)
    write_timeseries(series([1.0, 2.0], [0.0, 1.0], units="unknown", column="Load"), out,
                     overwrite=True)
    assert out.read_text().splitlines()[0] == "Time (s),Load"


def _wide_csv(path, rows, cols, encoding="utf-8", newline="\n"):
    """A CSV of ``cols`` columns (time in µs first), a blank line, and the values it holds."""
    rng = np.random.default_rng(3)
    values = np.round(rng.normal(size=(rows, cols)), 6)
    values[:, 0] = np.arange(rows) * 0.5
    header = ",".join(["Time (µs)", "Load (kN)"] + [f"c{j}" for j in range(cols - 2)])
    lines = [header] + [",".join(map(repr, row)) for row in values.tolist()]
    lines.insert(rows // 2, "")
    path.write_bytes(newline.join(lines + [""]).encode(encoding))
    return values


@pytest.mark.parametrize(("encoding", "newline"), [("utf-8", "\n"), ("utf-8-sig", "\r\n"),
                                                   ("utf-16", "\r\n"), ("cp1252", "\n")])
def test_a_csv_read_in_small_pieces_reads_the_same(tmp_path, monkeypatch, encoding, newline):
    """The file is read a piece at a time: where the pieces are cut changes nothing."""
    from tactilecal import _textfile

    path = tmp_path / "lc.csv"
    values = _wide_csv(path, 300, 5, encoding, newline)
    whole = read_timeseries(path)
    np.testing.assert_array_equal(whole.time.values, values[:, 0] * 1e-6)
    np.testing.assert_array_equal(whole.values, values[:, 1] * 1000)
    for size in (1, 7, 4096):
        monkeypatch.setattr(_textfile, "PIECE_BYTES", size)
        assert read_timeseries(path).identical(whole), size
    text = path.read_bytes().decode(encoding).replace(f",{float(values[250, 1])!r},", ",x,", 1)
    path.write_bytes(text.encode(encoding))
    with pytest.raises(ValueError, match=r"line 253 of .*lc.csv, column 'Load \(kN\)': 'x'"):
        read_timeseries(path)


def test_a_wide_csv_is_read_without_holding_its_text(tmp_path, monkeypatch):
    """Memory is the two columns and a piece of the file, not the file (40 columns here)."""
    import tracemalloc

    from tactilecal import _textfile

    path = tmp_path / "wide.csv"
    _wide_csv(path, 100, 40)
    read_timeseries(path)  # imports done
    values = _wide_csv(path, 8000, 40)
    monkeypatch.setattr(_textfile, "PIECE_BYTES", 2**16)
    tracemalloc.start()
    series = read_timeseries(path)
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    np.testing.assert_array_equal(series.values, values[:, 1] * 1000)
    assert peak < path.stat().st_size / 4, peak  # the text alone would be the size
