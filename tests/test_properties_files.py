"""Property-based tests of the CSV and array readers (Hypothesis).

Load-cell CSVs (:func:`read_timeseries`), calibration manifests (through
:func:`tactilecal.calibration.load_points`) and NetCDF files and Zarr stores (through
:func:`open_recording`). Generated valid files round-trip exactly; neutral edits (encodings,
spaces, blank lines) read the same; breaking edits raise :class:`TactilecalError` naming the
file on one line of at most 300 characters; any edit does one or the other. The profile
(``tests/conftest.py``) sets how many examples run.
"""

import itertools
import json
import shutil

import numpy as np
import pytest
import xarray as xr
from edits import byte_edits
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from tactilecal import TactilecalError
from tactilecal._errors import MAX_MESSAGE
from tactilecal._units import force_to_N, mass_to_N, pressure_to_kPa, time_to_s
from tactilecal.calibration import load_points
from tactilecal.io import (
    convert,
    open_recording,
    read_timeseries,
    write_netcdf,
    write_tekscan,
    write_timeseries,
)
from tactilecal.simulate import deadweight_session, make_sensor

_COUNT = itertools.count()
#: NetCDF and Zarr examples cost 0.1-0.3 s each (HDF5, dask): a fifth of the profile's count.
FEWER = settings(max_examples=max(4, settings.default.max_examples // 5))


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    return tmp_path_factory.mktemp("properties")


def _path(folder, name):
    return folder / f"{next(_COUNT)}-{name}"


def _assert_clean_error(exc, path):
    message = str(exc)
    assert isinstance(exc, TactilecalError), f"{type(exc).__name__}: {message}"
    assert path.name in message, message
    assert "\n" not in message and len(message) <= MAX_MESSAGE, message


def _reads_or_clean_error(read, path):
    try:
        return read(path)
    except Exception as exc:  # noqa: BLE001 - the class is what is tested
        _assert_clean_error(exc, path)
        return None


# ----------------------------------------------------------------------------- load-cell CSV
TIME_COLUMNS = {"Time (s)": "s", "Time (ms)": "ms", "time_s": "s", "t [us]": "us"}
VALUE_COLUMNS = {"Load (N)": ("N", force_to_N, "N"), "Force [kN]": ("kN", force_to_N, "N"),
                 "Load (lbf)": ("lbf", force_to_N, "N"), "Mass (kg)": ("kg", mass_to_N, "N"),
                 "Pressure (kPa)": ("kPa", pressure_to_kPa, "kPa"),
                 "reading": (None, None, "unknown")}
FINITE = st.floats(-1e6, 1e6, allow_nan=False, allow_infinity=False)


@st.composite
def loadcell_files(draw):
    n = draw(st.integers(2, 12))
    t_name = draw(st.sampled_from(sorted(TIME_COLUMNS)))
    v_name = draw(st.sampled_from(sorted(VALUE_COLUMNS)))
    steps = draw(st.lists(st.floats(1e-3, 10.0), min_size=n, max_size=n))
    times = np.cumsum(steps)
    assume((np.diff(times) > 0).all())
    values = np.array(draw(st.lists(FINITE, min_size=n, max_size=n)))
    extra = draw(st.booleans())
    header = [t_name, v_name] + (["note"] if extra else [])
    lines = [",".join(header)] + [
        ",".join([repr(float(t)), repr(float(v))] + ([f"s{k}"] if extra else []))
        for k, (t, v) in enumerate(zip(times, values, strict=True))]
    newline = draw(st.sampled_from(["\n", "\r\n"]))
    return newline.join(lines) + newline, t_name, v_name, times, values, newline


def _expected_series(t_name, v_name, times, values):
    t_s = time_to_s(times, TIME_COLUMNS[t_name])
    unit, convert_to, units = VALUE_COLUMNS[v_name]
    return t_s, (values if unit is None else convert_to(values, unit)), units


@given(loadcell_files())
def test_generated_loadcell_csvs_read_to_their_values(folder, generated):
    text, t_name, v_name, times, values, _ = generated
    path = _path(folder, "lc.csv")
    path.write_text(text)
    series = read_timeseries(path)
    t_s, v, units = _expected_series(t_name, v_name, times, values)
    assert series.time.values.tolist() == t_s.tolist()
    assert series.values.tolist() == v.tolist() and series.attrs["units"] == units
    out = _path(folder, "written.csv")
    write_timeseries(series, out)
    back = read_timeseries(out)
    assert back.time.values.tolist() == t_s.tolist() and back.values.tolist() == v.tolist()


@given(st.data())
def test_neutral_loadcell_edits_read_the_same(folder, data):
    text, t_name, v_name, times, values, nl = data.draw(loadcell_files())
    kind = data.draw(st.sampled_from(["utf-8-sig", "utf-16", "spaces", "blank line",
                                      "no final newline"]))
    if kind in ("utf-8-sig", "utf-16"):
        edited = text.encode(kind)
    elif kind == "spaces":
        edited = text.replace(",", data.draw(st.sampled_from([", ", " ,", " , "]))).encode()
    elif kind == "blank line":
        lines = text.split(nl)
        lines.insert(data.draw(st.integers(1, len(lines) - 1)), "")
        edited = nl.join(lines).encode()
    else:
        edited = text.rstrip("\r\n").encode()
    path = _path(folder, "lc.csv")
    path.write_bytes(edited)
    series = read_timeseries(path)
    t_s, v, _ = _expected_series(t_name, v_name, times, values)
    assert series.time.values.tolist() == t_s.tolist() and series.values.tolist() == v.tolist()


@given(st.data())
def test_breaking_loadcell_edits_are_errors_naming_the_file(folder, data):
    text, *_, nl = data.draw(loadcell_files())
    lines = text.split(nl)
    k = data.draw(st.integers(1, len(lines) - 2))
    cells = lines[k].split(",")
    kind = data.draw(st.sampled_from(["time repeated", "bad time", "bad value", "extra value",
                                      "missing value", "nul", "lone cr", "huge cell",
                                      "time unit"]))
    if kind == "time repeated":
        cells[0] = lines[k - 1].split(",")[0] if k > 1 else lines[k + 1].split(",")[0]
    elif kind in ("bad time", "bad value"):
        cells[kind == "bad value"] = data.draw(st.sampled_from(["nan", "inf", "", "1_0", "x",
                                                                "0x1", "--1"]))
    elif kind == "extra value":
        cells.append("1")
    elif kind == "missing value":
        cells = cells[:1]
    elif kind == "nul":
        cells[0] += "\x00"
    elif kind == "lone cr":
        cells[0] += "\r"
    elif kind == "huge cell":
        cells[1] = "1" * 140_000
    lines[k] = ",".join(cells)
    if kind == "time unit":
        lines[0] = "Time (kg)," + lines[0].split(",", 1)[1]
    path = _path(folder, "lc.csv")
    path.write_bytes(nl.join(lines).encode())
    with pytest.raises(TactilecalError) as info:
        read_timeseries(path)
    _assert_clean_error(info.value, path)


@given(st.data())
def test_any_loadcell_edit_reads_allowed_values_or_is_a_clean_error(folder, data):
    text, *_ = data.draw(loadcell_files())
    path = _path(folder, "lc.csv")
    path.write_bytes(data.draw(byte_edits(text.encode())))
    series = _reads_or_clean_error(read_timeseries, path)
    if series is not None:
        assert np.isfinite(series.values).all() and (np.diff(series.time.values) > 0).all()


# ----------------------------------------------------------------------------- manifests
@pytest.fixture(scope="module")
def session(tmp_path_factory):
    """Two simulated dead-weight recordings and what their manifest rows may name."""
    out = tmp_path_factory.mktemp("session")
    session = deadweight_session(make_sensor("5051", seed=0), n_patches=2, seed=4)
    session.write(out)
    files = {row["file"]: open_recording(out / row["file"]).frame.values
             for row in session.manifest_rows()}
    return out, files


@st.composite
def manifests(draw, files):
    """A manifest over the session's files: ``(text, expected loads in N, frames or None)``."""
    n = draw(st.integers(1, 4))
    by_mass = draw(st.booleans())
    rows, loads = [], []
    for k in range(n):
        name = draw(st.sampled_from(sorted(files)))
        frame = draw(st.one_of(st.none(), st.sampled_from(files[name].tolist())))
        load = draw(st.floats(0.01, 1e4))
        pad = draw(st.floats(0, 100))
        if by_mass:
            rows.append([name, "" if frame is None else str(frame), repr(load), repr(pad),
                         f"p{k}"])
            loads.append(mass_to_N(load, "kg") + mass_to_N(pad, "g"))  # each weighed in N
        else:
            rows.append([name, "" if frame is None else str(frame), repr(load), f"p{k}"])
            loads.append(load)
    header = (["file", "frame", "mass_kg", "pad_mass_g", "label"] if by_mass
              else ["file", "frame", "load_N", "label"])
    text = "\n".join(",".join(row) for row in [header, *rows]) + "\n"
    return text, loads


@given(st.data())
def test_generated_manifests_read_to_their_loads(session, data):
    out, files = session
    text, loads = data.draw(manifests(files))
    path = _path(out, "manifest.csv")
    path.write_text(text)
    points = load_points(path)
    assert [p.load_N for p in points] == loads
    assert [p.label for p in points] == [f"p{k}" for k in range(len(loads))]


@given(st.data())
def test_neutral_manifest_edits_read_the_same(session, data):
    out, files = session
    text, loads = data.draw(manifests(files))
    kind = data.draw(st.sampled_from(["utf-8-sig", "utf-16", "cp1252", "crlf", "spaces",
                                      "blank line"]))
    if kind in ("utf-8-sig", "utf-16", "cp1252"):
        edited = text.encode(kind)
    elif kind == "crlf":
        edited = text.replace("\n", "\r\n").encode()
    elif kind == "spaces":
        edited = text.replace(",", " , ").encode()
    else:
        edited = text.replace("\n", "\n\n", 1).encode()
    path = _path(out, "manifest.csv")
    path.write_bytes(edited)
    assert [p.load_N for p in load_points(path)] == loads


@given(st.data())
def test_breaking_manifest_edits_are_errors_naming_the_manifest(session, data):
    out, files = session
    text, _ = data.draw(manifests(files))
    lines = text.splitlines()
    k = data.draw(st.integers(1, len(lines) - 1))
    cells = lines[k].split(",")
    kind = data.draw(st.sampled_from(["bad load", "frame not in file", "missing file",
                                      "device", "extra value", "missing column", "nul",
                                      "lone cr", "bad frame"]))
    if kind == "bad load":  # (a mass of 0 with a pad's mass is a load)
        zero = ["0"] if "load_N" in lines[0] else []
        cells[2] = data.draw(st.sampled_from(["nan", "inf", "-1", "1_0", "abc", "1e308", "",
                                              "0x10", *zero]))
    elif kind == "frame not in file":
        cells[1] = str(int(files[cells[0]][-1]) + data.draw(st.integers(1, 100)))
    elif kind == "missing file":
        cells[0] = "no-such-file.csv"
    elif kind == "device":
        cells[0] = "/dev/null"
    elif kind == "extra value":
        cells.append("x")
    elif kind == "missing column":
        lines[0] = lines[0].replace("file,", "fil,")
    elif kind == "nul":
        cells[-1] += "\x00"
    elif kind == "lone cr":
        cells[-1] = cells[-1][:1] + "\r" + cells[-1][1:]
    else:
        cells[1] = data.draw(st.sampled_from(["1.5", "-1", "x", "nan"]))
    lines[k] = ",".join(cells)
    path = _path(out, "manifest.csv")
    path.write_bytes("\n".join(lines).encode() + b"\n")
    with pytest.raises(TactilecalError) as info:
        load_points(path)
    _assert_clean_error(info.value, path)


@given(st.data())
def test_any_manifest_edit_reads_allowed_loads_or_is_a_clean_error(session, data):
    out, files = session
    text, _ = data.draw(manifests(files))
    path = _path(out, "manifest.csv")
    path.write_bytes(data.draw(byte_edits(text.encode())))
    points = _reads_or_clean_error(load_points, path)
    for point in points or []:
        assert np.isfinite(point.load_N) and point.load_N > 0


# ----------------------------------------------------------------------------- NetCDF, Zarr
@st.composite
def recordings(draw):
    n, rows, cols = draw(st.integers(1, 4)), draw(st.integers(1, 4)), draw(st.integers(1, 4))
    raw = draw(st.booleans())
    cell = st.integers(0, 255).map(float) if raw else FINITE
    values = np.array(draw(st.lists(st.one_of(cell, st.just(np.nan)), min_size=n * rows * cols,
                                    max_size=n * rows * cols))).reshape(n, rows, cols)
    first = draw(st.integers(0, 10**6))
    spf = draw(st.sampled_from([0.1, 0.032]))
    attrs = {"units": "raw" if raw else "kPa", "seconds_per_frame": spf,
             "sensel_area_mm2": 1.6129, "sensor_type": "5051",
             "note": draw(st.text(st.characters(exclude_categories=["Cs", "Cc"]), max_size=20))}
    return xr.DataArray(values, dims=("frame", "row", "col"),
                        coords={"frame": np.arange(first, first + n),
                                "time": ("frame", np.arange(n) * spf),
                                "row": np.arange(rows), "col": np.arange(cols)},
                        attrs=attrs)


@FEWER
@given(recordings())
def test_netcdf_round_trips_exactly_through_open_recording(folder, recording):
    path = _path(folder, "rec.nc")
    write_netcdf(recording, path)
    assert open_recording(path).identical(recording)


@FEWER
@given(recordings())
def test_zarr_from_an_export_round_trips_through_open_recording(folder, recording):
    export = _path(folder, "rec.csv")
    write_tekscan(recording, export)
    store = _path(folder, "rec.zarr")
    convert(export, store, chunks=2)
    back = open_recording(store).compute()
    np.testing.assert_array_equal(back.values, recording.values)
    assert back.frame.values.tolist() == recording.frame.values.tolist()
    assert back.time.values.tolist() == recording.time.values.tolist()


@FEWER
@given(st.data())
def test_any_netcdf_edit_reads_or_is_a_clean_error(folder, data):
    recording = data.draw(recordings())
    path = _path(folder, "rec.nc")
    write_netcdf(recording, path)
    path.write_bytes(data.draw(byte_edits(path.read_bytes())))
    _reads_or_clean_error(open_recording, path)


@FEWER
@given(st.data())
def test_any_zarr_metadata_edit_reads_or_is_a_clean_error(folder, data):
    recording = data.draw(recordings())
    export = _path(folder, "rec.csv")
    write_tekscan(recording, export)
    store = _path(folder, "rec.zarr")
    convert(export, store, chunks=2)
    names = sorted(p.relative_to(store) for p in store.rglob("*") if p.is_file()
                   and p.name in (".zarray", ".zattrs", ".zgroup", ".zmetadata"))
    target = store / data.draw(st.sampled_from(names))
    if data.draw(st.booleans()):
        target.write_bytes(data.draw(byte_edits(target.read_bytes())))
    else:
        meta = json.loads(target.read_text())
        key = data.draw(st.sampled_from(sorted(meta) or ["x"]))
        meta[key] = data.draw(st.sampled_from([None, -1, "abc", [], {}, 1e308]))
        target.write_text(json.dumps(meta))
    try:
        _reads_or_clean_error(lambda p: open_recording(p).compute(), store)
    finally:
        shutil.rmtree(store, ignore_errors=True)
