"""tactilecal.io.convert and ``tactilecal convert``: streaming to Zarr/NetCDF, atomically."""

import hashlib
import json
import tracemalloc

import numpy as np
import pytest
import xarray as xr

from tactilecal import TactilecalError
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
    """Open a store with xarray's defaults (consolidated metadata expected; warnings fail)."""
    return xr.open_dataarray(path, engine="zarr")


def _traced(stored, source):
    """Check the output names the export it came from by its bytes; return it without that."""
    prov = json.loads(stored.attrs.pop("provenance"))
    assert prov["inputs"][0]["sha256"] == hashlib.sha256(source.read_bytes()).hexdigest()
    assert set(prov["options"]) == {"chunks", "dtype"}
    return stored


def _leftovers(folder, keep):
    return sorted(p.name for p in folder.iterdir() if p.name not in keep)


def test_zarr_holds_the_recording_in_blocks_of_chunks_frames(tmp_path):
    source = _export(tmp_path)
    convert(source, tmp_path / "out.zarr", chunks=8)
    with _open_zarr(tmp_path / "out.zarr") as stored:
        assert stored.encoding["chunks"] == (8, 4, 6)
        assert _traced(stored.load(), source).identical(read_tekscan(source))


def test_netcdf_reads_back_with_read_netcdf(tmp_path):
    source = _export(tmp_path)
    convert(source, tmp_path / "out.nc", chunks=7)
    assert _traced(read_netcdf(tmp_path / "out.nc"), source).identical(read_tekscan(source))


def test_real_export_converts_identically(iscan_csv, tmp_path):
    convert(iscan_csv, tmp_path / "iscan.zarr", chunks=64)
    with _open_zarr(tmp_path / "iscan.zarr") as stored:
        assert _traced(stored.load(), iscan_csv).identical(read_tekscan(iscan_csv))


@pytest.mark.parametrize("export", ["iscan_csv", "fscan_asf", "fscan_right_asf"])
def test_real_exports_convert_to_float32_exactly(export, request, tmp_path):
    source = request.getfixturevalue(export)  # raw counts and kPa, all whole numbers
    convert(source, tmp_path / "out.zarr", chunks=64, dtype="float32")
    with _open_zarr(tmp_path / "out.zarr") as stored:
        assert stored.dtype == np.float32
        np.testing.assert_array_equal(stored.values, read_tekscan(source).values)


@pytest.mark.slow  # a memory profile
def test_memory_is_bounded_by_the_blocks_not_the_recording(tmp_path, monkeypatch):
    """6.4 MB of float64 in 40 blocks of 160 kB: the peak stays well below the recording."""
    source = _export(tmp_path, n=2000, rows=20, cols=20)
    monkeypatch.setattr(_tekscan_index, "BLOCK_BYTES", 2**15)  # bytes indexed at a time
    # the modules convert imports on its first call are not the recording's memory: the test
    # runs first among the slow ones of this file
    convert(_export(tmp_path, n=3, name="warm.csv"), tmp_path / "warm.zarr")
    tracemalloc.start()
    convert(source, tmp_path / "out.zarr", chunks=50)
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    assert peak < 0.5 * 2000 * 20 * 20 * 8


def test_existing_store_is_replaced_only_with_overwrite(tmp_path):
    convert(_export(tmp_path, n=3, name="a.csv"), tmp_path / "out.zarr")
    source = _export(tmp_path, n=5, seed=1, name="b.csv")
    with pytest.raises(TactilecalError, match=r"out.zarr exists; expected a new path \(pass "
                                              r"overwrite=True to replace it\)"):
        convert(source, tmp_path / "out.zarr")
    convert(source, tmp_path / "out.zarr", overwrite=True)
    with _open_zarr(tmp_path / "out.zarr") as stored:
        assert _traced(stored.load(), source).identical(read_tekscan(source))
    assert _leftovers(tmp_path, {"a.csv", "b.csv", "out.zarr"}) == []


def test_cli_converts_and_says_what_it_wrote(tmp_path, capsys):
    source = _export(tmp_path)
    assert main(["convert", str(source), str(tmp_path / "out.zarr"), "--chunks", "4"]) == 0
    assert "30 frames of 4 x 6 sensels (float64) in blocks of 4 frames" in capsys.readouterr().err
    with _open_zarr(tmp_path / "out.zarr") as stored:
        assert stored.encoding["chunks"] == (4, 4, 6) and stored.shape == (30, 4, 6)


@pytest.mark.parametrize("suffix", [".zarr", ".nc"])
def test_float32_store_holds_raw_readings_and_nan_exactly(tmp_path, suffix):
    source = _export(tmp_path, n=200, rows=8, cols=8)
    lines = source.read_text().splitlines()
    for k, line in enumerate(lines[:-1]):
        if line.startswith("Frame "):  # sensel (0, 0) outside the sensor's shape: NaN
            lines[k + 1] = ",".join(["B"] + lines[k + 1].split(",")[1:])
    source.write_text("\n".join(lines) + "\n")
    narrow = tmp_path / f"narrow{suffix}"
    assert main(["-q", "convert", str(source), str(narrow), "--dtype", "float32"]) == 0
    truth = read_tekscan(source)
    stored = _open_zarr(narrow) if suffix == ".zarr" else read_netcdf(narrow)
    with stored:
        assert stored.dtype == np.float32
        assert np.isnan(stored.values[2, 0, 0]) and np.isnan(truth.values[2, 0, 0])
        np.testing.assert_array_equal(stored.values, truth.values)  # 0..255 and NaN: exact
        assert json.loads(stored.attrs["provenance"])["options"]["dtype"] == "float32"
    if suffix == ".nc":  # uncompressed: half the bytes (Zarr compresses both)
        convert(source, tmp_path / "wide.nc")
        assert narrow.stat().st_size < 0.7 * (tmp_path / "wide.nc").stat().st_size


@pytest.mark.parametrize("dtype", ["float16", "int64", "uint8", "raw"])
def test_a_stored_type_other_than_float64_or_float32_is_refused(tmp_path, dtype):
    with pytest.raises(ValueError, match=f"dtype='{dtype}'; expected 'float64' or 'float32'"):
        convert(_export(tmp_path, n=3), tmp_path / "out.zarr", dtype=dtype)
    assert not (tmp_path / "out.zarr").exists()


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
    _fails(["convert", str(source), str(out), "--chunks", "5", "--overwrite"], capsys,
           f"line {len(lines) - 3} of {source}, value 3: 'x' is not a finite number")
    after = sorted(p.name for p in out.rglob("*")) if out.is_dir() else out.read_bytes()
    assert after == before
    assert _leftovers(tmp_path, {"movie.csv", "good.csv", out.name}) == []


def test_unwritable_output_is_one_line_naming_it(tmp_path, capsys):
    source = _export(tmp_path)
    _fails(["convert", str(source), "/dev/null/out.zarr"], capsys, "/dev/null/out.zarr")


@pytest.mark.parametrize("out, match", [
    ("out.csv", "ends in '.csv'; expected .zarr (Zarr store) or .nc (NetCDF)"),
    ("out", "has no suffix; expected .zarr (Zarr store) or .nc (NetCDF)"),
    ("folder.zarr", "folder.zarr exists; expected a new path (add --overwrite to replace it)"),
    ("folder.zarr --overwrite", "folder.zarr is a folder, not a Zarr store written before; "
                                "expected a new path"),
])
def test_output_that_is_not_zarr_or_netcdf_is_refused(tmp_path, capsys, out, match):
    source = _export(tmp_path)
    (tmp_path / "folder.zarr").mkdir()
    (tmp_path / "folder.zarr" / "notes.txt").write_text("mine")
    out, *flags = out.split()
    _fails(["convert", str(source), str(tmp_path / out), *flags], capsys, match)
    assert (tmp_path / "folder.zarr" / "notes.txt").read_text() == "mine"


@pytest.mark.parametrize("value, match", [
    ("0", "argument --chunks: '0'; expected a finite number > 0"),
    ("-3", "argument --chunks: '-3'; expected a finite number > 0"),
    ("1.5", "argument --chunks: '1.5'; expected a whole number > 0"),
])
def test_chunks_flag_must_be_a_positive_whole_number(tmp_path, capsys, value, match):
    source = _export(tmp_path)
    _fails(["convert", str(source), str(tmp_path / "o.zarr"), "--chunks", value], capsys,
           match)
    assert _leftovers(tmp_path, {"movie.csv"}) == []


def test_zarr_store_has_consolidated_metadata_in_format_2(tmp_path):
    convert(_export(tmp_path), tmp_path / "out.zarr", chunks=8)
    assert (tmp_path / "out.zarr" / ".zmetadata").is_file()
    assert (tmp_path / "out.zarr" / ".zgroup").is_file()
    with xr.open_zarr(tmp_path / "out.zarr") as stored:  # xarray's default: consolidated
        assert stored["__xarray_dataarray_variable__"].shape == (30, 4, 6)


def test_a_local_cluster_reads_the_converted_zarr_store_without_a_warning(tmp_path):
    """The workers open the store as xarray does by default; warnings are errors here."""
    from dask.distributed import Client, LocalCluster

    source = _export(tmp_path, n=40)
    convert(source, tmp_path / "out.zarr", chunks=16)
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=False,
                      dashboard_address=":0") as cluster, Client(cluster) as client:
        with xr.open_dataarray(tmp_path / "out.zarr", engine="zarr", chunks={}) as lazy:
            assert lazy.chunks[0] == (16, 16, 8)
            total = client.compute(lazy.sum(dim="frame").data).result()
    np.testing.assert_array_equal(total, read_tekscan(source).sum(dim="frame").values)


def _failing_recording(n_blocks=4):
    """A lazy recording whose first block fails at once while the others are still running."""
    import time

    import dask
    import dask.array as da

    def block(k):
        if k == 0:
            raise ValueError("block 0 of rec.csv: bad value")
        time.sleep(0.3)
        return np.zeros((5, 2, 3))

    parts = [da.from_delayed(dask.delayed(block)(k), shape=(5, 2, 3), dtype=float)
             for k in range(n_blocks)]
    return xr.DataArray(da.concatenate(parts), dims=("frame", "row", "col"))


def test_tasks_still_running_when_one_fails_finish_before_the_error_leaves_the_block():
    """Else a writer removes its temporary output while they still write into it (seen as
    a left-over '.out.nc.tmp*' file in about 1 of 10 runs of the test below before)."""
    import threading
    import time

    import dask

    from tactilecal._atomic import dask_tasks_finished

    done = threading.Event()

    def slow():
        time.sleep(0.3)
        done.set()

    def failing():
        time.sleep(0.05)
        raise ValueError("block 0 of rec.csv: bad value")

    with pytest.raises(ValueError, match="block 0 of rec.csv"), dask_tasks_finished():
        dask.compute(dask.delayed(slow)(), dask.delayed(failing)())
    assert done.is_set()  # dask's own threaded scheduler raises before it is (0.05 s)


@pytest.mark.parametrize("suffix", [".nc", ".zarr"])
def test_a_failed_block_leaves_no_temporary_output_behind(tmp_path, suffix):
    """Nothing at OUT and no temporary output, whichever block fails and when."""
    from tactilecal.io._convert import write_lazy

    with pytest.raises(ValueError, match="block 0 of rec.csv: bad value"):
        write_lazy(_failing_recording(), tmp_path / f"out{suffix}")
    assert _leftovers(tmp_path, set()) == []


@pytest.mark.slow  # a local cluster, and tasks that sleep
def test_write_netcdf_on_a_distributed_client_waits_for_running_tasks_after_a_failure(tmp_path):
    """The blocks still running when one fails wrote the temporary file again after the
    writer removed it (a left-over '.out.nc.tmp*' in 9 of 10 tries before); under a
    distributed client they are now cancelled and waited for (0 of 10)."""
    import time

    from dask.distributed import Client, LocalCluster

    from tactilecal.io import write_netcdf

    with LocalCluster(n_workers=2, threads_per_worker=2, processes=False,
                      dashboard_address=None) as cluster, Client(cluster):
        for attempt in range(3):
            folder = tmp_path / str(attempt)
            folder.mkdir()
            with pytest.raises(ValueError, match="block 0 of rec.csv: bad value"):
                write_netcdf(_failing_recording(n_blocks=6), folder / "out.nc")
            time.sleep(0.5)  # the other blocks sleep 0.3 s: they have ended by now
            assert _leftovers(folder, set()) == []


def test_stale_temporary_folder_of_a_name_with_brackets_is_removed(tmp_path, capsys):
    """Folders go through tactilecal._atomic as files do (glob.escape of the name kept)."""
    stale = tmp_path / ".out[1].zarr.tmp999999999.x"  # a writer that was killed
    stale.mkdir()
    (stale / ".zgroup").write_text("{}")
    convert(_export(tmp_path), tmp_path / "out[1].zarr", chunks=10)
    assert not stale.exists() and "left by an interrupted write" in capsys.readouterr().err
    assert _leftovers(tmp_path, {"movie.csv", "out[1].zarr"}) == []
