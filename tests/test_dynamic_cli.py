"""``tactilecal dynamic fit|apply|evaluate`` on short simulated sessions written to files."""

import json
import re

import numpy as np
import pandas as pd
import pytest

from tactilecal.cli import main
from tactilecal.io import read_netcdf, write_netcdf
from tactilecal.simulate import random_sine_sets, sine_sweep
from tactilecal.simulate._dynamic import sensel_matrix

FAST = {"fs_sensor_hz": 1000.0, "fs_reference_hz": 1250.0, "sensor_noise_N": 0.2,
        "reference_noise_N": 0.05}


def _csv(record, path, value="Force (N)"):
    pd.DataFrame({"Time (s)": record.time.values, value: record.values}).to_csv(
        path, index=False, float_format="%.10g")
    return str(path)


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    d = tmp_path_factory.mktemp("dyn")
    sweep = sine_sweep(step_hz=2, cycles_high=10, seed=0, **FAST)
    blind = random_sine_sets(n_sets=8, f_range_hz=(10, 140), cycles_range=(5, 40), seed=7,
                             **FAST)
    return {"d": d, "sweep": sweep,
            "sensor": _csv(sweep.sensor, d / "sensor.csv"),
            "cell": _csv(sweep.reference, d / "cell.csv", "Load (lbf)"),
            "blind_sensor": _csv(blind.sensor, d / "blind_sensor.csv"),
            "blind_cell": _csv(blind.reference, d / "blind_cell.csv")}


@pytest.fixture(scope="module")
def filter_json(files):
    out = files["d"] / "FILTER.json"
    assert main(["-q", "dynamic", "fit", files["sensor"], files["cell"], "--out", str(out),
                 "--model", "log10"]) == 0
    return out


def test_fit_writes_the_contract_keys(files, filter_json, capsys, assert_names_by_bytes):
    d = json.loads(filter_json.read_text())
    for key in ("model", "A", "log_base", "lag_s", "fs_hz", "band_hz", "fit"):
        assert key in d
    assert_names_by_bytes(d["provenance"], [files["sensor"], files["cell"]])
    assert d["model"] == "log10" and d["log_base"] == "10"
    # the load cell column is in lbf; the sensor in N: the static factor absorbs it
    assert d["A"] == pytest.approx(0.11, rel=0.05)
    assert d["lag_s"] == pytest.approx(files["sweep"].lag_s, abs=1e-3)
    assert d["fs_hz"] == pytest.approx(1000.0)
    assert "r2" in d["fit"] and len(d["fit"]["residuals"]) == len(d["fit"]["f_hz"])
    out = files["d"] / "F2.json"
    assert main(["-q", "dynamic", "fit", files["sensor"], files["cell"], "--out", str(out),
                 "--json", "--band", "2", "120"]) == 0
    printed = json.loads(capsys.readouterr().out)
    # the default model is auto, which takes the thesis' law in its log10 base
    assert printed["model"] == "log10" and printed["log_base"] == "10"
    assert printed["band_hz"] == [2.0, 120.0]
    assert printed["A"] == pytest.approx(0.11, rel=0.05)


def test_apply_csv_keeps_columns(files, filter_json, assert_names_by_bytes):
    out = files["d"] / "corrected.csv"
    assert main(["-q", "dynamic", "apply", str(filter_json), files["blind_sensor"], "--out",
                 str(out)]) == 0
    before, after = pd.read_csv(files["blind_sensor"]), pd.read_csv(out)
    assert list(after.columns) == list(before.columns)
    np.testing.assert_allclose(after["Time (s)"], before["Time (s)"])
    assert after["Force (N)"].mean() == pytest.approx(before["Force (N)"].mean(), rel=1e-3)
    assert after["Force (N)"].std() > before["Force (N)"].std()  # dynamic part restored
    side = json.loads((files["d"] / "corrected.provenance.json").read_text())
    assert_names_by_bytes(side, [files["blind_sensor"]])
    assert side["options"] == {"method": "auto", "causal": False, "dtype": "float64"}
    assert side["dynamic_filter"]["A"] == json.loads(filter_json.read_text())["A"]



def test_apply_netcdf_every_sensel(files, filter_json, assert_names_by_bytes):
    rec = sensel_matrix(files["sweep"], shape=(2, 3))
    src, out = files["d"] / "rec.nc", files["d"] / "rec_dyn.nc"
    write_netcdf(rec, src)
    assert main(["-q", "dynamic", "apply", str(filter_json), str(src), "--out", str(out),
                 "--chunk-frames", "5000"]) == 0
    back = read_netcdf(out)
    assert back.dims == rec.dims and back.shape == rec.shape
    from tactilecal.dynamic import CorrectionFilter, apply_filter

    expected = apply_filter(rec, CorrectionFilter.from_json(filter_json))
    span = float(np.ptp(rec.values))
    np.testing.assert_allclose(back.values, expected.values, atol=5e-6 * span)  # float32 FFTs
    assert "dynamic_filter" in back.attrs
    prov = json.loads(back.attrs["provenance"])
    assert_names_by_bytes(prov, [src])
    assert prov["options"] == {"method": "auto", "causal": False, "chunk_frames": 5000,
                               "dtype": "float64"}


def test_apply_netcdf_as_float32(files, filter_json):
    rec = sensel_matrix(files["sweep"], shape=(2, 3))
    src = files["d"] / "rec32.nc"
    write_netcdf(rec, src)
    outs = {dtype: files["d"] / f"rec_dyn_{dtype}.nc" for dtype in ("float64", "float32")}
    for dtype, out in outs.items():
        assert main(["-q", "dynamic", "apply", str(filter_json), str(src), "--out", str(out),
                     "--chunk-frames", "5000", "--dtype", dtype]) == 0
    wide, narrow = read_netcdf(outs["float64"]), read_netcdf(outs["float32"])
    assert wide.dtype == np.float64 and narrow.dtype == np.float32
    assert outs["float32"].stat().st_size < 0.75 * outs["float64"].stat().st_size
    step = np.spacing(np.float32(np.abs(wide.values).max()))
    np.testing.assert_allclose(narrow.values, wide.values, rtol=0, atol=2 * step)  # rounding
    assert json.loads(narrow.attrs["provenance"])["options"]["dtype"] == "float32"


def test_fit_sums_a_recording(files, tmp_path):
    rec = sensel_matrix(files["sweep"], shape=(2, 2), noise_N=0.0)
    src = tmp_path / "rec.nc"
    write_netcdf(rec, src)
    out = tmp_path / "F.json"
    # the sensels are summed before any model is fitted: the model is given (log10, auto's
    # choice on this sweep, which test_fit_prints_readable_lines_and_no_library_noise makes)
    assert main(["-q", "dynamic", "fit", str(src), files["cell"], "--out", str(out),
                 "--model", "log10"]) == 0
    assert json.loads(out.read_text())["A"] == pytest.approx(0.11, rel=0.05)


def test_fit_sums_a_tekscan_export(files, tmp_path):
    from tactilecal.io import write_tekscan

    rec = sensel_matrix(files["sweep"], shape=(2, 2), noise_N=0.0)
    src = tmp_path / "sweep_export.csv"  # Tekscan exports are often .csv
    write_tekscan(rec, src)
    out = tmp_path / "F.json"
    assert main(["-q", "dynamic", "fit", str(src), files["cell"], "--out", str(out),
                 "--model", "log10"]) == 0
    d = json.loads(out.read_text())
    assert d["A"] == pytest.approx(0.11, rel=0.05)
    assert d["lag_s"] == pytest.approx(files["sweep"].lag_s, abs=1e-3)


def test_evaluate_blind_test(files, filter_json, capsys, assert_names_by_bytes):
    out = files["d"] / "eval"
    assert main(["-q", "dynamic", "evaluate", str(filter_json), files["blind_sensor"],
                 files["blind_cell"], "--json", "--out", str(out)]) == 0
    result = json.loads(capsys.readouterr().out)
    assert result["rms_before_N"] > 3 * result["rms_after_N"]
    assert len(result["error_before_pct"]) == len(result["f_hz"]) > 10
    for name in ("time.png", "spectra.png", "error.png", "transfer.png", "evaluation.json"):
        assert (out / name).stat().st_size > 1000 or name.endswith(".json")
    saved = json.loads((out / "evaluation.json").read_text())
    assert_names_by_bytes(saved["provenance"], [files["blind_sensor"], files["blind_cell"]])


def test_cli_errors(files, filter_json, tmp_path, capsys):
    late = tmp_path / "late.csv"
    t = np.arange(0, 2, 1e-3)
    pd.DataFrame({"t": t + 1000.0, "F (N)": np.sin(9 * t)}).to_csv(late, index=False)
    assert main(["dynamic", "apply", str(filter_json), str(late), "--out",
                 str(tmp_path / "x.csv")]) == 0  # apply needs no reference
    irregular = tmp_path / "irregular.csv"
    pd.DataFrame({"t": np.r_[0, np.cumsum(np.r_[np.full(1500, 1e-3), 0.01])],
                  "F (N)": np.ones(1502)}).to_csv(irregular, index=False)
    assert main(["dynamic", "fit", str(irregular), files["cell"], "--out",
                 str(tmp_path / "f.json")]) == 1
    assert "irregular.csv: irregular time column" in capsys.readouterr().err
    assert main(["dynamic", "fit", files["sensor"], files["cell"], "--out",
                 str(tmp_path / "f.json"), "--band", "1", "900"]) == 1
    assert "reaches beyond the Nyquist frequency 500" in capsys.readouterr().err
    assert main(["dynamic", "apply", str(late), files["sensor"], "--out",
                 str(tmp_path / "y.csv")]) == 1
    assert "late.csv: not valid JSON" in capsys.readouterr().err


def test_apply_method_direct_matches_auto(files):
    from tactilecal.dynamic import CorrectionFilter
    from tactilecal.dynamic._multirate import plan_multirate

    filt = CorrectionFilter.from_model(("log", {"A": 0.05}), fs_hz=1000.0, band_hz=(1, 40))
    assert plan_multirate(filt).factor == 5  # 1000 / (4 (40 + 10)): auto is multirate
    filter_json = files["d"] / "narrow.json"
    filt.to_json(filter_json)
    auto, direct = files["d"] / "auto.csv", files["d"] / "direct.csv"
    for method, out in (("auto", auto), ("direct", direct)):
        assert main(["-q", "dynamic", "apply", str(filter_json), files["blind_sensor"],
                     "--out", str(out), "--method", method]) == 0
    a, d = pd.read_csv(auto)["Force (N)"], pd.read_csv(direct)["Force (N)"]
    assert np.abs(a - d).max() < 1e-4 * np.ptp(d)  # two realisations of one filter
    assert np.abs(a - d).max() > 0  # and really two methods


def test_library_file_functions_match_apply_filter(files, filter_json, tmp_path):
    # the library calls behind the CLI: the same numbers as apply_filter on the data
    from tactilecal.dynamic import (
        CorrectionFilter,
        Evaluation,
        apply_filter,
        evaluate,
        filter_recording,
        filter_timeseries_csv,
        read_record,
    )
    from tactilecal.io import recording_format

    filt = CorrectionFilter.from_json(filter_json)
    out = tmp_path / "c.csv"
    assert recording_format(files["blind_sensor"]) is None  # a time series, not a recording
    assert filter_timeseries_csv(filt, files["blind_sensor"], out) == (1, len(
        pd.read_csv(files["blind_sensor"])))
    expected = apply_filter(read_record(files["blind_sensor"]), filt).values
    np.testing.assert_allclose(pd.read_csv(out)["Force (N)"], expected,
                               atol=1e-9 * np.ptp(expected))  # CSV keeps 10 digits
    rec = sensel_matrix(files["sweep"], shape=(2, 2))
    write_netcdf(rec, tmp_path / "r.nc")
    assert recording_format(tmp_path / "r.nc") == "netcdf"
    lazy = filter_recording(filt, tmp_path / "r.nc", chunk_frames=3000)
    assert lazy.chunks is not None  # NetCDF streams in chunks
    np.testing.assert_allclose(lazy.values, apply_filter(rec, filt).values,
                               atol=5e-6 * float(np.ptp(rec.values)))  # float32 FFTs
    ev = evaluate(filt, read_record(files["blind_sensor"]), read_record(files["blind_cell"]))
    ev.inputs = {"filter": "F"}
    written = ev.save(tmp_path, filt)
    stored = json.loads((tmp_path / "evaluation.json").read_text())
    assert stored["format"] == "tactilecal-dynamic-evaluation/1"
    assert stored["inputs"] == {"filter": "F"} and stored["figures"] == list(written.figures)
    assert Evaluation.from_json(tmp_path / "evaluation.json") == written  # by value
    assert all((tmp_path / name).stat().st_size > 1000 for name in written.figures)


def _actions(parser, *path):
    """The options of subcommand ``path`` of ``parser``, by keyword."""
    import argparse

    for name in path:
        sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
        parser = sub.choices[name]
    parser.format_help()  # adds the flags whose defaults come from the library
    return {a.dest: a for a in parser._actions if a.option_strings}


def test_every_dynamic_flag_default_is_the_librarys():
    import inspect

    from tactilecal.cli import build_parser
    from tactilecal.dynamic import evaluate, filter_recording, fit_filter

    parser = build_parser()
    owners = {("dynamic", "fit"): fit_filter, ("dynamic", "apply"): filter_recording,
              ("dynamic", "evaluate"): evaluate}
    checked = 0
    for path, function in owners.items():
        signature = inspect.signature(function).parameters
        for dest, action in _actions(parser, *path).items():
            if dest in signature:
                assert action.default == signature[dest].default, (path, dest)
                checked += 1
    assert checked >= 12  # model, band, method, coherence, power, outside, noise, force, ...
    assert fit_filter.__kwdefaults__["model"] == "auto"  # the same door as dynamic fit
    help_text = _actions(parser, "dynamic", "apply")["chunk_frames"].help
    assert "%(default)s" in help_text and "65536" not in help_text  # said, not restated


def test_fit_prints_readable_lines_and_no_library_noise(files, tmp_path, capsys):
    out = tmp_path / "F.json"
    assert main(["dynamic", "fit", files["sensor"], files["cell"], "--out", str(out)]) == 0
    captured = capsys.readouterr()
    lines = captured.out.splitlines()
    assert [line.split(":")[0] for line in lines] == ["fit", "band", "model choice", "clock",
                                                      "filter"]
    assert "{" not in captured.out  # no raw dict
    assert re.search(r"A = 0\.1\d+ \+- .* \(natural-log A 0\.04\d+\)", lines[0])
    assert "Warning" not in captured.err and "encountered" not in captured.err
    assert captured.err.strip() == f"filter written to {out}"


def test_evaluate_says_its_clock_and_labels_the_realigned_figure(files, filter_json, capsys):
    assert main(["-q", "dynamic", "evaluate", str(filter_json), files["blind_sensor"],
                 files["blind_cell"], "--realign"]) == 0
    text = capsys.readouterr().out
    assert "at the fitted clock (lag" in text and "timing error" in text
    assert "re-aligned by" in text and "not what the filter delivers" in text
    assert main(["-q", "dynamic", "evaluate", str(filter_json), files["blind_sensor"],
                 files["blind_cell"], "--lag", "0.5", "--json"]) == 0
    result = json.loads(capsys.readouterr().out)
    assert result["clock"] == "given" and result["lag_s"] == 0.5
    assert result["rms_after_realigned_N"] is None  # not asked for


def test_an_unknown_model_is_bad_input_naming_the_choices(files, tmp_path, capsys):
    assert main(["dynamic", "fit", files["sensor"], files["cell"], "--out",
                 str(tmp_path / "F.json"), "--model", "cubic"]) == 1
    assert capsys.readouterr().err.strip() == (
        "tactilecal dynamic fit: error: --model 'cubic'; expected one of auto, log, log10, "
        "log-quadratic, rational, wiener")
