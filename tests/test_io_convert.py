"""tactilecal.io.convert and ``tactilecal convert``: streaming to Zarr/NetCDF, atomically."""

import tracemalloc

import numpy as np
import pytest
import xarray as xr

from tactilecal.cli import main
from tactilecal.io import _tekscan_index, convert, read_netcdf, read_tekscan


def _export(tmp_path, n=30, rows=4, cols=6, seed=0, name="movie.csv"):
    rng = np.random.default_rng(seed)
    lines = [f"ROWS {rows}", f"COLS {cols}", "UNITS raw", "SECONDS_PER_FRAME 0.01",
             "ASCII_DATA @@", ""]
    for k in range(n):
        lines.append(f"Frame {k + 1}")
        lines += [",".join(map(str, rng.integers(0, 256, cols))) for _ in range(rows)]
    path = tmp_path / name
    path.write_text("\n".join(lines + ["@@", ""]))
    return path


def _open_zarr(path):
    return xr.open_dataarray(path, engine="zarr", consolidated=False)


def _leftovers(folder, keep):
    return sorted(p.name for p in folder.iterdir() if p.name not in keep)


def test_zarr_holds_the_recording_in_blocks_of_chunks_frames(tmp_path):
    source = _export(tmp_path)
    convert(source, tmp_path / "out.zarr", chunks=8)
    with _open_zarr(tmp_path / "out.zarr") as stored:
        assert stored.encoding["chunks"] == (8, 4, 6)
        assert stored.load().identical(read_tekscan(source))


def test_netcdf_reads_back_with_read_netcdf(tmp_path):
    source = _export(tmp_path)
    convert(source, tmp_path / "out.nc", chunks=7)
    assert read_netcdf(tmp_path / "out.nc").identical(read_tekscan(source))


def test_real_export_converts_identically(iscan_csv, tmp_path):
    convert(iscan_csv, tmp_path / "iscan.zarr", chunks=64)
    with _open_zarr(tmp_path / "iscan.zarr") as stored:
        assert stored.load().identical(read_tekscan(iscan_csv))


def test_memory_is_bounded_by_the_blocks_not_the_recording(tmp_path, monkeypatch):
    """6.4 MB of float64 in 40 blocks of 160 kB: the peak stays well below the recording."""
    source = _export(tmp_path, n=2000, rows=20, cols=20)
    monkeypatch.setattr(_tekscan_index, "BLOCK_BYTES", 2**15)  # bytes indexed at a time
    tracemalloc.start()
    convert(source, tmp_path / "out.zarr", chunks=50)
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    assert peak < 0.5 * 2000 * 20 * 20 * 8


def test_existing_store_is_replaced(tmp_path):
    convert(_export(tmp_path, n=3, name="a.csv"), tmp_path / "out.zarr")
    source = _export(tmp_path, n=5, seed=1, name="b.csv")
    convert(source, tmp_path / "out.zarr")
    with _open_zarr(tmp_path / "out.zarr") as stored:
        assert stored.load().identical(read_tekscan(source))
    assert _leftovers(tmp_path, {"a.csv", "b.csv", "out.zarr"}) == []


def test_cli_converts_and_says_what_it_wrote(tmp_path, capsys):
    source = _export(tmp_path)
    assert main(["convert", str(source), str(tmp_path / "out.zarr"), "--chunks", "4"]) == 0
    assert "30 frames of 4 x 6 sensels in blocks of 4 frames" in capsys.readouterr().err
    with _open_zarr(tmp_path / "out.zarr") as stored:
        assert stored.encoding["chunks"] == (4, 4, 6) and stored.shape == (30, 4, 6)


def _fails(argv, capsys, match):
    assert main(argv) == 1
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("tactilecal convert: error: "), err
    assert match in err, err
    return err


@pytest.mark.parametrize("suffix", [".zarr", ".nc"])
def test_malformed_input_leaves_no_output(tmp_path, capsys, suffix):
    source = _export(tmp_path)
    source.write_text(source.read_text().replace("Frame 9\n", "Frame 9\n1,2\n"))
    out = tmp_path / f"out{suffix}"
    _fails(["convert", str(source), str(out)], capsys,
           f"frame 9 of {source} (line 47) has 5 rows of values; expected 4 (ROWS)")
    assert _leftovers(tmp_path, {"movie.csv"}) == []


@pytest.mark.parametrize("suffix", [".zarr", ".nc"])
def test_bad_value_in_a_late_block_leaves_no_output_and_keeps_the_old_one(tmp_path, capsys,
                                                                          suffix):
    out = tmp_path / f"out{suffix}"
    convert(_export(tmp_path, name="good.csv"), out)
    before = sorted(p.name for p in out.rglob("*")) if out.is_dir() else out.read_bytes()
    source = _export(tmp_path)
    lines = source.read_text().split("\n")
    lines[-4] = "1,2,x,4,5,6"  # a row of the last frame
    source.write_text("\n".join(lines))
    _fails(["convert", str(source), str(out), "--chunks", "5"], capsys,
           f"line {len(lines) - 3} of {source}, value 3: 'x' is not a finite number")
    after = sorted(p.name for p in out.rglob("*")) if out.is_dir() else out.read_bytes()
    assert after == before
    assert _leftovers(tmp_path, {"movie.csv", "good.csv", out.name}) == []


def test_unwritable_output_is_one_line_naming_it(tmp_path, capsys):
    source = _export(tmp_path)
    _fails(["convert", str(source), "/dev/null/out.zarr"], capsys, "/dev/null/out.zarr")


@pytest.mark.parametrize("out, match", [
    ("out.csv", "ends in '.csv'; expected .zarr (Zarr store) or .nc (NetCDF)"),
    ("folder.zarr", "exists and is no Zarr store; expected a new path"),
])
def test_output_that_is_not_zarr_or_netcdf_is_refused(tmp_path, capsys, out, match):
    source = _export(tmp_path)
    (tmp_path / "folder.zarr").mkdir()
    (tmp_path / "folder.zarr" / "notes.txt").write_text("mine")
    _fails(["convert", str(source), str(tmp_path / out)], capsys, match)
    assert (tmp_path / "folder.zarr" / "notes.txt").read_text() == "mine"


def test_chunks_flag_must_be_positive(tmp_path, capsys):
    source = _export(tmp_path)
    assert main(["convert", str(source), str(tmp_path / "o.zarr"), "--chunks", "0"]) == 1
    assert "--chunks" in capsys.readouterr().err
