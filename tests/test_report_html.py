"""The HTML report: sections, embedded figures, provenance, errors, headless Chromium."""

import base64
import hashlib
import json
import os
import re
import shutil
import subprocess

import numpy as np
import pytest

from tactilecal._text import number
from tactilecal.calibration import calibrate, points_from_frames
from tactilecal.dynamic import CorrectionFilter, fit_transfer
from tactilecal.dynamic._transfer import TransferFunction
from tactilecal.io import read_netcdf, write_netcdf
from tactilecal.report import build_report, load_input, write_report
from tactilecal.simulate import deadweight_session, make_sensor


@pytest.fixture(scope="module")
def session():
    return deadweight_session(make_sensor("5051", seed=1), n_patches=30, seed=3)


@pytest.fixture(scope="module")
def files(session, tmp_path_factory):
    folder = tmp_path_factory.mktemp("report")
    result = calibrate(points_from_frames(session.raw, session.load_N), method="power")
    result.to_json(folder / "cal.json")
    f = np.arange(0.0, 140.0)
    tf = TransferFunction(f, 1 + 0.11 * np.log10(f + 1), np.ones_like(f), f > 0, "h2",
                          4000.0, 400, 0.9)
    CorrectionFilter.from_model(fit_transfer(tf, model="log10"), fs_hz=4000.0).to_json(
        folder / "FILTER.json")
    write_netcdf(session.recording(0), folder / "patch.nc")
    return folder


@pytest.fixture(scope="module")
def report(files):
    """One report on a raw recording (with --cal) and a filter, built once."""
    out = write_report([files / "patch.nc", files / "FILTER.json"], files / "r.html",
                       calibration=files / "cal.json", command="tactilecal report ...")
    return out


def images(text):
    return re.findall(r'<img alt="([^"]*)" width="\d+" height="\d+" src="([^"]*)"', text)


def png_width(src):
    """Pixel width of a base64 PNG data URI (IHDR, bytes 16-20)."""
    data = base64.b64decode(src.split(",", 1)[1])
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    return int.from_bytes(data[16:20], "big")


def test_calibration_filter_and_raw_recording(files, report):
    text = report.read_text()
    imgs = images(text)
    assert all(src.startswith("data:image/png;base64,") for _, src in imgs)
    assert not re.search(r'(src|href)="(?!data:)', text)  # nothing fetched from outside
    captions = [alt for alt, _ in imgs]
    for expected in ["cal.json: calibration curve", "cal.json: calibrated against applied load",
                     "cal.json: error histogram",
                     "FILTER.json: transfer function, fitted model and filter gain",
                     "patch.nc: total force and contact area against time",
                     # the three maps are one figure (a printed page holds them with a plot)
                     "patch.nc: peak-pressure map, the peak-force frame and the "
                     "centre-of-force path",
                     "patch.nc: row and column profiles at the peak-force frame"]:
        assert any(c.startswith(expected) for c in captions), expected
    assert "raw readings calibrated with method &#x27;power&#x27;" in text
    # calibration given with --cal comes first, then the inputs in order
    heads = re.findall(r"<h2>([^<]*)</h2>", text)
    assert heads == ["Calibration: cal.json", "Recording: patch.nc",
                     "Dynamic filter: FILTER.json", "Provenance"]
    # provenance: each file's SHA-256 (one per input set in the summary: here each kind is
    # one file), and every path, versions and the command (in collapsible sections)
    summary = text[text.index("<h2>Provenance</h2>"):text.index("<details>",
                                                                  text.index("<h2>Provenance"))]
    for name in ("cal.json", "FILTER.json", "patch.nc"):
        digest = hashlib.sha256((files / name).read_bytes()).hexdigest()
        assert digest in summary and str((files / name).resolve()) in text
    for item in ("tactilecal", "numpy", "matplotlib"):
        assert f"<td>{item}</td>" in text
    for item in ("report created (UTC)", "tactilecal report ..."):
        assert f"<td>{item}</td>" in summary


def test_peak_force_number_is_the_calibrated_peak(files, session, report):
    _, result, _ = load_input(files / "cal.json")
    # by hand: the sensor law applied to the peak frame's readings, summed
    raw = session.recording(0).values
    peak = max(float(np.nansum(result.predict_sensel_force(frame))) for frame in raw)
    text = report.read_text()
    assert f"<td>peak total force</td><td>{number(peak)} N</td>" in text


def test_raw_recording_without_calibration_is_shown_in_raw_readings(session):
    recording = session.recording(0)
    text = build_report([recording])
    assert "holds raw readings and no calibration was given" in text
    captions = [alt for alt, _ in images(text)]
    # the raw-weighted centre's path is drawn over the peak raw map, at the sensor's scale
    assert captions == ["DataArray in memory: sum of raw readings and loaded area against "
                        "time", "DataArray in memory: peak raw map"]
    largest = float(np.nansum(recording.values, axis=(1, 2)).max())
    assert f"<td>largest sum of raw readings</td><td>{number(largest)}</td>" in text


@pytest.mark.parametrize("kind", ["path", "recording", "result"])
def test_one_input_is_a_report_on_a_list_of_one(files, session, kind):
    """A recording is iterable (its frames) and a path a string: either alone is one input."""
    one = {"path": files / "cal.json", "recording": session.recording(0),
           "result": load_input(files / "cal.json")[1]}[kind]
    alone, listed = build_report(one, player=False), build_report([one], player=False)
    for part in (images, lambda text: re.findall(r"<h2>([^<]*)</h2>", text)):
        assert part(alone) == part(listed) and part(alone)


def test_every_figure_is_drawn_at_twice_its_size_and_says_how_to_read_it(report):
    text = report.read_text()
    for width, src in re.findall(r'<img alt="[^"]*" width="(\d+)" height="\d+" '
                                 r'src="([^"]*)"', text):
        assert png_width(src) == pytest.approx(2 * int(width), abs=2)
    guides = re.findall(r"<figcaption><b>[^<]+\.</b> ([^<]+)</figcaption>", text)
    # 3 calibration, 1 filter, 3 recording (force, the maps in one figure, profiles)
    assert len(guides) == len(images(text)) == 7
    assert all(len(guide.split()) >= 12 for guide in guides)


def test_method_comparison_lists_every_calibration_with_its_held_out_errors(session):
    from tactilecal.calibration import validate

    points = points_from_frames(session.raw, session.load_N)
    with pytest.warns(UserWarning, match="linear calibration: .*bends away"):  # b is not 1
        linear = calibrate(points[:20], method="linear")
    results = {"power": calibrate(points[:20], method="power"), "linear": linear,
               "lut": calibrate(points[:20], method="lut")}
    check = validate(results["power"], points[20:])
    text = build_report([*results.values(), check])
    heads = re.findall(r"<h2>([^<]*)</h2>", text)
    assert heads == ["Method comparison", *["Calibration: CalibrationResult in memory"] * 3,
                     "Validation: ValidationResult in memory", "Provenance"]
    table = text[text.index("<h2>Method comparison</h2>"):text.index("<h2>Calibration")]
    rows = re.findall(r"<tr><td>CalibrationResult in memory</td><td>([\w-]+)</td>", table)
    assert rows == ["power", "linear", "lut"]
    held_out = check.metrics["median_abs_error_pct"]
    assert f"<td>{number(held_out)}</td>" in table
    assert table.count("no validation input") == 2  # linear and lut were not validated
    assert "Calibration curves of all methods" in table


def _evaluation(**change):
    """An evaluation.json's content (``tactilecal dynamic evaluate``), three bins."""
    f_hz = np.arange(1.0, 4.0)
    return {"format": "tactilecal-dynamic-evaluation/1", "lag_s": 0.1, "clock": "fitted",
            "static_factor": 1.0, "fs_hz": 4000.0, "band_hz": [1.0, 140.0],
            "rms_before_N": 8.0, "rms_after_N": 2.0, "timing_error_s": 0.0,
            "above_band_share": 0.0, "f_hz": f_hz.tolist(),
            "error_before_pct": (-0.2 * f_hz).tolist(), "error_after_pct": (0.01 * f_hz).tolist(),
            "phase_before_deg": (-f_hz).tolist(), "phase_after_deg": (0 * f_hz).tolist(),
            **change}


def test_blind_test_section_shows_the_error_before_and_after():
    text = build_report([_evaluation()])
    assert re.findall(r"<h2>([^<]*)</h2>", text)[0] == ("Blind test of a dynamic filter: "
                                                        "evaluation dict in memory")
    assert "<td>improvement (before / after)</td><td>4</td>" in text
    assert "<td>clock</td><td>fitted (lag 0.1 s)</td>" in text
    assert [alt for alt, _ in images(text)] == [
        "evaluation dict in memory: amplitude and phase error before and after the filter "
        "(Gillis 2013, Fig. 4.12)"]


@pytest.mark.parametrize(("change", "message"), [
    ({"rms_after_N": "x"}, r"key 'rms_after_N' of dict input is 'x' \(str\); "
                           "expected a number"),
    ({"rms_before_N": -1.0}, r"key 'rms_before_N' of .* is -1.0; expected a finite number >= 0"),
    ({"f_hz": "abc"}, r"key 'f_hz' of .* is 'abc' \(str\); expected a list of numbers"),
    ({"error_before_pct": [1.0, 2.0]}, r"per-frequency lists of lengths \{'f_hz': 3, "
                                       r"'error_before_pct': 2, 'error_after_pct': 3"),
    ({"error_after_pct": None}, r"key 'error_after_pct' of .* is None \(NoneType\); expected "
                                "a list of numbers"),
    ({"timing_error_s": 1e308}, r"key 'timing_error_s' of .* is 1e\+308; expected a finite "
                                "number >= -1 and <= 1"),
    ({"clock": "guessed"}, r"key 'clock' of .* is 'guessed'; expected one of fitted, given"),
])
def test_a_bad_evaluation_is_refused_naming_its_key(change, message):
    with pytest.raises((ValueError, TypeError), match=message):
        build_report([_evaluation(**change)])


def test_a_perfect_correction_is_an_infinite_improvement_not_a_crash():
    # it divided by zero with a traceback before; a non-finite number is shown as n/a
    text = build_report([_evaluation(rms_after_N=0.0)])
    assert "<td>improvement (before / after)</td><td>n/a</td>" in text


def test_errors_and_atomic_write(files, tmp_path):
    bad = tmp_path / "other.json"
    bad.write_text('{"hello": 1}')
    out = tmp_path / "r.html"
    out.write_text("<!DOCTYPE html>previous report")
    with pytest.raises(ValueError, match=r"r.html exists; expected a new path"):
        write_report([files / "cal.json"], out)
    with pytest.raises(ValueError, match=r"other.json has no key 'format'; expected a "
                                         "tactilecal result JSON"):
        write_report([bad], out, overwrite=True)
    assert out.read_text() == "<!DOCTYPE html>previous report"  # untouched on failure
    with pytest.raises(ValueError, match="not valid JSON"):
        (tmp_path / "broken.json").write_text("{")
        write_report([tmp_path / "broken.json"], out, overwrite=True)
    with pytest.raises(FileNotFoundError, match="report input .*missing.csv does not exist"):
        write_report([tmp_path / "missing.csv"], out, overwrite=True)
    with pytest.raises(ValueError, match="no report inputs"):
        write_report([], out, overwrite=True)
    with pytest.raises(ValueError, match=r"calibration= \(--cal\) FILTER.json is a filter; "
                                         "expected a calibration JSON"):
        write_report([files / "patch.nc"], out, calibration=files / "FILTER.json",
                     overwrite=True)
    with pytest.raises(ValueError, match="report input of type int"):
        write_report([3], out, overwrite=True)
    with pytest.raises(FileNotFoundError, match="cannot write .*r.html: folder .*nope does not"):
        write_report([files / "cal.json"], tmp_path / "nope" / "r.html")


CHROMIUM_FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic",
                  "--no-first-run", "--disable-background-networking",
                  "--disable-component-update", "--disable-sync",
                  "--virtual-time-budget=5000", "--dump-dom"]
MARK_IMAGES = ('<script>window.addEventListener("load",()=>{for(const i of document.images)'
               '{i.setAttribute("data-natural-width",i.naturalWidth)}'
               'document.body.setAttribute("data-checked","yes")});</script></body>')


CHECK_PAGE = (
    '<script>window.addEventListener("load",()=>{'
    'for(const i of document.images){i.setAttribute("data-natural-width",i.naturalWidth)}'
    'const view=document.documentElement.clientWidth;'
    'const over=[...document.querySelectorAll("body *")]'
    '.filter(e=>e.getBoundingClientRect().right>view+1).map(e=>e.tagName);'
    'document.body.setAttribute("data-overflow",over.join(",")||"none");'
    'document.body.setAttribute("data-checked","yes")});</script></body>')


def _chromium():
    browser = shutil.which("chromium") or shutil.which("chromium-browser")
    if browser is None:
        if os.environ.get("CI") == "true":
            pytest.fail("CI=true but headless Chromium is not installed; .ci/run installs "
                        "Debian's 'chromium' package")
        pytest.skip("headless Chromium not installed (Debian package 'chromium'); "
                    "rendering not checked")
    return browser


@pytest.mark.slow  # a browser renders the page
def test_report_renders_at_1280_px_without_overflow(report, tmp_path):
    browser = _chromium()
    page = tmp_path / "checked.html"
    page.write_text(report.read_text().replace("</body>", CHECK_PAGE))
    common = [browser, *CHROMIUM_FLAGS[:-1], "--window-size=1280,2000",
              f"--user-data-dir={tmp_path / 'profile'}"]
    run = subprocess.run([*common, "--dump-dom", page.as_uri()], capture_output=True,
                         text=True, timeout=120)
    assert 'data-checked="yes"' in run.stdout, run.stderr[-2000:]
    assert 'data-overflow="none"' in run.stdout  # no element wider than the viewport
    widths = [int(w) for w in re.findall(r'data-natural-width="(\d+)"', run.stdout)]
    assert len(widths) == len(images(report.read_text())) == 7
    assert all(w > 100 for w in widths)  # every embedded PNG decoded to a real image
    shot = tmp_path / "shot.png"
    subprocess.run([*common, f"--screenshot={shot}", page.as_uri()], capture_output=True,
                   timeout=120, check=True)
    header = shot.read_bytes()[:24]
    assert header[:8] == b"\x89PNG\r\n\x1a\n" and int.from_bytes(header[16:20], "big") == 1280


def test_zvyagin_calibration_shows_its_figures(session):
    from tactilecal.calibration.methods.zvyagin import _plots as zvyagin_plots

    result = calibrate(points_from_frames(session.raw, session.load_N), method="zvyagin")
    text = build_report([result])
    captions = [alt for alt, _ in images(text)]
    names = [n for n in zvyagin_plots.__all__ if n.startswith("plot_")]
    zvyagin = [c for c in captions if "Zvyagin (2022) " in c]
    assert len(zvyagin) == len(names) >= 5, re.findall(r'class="note">([^<]*)', text)
    assert any("Fig. 9" in c for c in zvyagin)


def test_a_calibration_is_not_shown_as_applied_to_a_calibrated_recording(files, tmp_path):
    from tactilecal.calibration import CalibrationResult

    calibrated = CalibrationResult.from_json(files / "cal.json").apply(
        read_netcdf(files / "patch.nc"))
    write_netcdf(calibrated, tmp_path / "kpa.nc")
    with pytest.raises(ValueError, match=r"calibration= \(--cal\) applies to raw recordings, "
                                         r"but kpa.nc is already calibrated \(units 'kPa'\)"):
        write_report([tmp_path / "kpa.nc"], tmp_path / "r.html", calibration=files / "cal.json")
    assert not (tmp_path / "r.html").exists()
    text = write_report([files / "cal.json", tmp_path / "kpa.nc"],
                        tmp_path / "r.html").read_text()
    assert "kpa.nc is already calibrated (units kPa): the calibration among the inputs is not " \
           "applied to it" in text
    assert "raw readings calibrated with method" not in text


EVALUATION = {"format": "tactilecal-dynamic-evaluation/1", "lag_s": 0.01, "clock": "fitted",
              "static_factor": 1.2, "fs_hz": 100.0, "band_hz": [1.0, 40.0],
              "rms_before_N": 3.0, "rms_after_N": 1.0, "timing_error_s": 0.0,
              "above_band_share": 0.0, "f_hz": [1.0, 2.0], "error_before_pct": [-1.0, -3.0],
              "error_after_pct": [0.1, -0.2], "phase_before_deg": [-1.0, -2.0],
              "phase_after_deg": [0.0, 0.1]}


def test_a_blind_test_json_is_checked_before_it_is_drawn(tmp_path):
    path = tmp_path / "evaluation.json"
    path.write_text(json.dumps({**EVALUATION, "f_hz": [1.0, "x"]}))
    with pytest.raises(TypeError, match=r"key 'f_hz' of .*evaluation.json"):
        write_report([path], tmp_path / "r.html")


def test_an_absurd_blind_test_error_is_refused_naming_the_key(tmp_path):
    path = tmp_path / "evaluation.json"
    path.write_text(json.dumps({**EVALUATION, "error_before_pct": [-1.0, 1e308]}))
    with pytest.raises(ValueError, match=r"key 'error_before_pct' of .*evaluation.json"):
        write_report([path], tmp_path / "r.html")
