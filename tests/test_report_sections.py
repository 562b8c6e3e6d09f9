"""What the report says: header calibration, units, regions, one time axis, folded
provenance, honest captions, numbers at their precision, progress figure by figure."""

import re

import numpy as np
import pytest

from tactilecal._text import number
from tactilecal.report import build_report
from tactilecal.simulate import compartment_recording


def _cells(text):
    return re.findall(r"<tr><td>(.*?)</td><td>(.*?)</td>", text)


@pytest.fixture(scope="module")
def walk(fscan_asf, fscan_right_asf):
    """One report of the left and right foot of a walk, in MPa, built once; its progress."""
    seen = []

    def progress(iterable, *, total=None, desc=None):
        for item in iterable:
            seen.append(desc)
            yield item

    text = build_report([fscan_asf, fscan_right_asf], units="MPa", player=False,
                        progress=progress)
    return text, seen


def test_the_exports_own_calibration_is_shown_in_the_units_asked(walk):
    text, _ = walk
    left = text[:text.index("<h2>Recording: footPress_FrasP01R.asf")]
    rows = dict(_cells(left))
    # 75.0001 kg x 9.80665 / (4798 x 25.8064 mm2) = 5.940 kPa per raw count (realdata README)
    assert rows["law per sensel"] == "p = 0.00594 MPa x raw"
    assert rows["calibration point 1"] == ("75 kg (735.5 N), raw sum 4798, 240 loaded "
                                           "sensels")
    assert rows["method"] == "Walk calibration, linear through zero (1 point)"
    assert rows["saturation pressure (header)"] == rows["pressure at raw 255 by this law"] \
        == "1.515 MPa"
    assert rows["largest sensel pressure"] == "0.76 MPa"  # 760 kPa


def test_units_are_checked_and_converted():
    import xarray as xr

    from tactilecal.report._recording import display_units, header_blocks

    rec = xr.DataArray(np.zeros((1, 2, 2)), dims=("frame", "row", "col"),
                       attrs={"units": "MPa", "sensel_area_mm2": 25.8064,
                              "calibration_point_1_load": 75.0001,
                              "calibration_point_1_load_unit": "kg",
                              "calibration_point_1_load_N": 735.4997,
                              "calibration_point_1_raw_sum": 4798.0,
                              "calibration_point_1_loaded_cells": 240})
    assert display_units(rec, None) == ("MPa", 1000.0)  # an MPa recording stays in MPa
    unit, factor = display_units(rec, "psi")
    rows = dict(_cells("".join(header_blocks(rec, unit, factor))))
    assert rows["law per sensel"] == "p = 0.8615 psi x raw"  # 5.940 kPa / 6.894757
    with pytest.raises(ValueError, match=r"units \(--units\) 'N' is a force unit; expected a "
                                         "pressure unit"):
        display_units(rec, "N")


def test_regions_of_a_knee_and_their_centres():
    from types import SimpleNamespace

    from tactilecal.report._recording import _region_blocks

    knee = compartment_recording(n_frames=40)
    options = SimpleNamespace(regions="contacts", gap_mm=None, threshold_kPa=0.0, unit="kPa",
                              factor=1.0, units=None)
    text = "".join(_region_blocks(knee.recording, "knee.nc", options))
    assert "<h3>Regions of knee.nc</h3>" in text
    captions = re.findall(r'<img alt="([^"]*)"', text)
    assert captions == ["knee.nc: force of every region",
                        "knee.nc: centre of force of every region"]
    peaks = re.findall(r"<tr><td>(contact \d)</td><td>split_contacts[^<]*</td><td>\d+</td>"
                       r"<td>([\d.]+) N</td>", text)
    assert [name for name, _ in peaks] == ["contact 1", "contact 2"]
    np.testing.assert_allclose([float(v) for _, v in peaks], knee.force_N.max(axis=0),
                               rtol=5e-4)  # written to four significant digits


def test_left_and_right_on_one_time_axis(walk):
    text, _ = walk
    section = text[text.index("<h2>Recordings on one time axis</h2>"):]
    assert "Total force of every recording on one time axis" in section
    steps = re.findall(r"<tr><td>(footPress_FrasP01[LR]\.asf)</td><td>\d+</td><td>([\d.]+) s"
                       r"</td>", section)
    sides = [name[-5] for name, _ in steps]
    starts = [float(s) for _, s in steps]
    # six stances of each foot (five complete, one cut by the recording), in time order
    assert starts == sorted(starts) and sides.count("L") == sides.count("R") == 6
    assert sum(a != b for a, b in zip(sides, sides[1:], strict=False)) == 11  # alternating


def test_progress_moves_figure_by_figure(walk):
    _, seen = walk
    # each block of a recording's section is counted as it is drawn
    assert seen.count("report: footPress_FrasP01L.asf") >= 6
    assert seen.count("report: one time axis") >= 2


def test_provenance_is_folded_into_one_hash_per_input_set(walk, fscan_asf, fscan_right_asf):
    import hashlib

    text, _ = walk
    summary = text[text.index("<h2>Provenance</h2>"):]
    summary = summary[:summary.index("<details>")]
    lines = sorted(f"{hashlib.sha256(p.read_bytes()).hexdigest()}  {p.resolve()}"
                   for p in (fscan_asf, fscan_right_asf))
    digest = hashlib.sha256("\n".join(lines).encode()).hexdigest()
    assert f"<td>SHA-256 of the set {digest}</td>" in summary
    assert "2 recordings (footPress_FrasP01L.asf, footPress_FrasP01R.asf)" in summary
    assert text.count("<details>") == 3  # every input, the versions, the JSON
    assert '<pre class="provenance-json">{' in text


def test_a_calibration_from_many_files_lists_them_folded():
    from tactilecal.calibration import calibrate, points_from_frames
    from tactilecal.simulate import deadweight_session, make_sensor

    session = deadweight_session(make_sensor("5051", seed=1), n_patches=12, seed=2)
    result = calibrate(points_from_frames(session.raw, session.load_N), method="power")
    inputs = [{"path": f"/data/p{k}.csv", "sha256": f"{k:064x}", "size_bytes": 10}
              for k in range(151)]
    result.provenance["inputs"] = inputs
    text = build_report([result])
    record = text[text.index("calibration record"):]
    assert "<td>inputs (151 files)</td><td>SHA-256 of the set " in record
    assert record.index("<details><summary>all 151 input files") < record.index("<img")
    # an error of 1e-13 N on loads of tens of newtons is 0 at their precision
    assert "<td>rmse_N</td><td>" in text


def test_metrics_far_below_the_loads_precision_are_zero():
    from tactilecal.report._sections import _metric

    assert _metric("rmse_N", 1.137e-13, 50.0) == "0 (below 1e-9 of the largest load)"
    assert _metric("rmse_N", 0.0035, 50.0) == "0.0035"
    assert _metric("median_abs_error_pct", 1e-13, 50.0) == "1e-13"


@pytest.mark.parametrize("mode", ["faithful", "robust"])
def test_the_energy_figure_marks_what_each_mode_returned(mode):
    from tactilecal.calibration.methods.zvyagin import Options
    from tactilecal.calibration.methods.zvyagin._calibrate import zvyagin_fit
    from tactilecal.report._sections import energy_caption
    from tactilecal.simulate import patch_histograms

    res = zvyagin_fit(*patch_histograms(20, seed=1)[:2], Options(mode=mode))
    ax = res.plot_energy()
    marks = {line.get_label(): float(line.get_xdata()[0]) for line in ax.lines[1:]}
    curve_b0 = res.final.get("curve_b0", res.b0)
    grid, energy = res.final["b_grid"], res.final["E_grid"]
    assert marks[f"minimum of E on the curve: b0 = {curve_b0:.4f}"] == pytest.approx(curve_b0)
    # the line marks the minimum of E: within one grid step of the grid's smallest E
    assert abs(curve_b0 - grid[np.argmin(energy)]) <= np.max(np.diff(grid))
    caption = energy_caption(res)
    if mode == "robust":
        assert res.final["free"] and f"returned law (robust free fit): b = {res.b0:.4f}" in marks
        assert "robust mode returned another law" in caption
    else:
        assert len(marks) == 1 and "the orange line at its minimum is the chosen b0" in caption


def test_validation_shares_are_percentages():
    from tactilecal.calibration import calibrate, points_from_frames, validate
    from tactilecal.simulate import deadweight_session, make_sensor

    session = deadweight_session(make_sensor("5051", seed=1), n_patches=12, seed=2)
    points = points_from_frames(session.raw, session.load_N)
    check = validate(calibrate(points[:8], method="power"), points[8:])
    text = build_report([check])
    share = check.metrics["within_5pct"]
    assert f"<td>within_5pct</td><td>{100 * share:.1f} %</td>" in text


def test_each_validation_is_matched_to_the_calibration_it_scored():
    """Two calibrations of one method: matched by the calibration's fingerprint, not by name."""
    from tactilecal.calibration import calibrate, points_from_frames, validate
    from tactilecal.simulate import family_sessions

    train, test = family_sessions("5051-zvyagin", seed=0)
    points = points_from_frames(train.raw.values, train.load_N)
    held_out = points_from_frames(test.raw.values, test.load_N)
    l1 = calibrate(points, method="power", objective="l1")
    relative = calibrate(points, method="power", objective="relative")
    checks = [validate(cal, held_out) for cal in (l1, relative)]
    assert checks[0].metrics["median_abs_error_pct"] != checks[1].metrics["median_abs_error_pct"]
    text = build_report([l1, relative, *reversed(checks)], player=False)
    comparison = text[text.index("<h2>Method comparison</h2>"):text.index("<h2>Calibration")]
    rows = re.findall(r"<tr><td>[^<]*</td><td>power</td>.*?</tr>", comparison)
    assert len(rows) == 2
    for row, check in zip(rows, checks, strict=True):
        assert f"<td>{number(check.metrics['median_abs_error_pct'])}</td>" in row, row
