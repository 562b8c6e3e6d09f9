"""One saturation default for the CLI and the API (issue 12): same manifest, same numbers."""

import copy
import json
import re

import pytest

from tactilecal import calibrate
from tactilecal.calibration import load_points
from tactilecal.calibration._saturation import SATURATED_DEFAULT
from tactilecal.cli import main


@pytest.fixture(scope="module")
def saturated_session(tmp_path_factory):
    folder = tmp_path_factory.mktemp("sat")
    assert main(["-q", "simulate", "deadweight", str(folder), "--patches", "40",
                 "--saturated-share", "0.25", "--seed", "4"]) == 0
    return folder / "manifest.csv"


@pytest.fixture(scope="module")
def read_points(saturated_session):
    """The session's 40 points, read from the manifest once; each test gets its own copy."""
    points = load_points(saturated_session)
    return lambda: copy.deepcopy(points)


def _cli(manifest, *flags, capsys):
    assert main(["-q", "calibrate", str(manifest), *flags, "--json"]) == 0
    return json.loads(capsys.readouterr().out)


@pytest.mark.parametrize("method", ["power", "zvyagin"])
def test_cli_and_api_give_the_same_calibration_by_default(saturated_session, read_points, method,
                                                           capsys):
    api = calibrate(read_points(), method=method)
    cli = _cli(saturated_session, "--method", method, capsys=capsys)
    for name in ("A", "b"):
        assert cli["params"][name] == pytest.approx(api.params[name], rel=1e-12)
    saturated = [p["saturated_cells"] > 0 for p in cli["points"]]
    assert any(saturated)  # the session does hold saturated patches ...
    assert not any(p["used"] for p, s in zip(cli["points"], saturated, strict=True) if s)
    assert SATURATED_DEFAULT == "drop"  # ... and the default leaves them out, in both


@pytest.mark.parametrize("method", ["power", "zvyagin"])
def test_saturated_keep_is_the_same_option_in_cli_and_api(saturated_session, read_points, method,
                                                           capsys):
    # saturated patches kept as exact loads bend the response away from the law, and the
    # calibration says so
    with pytest.warns(UserWarning, match=rf"{method} calibration: .*(bends|misses)"):
        api = calibrate(read_points(), method=method, saturated="keep")
    cli = _cli(saturated_session, "--method", method, "--saturated", "keep", capsys=capsys)
    assert cli["params"]["b"] == pytest.approx(api.params["b"], rel=1e-12)
    dropped = calibrate(read_points(), method=method)
    assert api.params["b"] != pytest.approx(dropped.params["b"], rel=1e-6)


def test_an_unknown_saturation_treatment_is_refused(read_points):
    points = read_points()
    with pytest.raises(ValueError, match=r"saturated='censor' is not an option of every method; "
                                         r"expected one of \('drop', 'keep', 'censored'\)"):
        calibrate(points, method="zvyagin", saturated="censor")


@pytest.mark.filterwarnings("ignore:.* calibration. .*:UserWarning")  # law choice: not tested here
@pytest.mark.parametrize("method", ["power", "linear", "linear-offset", "polynomial", "lut",
                                    "piecewise", "power-2pt", "zvyagin"])
def test_every_method_takes_censored_and_counts_the_lower_bounds(read_points, method):
    points = read_points()
    n_saturated = sum(p.saturated_cells > 0 for p in points)
    cal = calibrate(points, method=method, saturated="censored")
    assert cal.options["saturated"] == "censored"
    used = cal.points[cal.points["used"]]
    if method == "zvyagin":
        assert (used["saturated_cells"] > 0).sum() == n_saturated
    else:
        assert cal.diagnostics["censored"] == n_saturated
        assert 0 <= cal.diagnostics["censored_active"] <= n_saturated
    # the saturated points are lower bounds: left out of the fit's error metrics
    assert cal.metrics["n"] == int((cal.points["used"]
                                         & (cal.points["saturated_cells"] == 0)).sum())


def test_a_two_point_law_takes_its_points_from_unsaturated_patches(read_points):
    points = read_points()
    cal = calibrate(points, method="power-2pt", saturated="censored")
    pair = cal.points[cal.points["used"]]
    assert len(pair) == 2 and (pair["saturated_cells"] == 0).all()


def test_censored_fit_needs_two_unsaturated_patches():
    import numpy as np

    from tactilecal.calibration import points_from_frames

    frames = np.zeros((4, 3, 3))
    frames[:, 1, 1] = [100, 255, 255, 255]
    with pytest.raises(ValueError, match=r"1 usable point\(s\) without a saturated sensel.*"
                                         r"saturated: frame 2, frame 3, frame 4\)"):
        calibrate(points_from_frames(frames, [1.0, 3.0, 4.0, 5.0]), method="power",
                  saturated="censored")


def test_censored_zvyagin_keeps_saturated_patches_out_of_the_pairs(read_points):
    points = read_points()
    cal = calibrate(points, method="zvyagin", saturated="censored")
    saturated = {k for k, p in enumerate(points) if p.saturated_cells > 0}
    pairs = cal.diagnostics["pairs"]  # the stored pairs: those with a root, of usable patches
    assert saturated and len(pairs["i"]) > 100
    # a lower bound cannot enter an equation (eq. 12): no stored pair holds a saturated patch
    assert not saturated & (set(pairs["i"]) | set(pairs["j"]))


@pytest.mark.parametrize(("saturated", "message"), [
    ("drop", r"no usable calibration points among 6 \(saturated: "),
    ("censored", r"0 usable point\(s\) without a saturated sensel"),
])
def test_a_session_where_every_patch_saturates_names_manifest_and_patches(
        tmp_path, capsys, saturated, message):
    folder = tmp_path / "allsat"
    assert main(["-q", "simulate", "deadweight", str(folder), "--patches", "6",
                 "--saturated-share", "1.0", "--seed", "1"]) == 0
    assert main(["-q", "calibrate", str(folder / "manifest.csv"), "--saturated",
                 saturated]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "manifest.csv: " in err[0]
    assert __import__("re").search(message, err[0])


def _empty_session(folder, *, blank_frames):
    """A simulated session whose recordings read 0 everywhere: no patch reaches the law."""
    import csv

    from tactilecal.io import read_tekscan, write_tekscan

    assert main(["-q", "simulate", "deadweight", str(folder), "--patches", "4",
                 "--seed", "1"]) == 0
    with open(folder / "manifest.csv", newline="") as table:
        rows = list(csv.DictReader(table))
    for name in {row["file"] for row in rows}:
        write_tekscan(read_tekscan(folder / name) * 0, folder / name, overwrite=True)
    if not blank_frames:  # every row names frame 1 instead of asking for the plateau
        for row in rows:
            row["frame"] = "1"
        with open(folder / "manifest.csv", "w", newline="") as out:
            writer = csv.DictWriter(out, fieldnames=list(rows[0]))
            writer.writeheader()
            writer.writerows(rows)
    return folder / "manifest.csv", [row["label"] for row in rows]


@pytest.mark.parametrize("method", ["power", "zvyagin", "lut", "piecewise", "linear"])
def test_a_session_where_no_patch_is_loaded_names_manifest_and_patches(tmp_path, capsys,
                                                                       method):
    manifest, labels = _empty_session(tmp_path / "empty", blank_frames=False)
    assert main(["-q", "calibrate", str(manifest), "--method", method]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) in (1, 2)  # zvyagin warns first that it leaves the empty frames out
    assert "manifest.csv: " in err[-1] and all(label in err[-1] for label in labels)
    assert "empty frame" in err[-1] or "no loaded sensels (raw > 0)" in err[-1]


def test_an_empty_recording_behind_a_blank_frame_names_the_manifest_line(tmp_path, capsys):
    manifest, labels = _empty_session(tmp_path / "blank", blank_frames=True)
    assert main(["-q", "calibrate", str(manifest)]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1
    assert re.search(r"manifest.csv line 2: [^:]+\.csv: every frame has a total raw reading "
                     "of 0; expected a loaded plateau", err[0])


@pytest.mark.parametrize("method", ["zvyagin", "lut", "piecewise"])
def test_every_patch_saturating_names_manifest_and_patches_for_every_method(
        tmp_path, capsys, method):
    folder = tmp_path / "allsat"
    assert main(["-q", "simulate", "deadweight", str(folder), "--patches", "5",
                 "--saturated-share", "1.0", "--seed", "1"]) == 0
    assert main(["-q", "calibrate", str(folder / "manifest.csv"), "--method", method]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "manifest.csv: " in err[0]
    # the patches, as many as fit in a message of at most 300 characters (TactilecalError)
    assert re.search(r"saturated", err[0]) and err[0].count("-00") >= 3
    assert len(err[0]) <= len("tactilecal calibrate: error: ") + 300
