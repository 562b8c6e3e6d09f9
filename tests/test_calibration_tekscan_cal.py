"""Tekscan calibration files (.cal) read into calibration points that every method fits.

No .cal file written by Tekscan's software is available here (a search of public code for
CAL_HST, CAL_RSI and CAL_EXP_ENABLED found none), so the files below are written from the
format's description (issue 34): header lines like an export's, then per point CAL_FPI_n
(load in UNITS), CAL_FPC_n, CAL_RSI_n (raw sum), CAL_RSC_n, CAL_SM_n (loaded sensels) and
CAL_HST_n (256 counts), and flags. Point 1 is the SDK's sample: 170 PSI, raw sum 6940, 186
sensels, a histogram summing to exactly 186 sensels and 6940 counts.
"""

import warnings

import numpy as np
import pytest

from tactilecal import TactilecalError
from tactilecal._units import KPA_MM2_TO_N, PSI_TO_KPA
from tactilecal.calibration import METHODS, calibrate, load_points, validate
from tactilecal.simulate import patch_histograms

AREA_MM2 = 1.6129  # the 5051's sensel: SENSEL_AREA 0.016129 cm2
A_N, B = 0.0035, 1.16  # the law of the simulated points


def _fix(hist, loaded=186, raw_sum=6940):
    """Adjust a histogram to exactly ``loaded`` sensels and ``raw_sum`` counts."""
    hist = hist.copy()
    hist[37] += loaded - hist[1:].sum()
    while hist @ np.arange(256) != raw_sum:
        step = 1 if hist @ np.arange(256) < raw_sum else -1
        src = 37 if hist[37] > 0 else int(np.flatnonzero(hist[1:255])[0]) + 1
        hist[src] -= 1
        hist[src + step] += 1
    return hist


def write_cal(path, points, *, units="PSI", exp_enabled=1, extra=""):
    """Write a .cal file; ``points`` is a list of (load in UNITS, histogram)."""
    lines = ["SENSOR_TYPE 5051", "ROWS 44", "COLS 44", "ROW_SPACING 0.127 cm",
             "COL_SPACING 0.127 cm", "SENSEL_AREA 0.016129 cm2", f"UNITS {units}",
             "NOISE_THRESHOLD 3", f"CAL_EXP_ENABLED {exp_enabled}", "EQUFLAG 1",
             "CAL_TEMPERATURE_ENABLED 0", "CAL_TEMPERATURE 22.5"]
    for n, (load, hist) in enumerate(points, 1):
        lines += [f"CAL_FPI_{n} {float(load)!r}", f"CAL_FPC_{n} {n - 1}",
                  f"CAL_RSI_{n} {int(hist @ np.arange(256))}", f"CAL_RSC_{n} 1",
                  f"CAL_SM_{n} {int(hist[1:].sum())}",
                  f"CAL_HST_{n} " + " ".join(str(int(c)) for c in hist)]
    path.write_text("\r\n".join(lines) + extra + "\r\n")
    return path


def simulated_points(n=24, seed=4):
    """Dead-weight patches of a known law, their loads as pressures over loaded sensels."""
    hist, load_N, _ = patch_histograms(n, A_N=A_N, b=B, seed=seed)
    psi = load_N / (hist[:, 1:].sum(axis=1) * AREA_MM2 * KPA_MM2_TO_N) / PSI_TO_KPA
    return [(float(p), h) for p, h in zip(psi, hist, strict=True)], load_N


def test_the_sdk_point_reads_back_exactly(tmp_path):
    sdk = _fix(np.bincount(np.clip(np.random.default_rng(1).normal(37.3, 4, 186).round(), 1,
                                   254).astype(int), minlength=256))
    path = write_cal(tmp_path / "sdk.cal", [(170.0, sdk)])
    (point,) = load_points(path)
    assert int(point.histogram[1:].sum()) == point.loaded_cells == 186
    assert int(point.histogram @ np.arange(256)) == point.raw_sum == 6940
    # 170 psi over the 186 loaded sensels of 1.6129 mm2
    assert point.load_N == pytest.approx(170 * PSI_TO_KPA * 186 * AREA_MM2 * KPA_MM2_TO_N,
                                         rel=1e-12)
    assert (point.frame, point.label, point.source) == (1, "CAL point 1", "sdk.cal")
    assert point.sensor["sensor_type"] == "5051" and point.sensel_area_mm2 == AREA_MM2
    assert "CAL_FPC_1 0, CAL_RSC_1 1" in point.note


def test_every_method_fits_the_points_of_a_cal_file_and_validate_scores_them(tmp_path):
    points, load_N = simulated_points()
    path = write_cal(tmp_path / "session.cal", points)
    read = load_points(path)
    assert [p.raw_sum for p in read] == [float(h @ np.arange(256)) for _, h in points]
    np.testing.assert_allclose([p.load_N for p in read], load_N, rtol=1e-12)
    # a cubic through these points bends down above raw 147 and is refused; degree 2 is not
    options = {"polynomial": {"degree": 2}}
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        fits = {method: calibrate(path, method=method, **options.get(method, {}))
                for method in METHODS}
    # a power-law sensor (b = 1.2) read without noise: the linear laws and a quadratic are
    # said not to fit; no power law, no flexible law and not the default
    said = {str(w.message).split(" calibration:")[0] for w in caught}
    assert "linear" in said and not said & {"auto", "power", "zvyagin", "lut", "piecewise"}, \
        [str(w.message) for w in caught]
    power = fits["power"]
    assert power.params["b"] == pytest.approx(B, abs=0.02)
    assert power.params["A"] == pytest.approx(A_N, rel=0.1)
    assert fits["zvyagin"].params["b"] == pytest.approx(B, abs=0.05)
    for method, result in fits.items():  # every law predicts its own points
        assert result.metrics["median_abs_error_pct"] < 12, method
    held_out = write_cal(tmp_path / "other.cal", simulated_points(seed=9)[0])
    check = validate(power, held_out)
    assert check.metrics["n"] == 24 and check.metrics["median_abs_error_pct"] < 5


def test_the_files_own_law_is_reproduced(tmp_path):
    # I-Scan's 2-point power law: each loaded sensel at its point's mean raw reading carries
    # pressure = SCALE_FACTOR x raw^EXPONENT; the file states the law and the points it came
    # from, and power-2pt fitted to the points gives the law back
    scale_psi, exponent = 2.5, 1.3
    hists = [_fix(np.bincount(np.full(100, m), minlength=256), 100, 100 * m) for m in (20, 80)]
    hists[0] = _fix(np.bincount(np.r_[np.full(50, 19), np.full(50, 21)], minlength=256),
                    100, 2000)
    pressures = [scale_psi * (h @ np.arange(256) / h[1:].sum()) ** exponent for h in hists]
    path = write_cal(tmp_path / "law.cal", list(zip(pressures, hists, strict=True)),
                     extra=f"\r\nSCALE_FACTOR {scale_psi}\r\nEXPONENT {exponent}")
    fit = calibrate(path, method="power-2pt")
    from tactilecal.calibration import header_calibration
    from tactilecal.calibration._tekscan_cal import read_tekscan_cal

    _, header = read_tekscan_cal(path)
    stated = header_calibration({"scale_factor": float(header["SCALE_FACTOR"]),
                                 "exponent": float(header["EXPONENT"]), "units": "psi",
                                 "sensel_area_mm2": AREA_MM2})
    assert fit.params["b"] == pytest.approx(stated.params["b"], rel=1e-12)
    assert fit.params["A"] == pytest.approx(stated.params["A"], rel=1e-12)
    assert header["CAL_EXP_ENABLED"] == "1" and header["EQUFLAG"] == "1"


def test_calibrate_and_validate_take_a_cal_file_on_the_command_line(tmp_path, capsys):
    import json

    from tactilecal.cli import main

    points, _ = simulated_points(12)
    path = write_cal(tmp_path / "s.cal", points)
    out = tmp_path / "cal.json"
    assert main(["-q", "calibrate", str(path), "--method", "power", "--out", str(out)]) == 0
    capsys.readouterr()
    assert main(["-q", "validate", str(out), str(path), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["summary"]["n"] == 12


@pytest.mark.parametrize(("change", "message"), [
    (lambda t: t.replace("CAL_RSI_1 6940", "CAL_RSI_1 6941"),
     r"s.cal: CAL_HST_1 counts 186 loaded sensels with a raw sum of 6940; expected "
     r"CAL_SM_1 = 186 and CAL_RSI_1 = 6941"),
    (lambda t: t.replace("CAL_SM_1 186", "CAL_SM_1 185"), r"expected CAL_SM_1 = 185"),
    (lambda t: t.replace("CAL_HST_1 0 ", "CAL_HST_1 "),
     r"CAL_HST_1 on line \d+ of s.cal has 255 counts; expected 256"),
    (lambda t: t.replace("CAL_HST_1 0 ", "CAL_HST_1 x "),
     r"CAL_HST_1 on line \d+ of s.cal, raw value 0 is 'x'; expected a number"),
    (lambda t: t.replace("UNITS PSI", "UNITS mm"),
     r"UNITS on line 7 of s.cal is 'mm', a length; expected a pressure, force or mass"),
    (lambda t: t.replace("SENSEL_AREA 0.016129 cm2\n", ""), r"s.cal has no SENSEL_AREA"),
    (lambda t: t.replace("SENSEL_AREA 0.016129 cm2", "SENSEL_AREA 256 KPa"),  # found by fuzz
     r"SENSEL_AREA on line \d+ of s.cal is in 'kPa', a pressure unit; expected an area"),
    (lambda t: t.replace("SENSEL_AREA 0.016129 cm2", "SENSEL_AREA 1e308 cm2"),  # by fuzz
     r"SENSEL_AREA on line \d+ of s.cal: 1e\+308 cm2 is beyond the largest number in mm2"),
    (lambda t: t.replace("CAL_FPI_1 170.0\n", ""),
     r"s.cal: calibration point 1 lacks CAL_FPI_1; expected CAL_FPI \(load\)"),
    (lambda t: t.replace("CAL_FPI_1 170.0", "CAL_FPI_1 -3"),
     r"CAL_FPI_1 on line \d+ of s.cal is -3.0; expected a finite number > 0"),
])
def test_a_bad_cal_file_is_refused_naming_the_line(tmp_path, change, message):
    good = write_cal(tmp_path / "s.cal", [(170.0, _fix(np.bincount(np.full(186, 37),
                                                                   minlength=256)))])
    good.write_text(change(good.read_text()))
    with pytest.raises(TactilecalError, match=message):
        load_points(good)


def test_a_cal_file_has_no_frames_for_masks_or_equilibration(tmp_path):
    path = write_cal(tmp_path / "s.cal", [(170.0, _fix(np.bincount(np.full(186, 37),
                                                                   minlength=256)))])
    with pytest.raises(TactilecalError, match=r"s.cal is a Tekscan .cal file: it keeps "
                                              r"histograms, not frames; expected a manifest"):
        calibrate(path, method="linear", mask="detect")
    with pytest.raises(TactilecalError, match=r"s.cal is a Tekscan .cal file: it keeps each "
                                              r"point's histogram, not its frame, so "
                                              r"non-working sensels \(mask\) cannot"):
        load_points(path, mask=np.zeros((44, 44), bool))
    with pytest.raises(TactilecalError, match="has no CAL_FPI_n"):
        load_points(write_cal(tmp_path / "empty.cal", []))


def test_calibrate_says_a_recording_is_not_a_manifest(fscan_asf, capsys):
    from tactilecal.cli import main

    assert main(["calibrate", str(fscan_asf)]) == 1
    err = capsys.readouterr().err
    assert "footPress_FrasP01L.asf is a recording (a Tekscan export); calibrate expects a " \
           "manifest CSV (columns file, frame, load_N or mass_kg) or a Tekscan .cal file" in err


def test_one_load_is_refused_for_a_power_law(tmp_path):
    hist = _fix(np.bincount(np.full(186, 37), minlength=256))
    path = write_cal(tmp_path / "one.cal", [(170.0, hist), (170.0, hist)])
    with pytest.raises(TactilecalError, match=r"method 'power' needs at least two different "
                                              r"loads \(a power law has two parameters"):
        calibrate(path, method="power")
    assert calibrate(path, method="linear").params["b"] == 1.0
