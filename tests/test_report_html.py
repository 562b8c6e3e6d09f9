"""The HTML report: sections, embedded figures, provenance, errors, headless Chromium."""

import hashlib
import re
import shutil
import subprocess

import numpy as np
import pytest

from tactilecal.calibration import calibrate, points_from_frames
from tactilecal.dynamic import CorrectionFilter, fit_transfer
from tactilecal.dynamic._transfer import TransferFunction
from tactilecal.io import write_netcdf
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
    CorrectionFilter.from_model(fit_transfer(tf, model="log10"), fs_hz=4000.0).save(
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
    return re.findall(r'<img alt="([^"]*)" src="([^"]*)"', text)


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
                     "patch.nc: pressure map at the peak-force frame",
                     "patch.nc: centre-of-force path",
                     "patch.nc: row and column profiles at the peak-force frame"]:
        assert any(c.startswith(expected) for c in captions), expected
    assert "raw readings calibrated with method &#x27;power&#x27;" in text
    # calibration given with --cal comes first, then the inputs in order
    heads = re.findall(r"<h2>([^<]*)</h2>", text)
    assert heads == ["Calibration: cal.json", "Recording: patch.nc",
                     "Dynamic filter: FILTER.json", "Provenance"]
    # provenance: each file's SHA-256, versions, command
    for name in ("cal.json", "FILTER.json", "patch.nc"):
        digest = hashlib.sha256((files / name).read_bytes()).hexdigest()
        assert digest in text and str((files / name).resolve()) in text
    for item in ("tactilecal", "numpy", "matplotlib", "report created (UTC)",
                 "tactilecal report ..."):
        assert f"<td>{item}</td>" in text


def test_peak_force_number_is_the_calibrated_peak(files, session, report):
    _, result, _ = load_input(files / "cal.json")
    # by hand: the sensor law applied to the peak frame's readings, summed
    raw = session.recording(0).values
    peak = max(float(np.nansum(result.predict_sensel_force(frame))) for frame in raw)
    text = report.read_text()
    assert f"<td>peak total force [N]</td><td>{peak:.6g}</td>" in text


def test_raw_recording_without_calibration_says_so(session, tmp_path):
    text = build_report([session.recording(0)])
    assert "holds raw readings and no calibration was given" in text
    assert images(text) == []


def test_errors_and_atomic_write(files, tmp_path):
    bad = tmp_path / "other.json"
    bad.write_text('{"hello": 1}')
    out = tmp_path / "r.html"
    out.write_text("previous report")
    with pytest.raises(ValueError, match=r"other.json: JSON with keys \['hello'\] is neither"):
        write_report([bad], out)
    assert out.read_text() == "previous report"  # untouched on failure
    with pytest.raises(ValueError, match="not valid JSON"):
        (tmp_path / "broken.json").write_text("{")
        write_report([tmp_path / "broken.json"], out)
    with pytest.raises(FileNotFoundError, match="report input .*missing.csv does not exist"):
        write_report([tmp_path / "missing.csv"], out)
    with pytest.raises(ValueError, match="no report inputs"):
        write_report([], out)
    with pytest.raises(ValueError, match="report input of type int"):
        write_report([3], out)
    with pytest.raises(FileNotFoundError, match="cannot write .*r.html: folder .*nope does not"):
        write_report([files / "cal.json"], tmp_path / "nope" / "r.html")


CHROMIUM_FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic",
                  "--no-first-run", "--disable-background-networking",
                  "--disable-component-update", "--disable-sync",
                  "--virtual-time-budget=5000", "--dump-dom"]
MARK_IMAGES = ('<script>window.addEventListener("load",()=>{for(const i of document.images)'
               '{i.setAttribute("data-natural-width",i.naturalWidth)}'
               'document.body.setAttribute("data-checked","yes")});</script></body>')


def test_report_renders_its_figures_in_chromium(report, tmp_path):
    browser = shutil.which("chromium") or shutil.which("chromium-browser")
    if browser is None:
        pytest.skip("headless Chromium not installed (Debian package 'chromium'); "
                    "rendering not checked")
    n_images = len(images(report.read_text()))
    page = tmp_path / "checked.html"
    page.write_text(report.read_text().replace("</body>", MARK_IMAGES))
    run = subprocess.run([browser, *CHROMIUM_FLAGS, f"--user-data-dir={tmp_path / 'profile'}",
                          page.as_uri()], capture_output=True, text=True, timeout=120)
    assert 'data-checked="yes"' in run.stdout, run.stderr[-2000:]
    widths = [int(w) for w in re.findall(r'data-natural-width="(\d+)"', run.stdout)]
    assert len(widths) == n_images == 8
    assert all(w > 100 for w in widths)  # every embedded PNG decoded to a real image


def test_zvyagin_calibration_shows_its_figures(session):
    zvyagin_plots = pytest.importorskip("tactilecal.zvyagin._plots",
                                        reason="Zvyagin figures not in this version")
    result = calibrate(points_from_frames(session.raw, session.load_N), method="zvyagin")
    text = build_report([result])
    captions = [alt for alt, _ in images(text)]
    names = [n for n in zvyagin_plots.__all__ if n.startswith("plot_")]
    zvyagin = [c for c in captions if "Zvyagin (2022): " in c]
    assert len(zvyagin) == len(names) >= 5, re.findall(r'class="note">([^<]*)', text)
    assert any("Figure 9" in c for c in zvyagin)
    assert "not drawn" not in text
