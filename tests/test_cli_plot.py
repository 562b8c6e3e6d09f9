"""``tactilecal plot`` and ``tactilecal compare`` from calibration JSON files alone."""

import json

import pytest

from tactilecal.calibration import (
    CalibrationResult,
    calibrate,
    compare_calibrations,
    points_from_frames,
)
from tactilecal.cli import main
from tactilecal.simulate import deadweight_session, make_sensor


@pytest.fixture(scope="module")
def cal_files(tmp_path_factory):
    folder = tmp_path_factory.mktemp("cals")
    s = deadweight_session(make_sensor("5051", seed=1), n_patches=40, seed=2)
    points = points_from_frames(s.raw, s.load_N)
    paths = {}
    for name, kw in (("faithful", {"method": "zvyagin", "mode": "faithful"}),
                     ("robust", {"method": "zvyagin", "mode": "robust"}),
                     ("power", {"method": "power"})):
        paths[name] = folder / f"{name}.json"
        calibrate(points, **kw).to_json(paths[name])
    return paths


@pytest.mark.slow  # end to end: a command through every figure file
def test_plot_zvyagin_writes_figures_7_to_11(cal_files, tmp_path, capsys):
    assert main(["plot", str(cal_files["robust"]), "--out", str(tmp_path / "f"), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    names = sorted(p.rsplit("/", 1)[-1] for p in out["figures"])
    assert names == ["zvyagin_ab.png", "zvyagin_curves.png", "zvyagin_d_map.png",
                     "zvyagin_energy.png", "zvyagin_errors.png", "zvyagin_pairs.png"]
    for p in out["figures"]:
        with open(p, "rb") as fh:
            assert fh.read(8) == b"\x89PNG\r\n\x1a\n"


def test_plot_other_method_uses_generic_figures(cal_files, tmp_path, capsys):
    assert main(["-q", "plot", str(cal_files["power"]), "--out", str(tmp_path)]) == 0
    printed = capsys.readouterr().out.split()
    assert [p.rsplit("/", 1)[-1] for p in printed] == [
        "calibration_curve.png", "calibration_points.png", "calibration_errors.png"]


def test_plot_bad_arguments(cal_files, tmp_path, capsys):
    afile = tmp_path / "x.txt"
    afile.write_text("x")
    assert main(["plot", str(cal_files["power"]), "--out", str(afile)]) == 1
    assert "is a text file; expected a folder" in capsys.readouterr().err
    assert main(["plot", str(cal_files["power"]), "--out", str(tmp_path), "--dpi", "0"]) == 1
    assert "argument --dpi: '0'; expected a finite number > 0" in capsys.readouterr().err
    assert CalibrationResult.from_json(cal_files["power"]).method_result is None


def test_compare_table_and_curves(cal_files, tmp_path, capsys):
    files = [str(cal_files[k]) for k in ("faithful", "robust", "power")]
    assert main(["-q", "compare", *files, "--json", "--out", str(tmp_path)]) == 0
    out = json.loads(capsys.readouterr().out)
    rows = {r["name"]: r for r in out["rows"]}
    assert list(rows) == ["faithful", "robust", "power"]
    z = CalibrationResult.from_json(cal_files["faithful"])
    assert rows["faithful"]["I1"] == z.diagnostics["separation"][0]
    assert rows["faithful"]["A0"] == pytest.approx(z.params["A"])
    assert rows["faithful"]["p_s_MPa"] == pytest.approx(z.diagnostics["p_s_MPa"])
    assert rows["power"]["I1"] is None and rows["power"]["d"] is None
    assert (tmp_path / "compare_curves.png").stat().st_size > 1000
    assert main(["compare", *files]) == 0
    text = capsys.readouterr().out.splitlines()
    assert text[0].split()[:3] == ["calibration", "method", "|T|"] and len(text) == 4


def test_compare_calibrations_is_what_the_command_prints(cal_files, capsys):
    files = [str(cal_files[k]) for k in ("faithful", "power")]
    comparison = compare_calibrations([CalibrationResult.from_json(f) for f in files],
                                      names=["faithful", "power"])
    assert main(["-q", "compare", *files, "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["rows"] == comparison.rows
    assert main(["compare", *files]) == 0
    assert capsys.readouterr().out.strip() == comparison.table()
    assert len(comparison.plot().get_lines()) == 2  # one curve per calibration
    assert len(repr(comparison)) < 1000 and "faithful" in repr(comparison)


def test_compare_bad_input(cal_files):
    with pytest.raises(ValueError, match=r"no calibration to compare"):
        compare_calibrations([])
    cal = CalibrationResult.from_json(cal_files["power"])
    with pytest.raises(ValueError, match=r"1 names for 2 calibrations"):
        compare_calibrations([cal, cal], names=["a"])


def test_result_rebuilt_from_json_alone(cal_files):
    res = CalibrationResult.from_json(cal_files["faithful"]).method_result
    assert res.d_summary["n_vectors"] == 725_305
    assert len(res.pair_matrix) == 40
