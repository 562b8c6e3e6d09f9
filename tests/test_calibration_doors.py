"""One owner per decision: every door to a static fit gives the same calibration.

The doors are :func:`tactilecal.calibrate` on points, on the manifest's path, the command
line, and the method module's own ``fit`` on the points ``calibrate`` used. The session has
saturated patches (where the doors used to differ: Zvyagin kept them, the rest dropped
them), and the defaults of the command line are those of the option dataclasses.
"""

import dataclasses
import json
import warnings

import numpy as np
import pytest

import tactilecal as tc
from tactilecal.calibration import (
    DEFAULT_METHOD,
    METHOD_OPTIONS,
    METHODS,
    CommonOptions,
    load_points,
)
from tactilecal.calibration._fit import FitData
from tactilecal.calibration._points import points_to_arrays
from tactilecal.calibration.methods import MODULES
from tactilecal.cli import build_parser, main
from tactilecal.cli._calibrate_options import fit_options
from tactilecal.simulate import family_sessions

RTOL = 1e-12


@pytest.fixture(scope="module")
def saturated(tmp_path_factory):
    """The family's saturating member: 18 of 45 patches with a sensel at 255."""
    train, _ = family_sessions("5051-saturating", seed=0)
    manifest = train.write(tmp_path_factory.mktemp("saturated"))
    points = load_points(manifest)
    assert 10 <= sum(p.saturated_cells > 0 for p in points) < len(points) - 10
    return manifest, points


def _same(a, b):
    assert set(a) == set(b)
    for key in a:
        np.testing.assert_allclose(np.ravel(a[key]), np.ravel(b[key]), rtol=RTOL, err_msg=key)


@pytest.mark.parametrize("method", METHODS)
def test_every_door_gives_the_same_calibration(saturated, method, tmp_path, capsys):
    manifest, points = saturated
    with warnings.catch_warnings():  # a law that does not fit says so: not the point here
        warnings.filterwarnings("ignore", message=".* calibration: ")
        by_points = tc.calibrate(points, method=method)
        by_path = tc.calibrate(manifest, method=method)
    out = tmp_path / "cal.json"
    assert main(["-q", "calibrate", str(manifest), "--method", method, "--out", str(out)]) == 0
    capsys.readouterr()
    by_cli = tc.load(out)
    _same(by_points.params, by_path.params)
    _same(by_points.params, by_cli.params)
    assert by_points.options == by_path.options == by_cli.options
    used = by_points.points["used"].to_numpy()
    assert not used[[p.saturated_cells > 0 for p in points]].any()  # one saturation rule
    hist, load = points_to_arrays(points)
    usable = np.array([p.saturated_cells == 0 for p in points])
    chosen = by_points.method  # auto: the method it chose, with its options
    module = MODULES[chosen]
    options = module.Options(**{k: v for k, v in by_points.options.items()
                                if k in module.Options.names()})
    direct = module.fit(FitData(hist[usable], load[usable],
                                sensel_area_mm2=points[0].sensel_area_mm2,
                                labels=tuple(by_points.points["file"][usable].astype(str)
                                             + "#8")), options)
    _same(by_points.params, direct.params)
    # and the sensel area is the points' for every method: Zvyagin's p_s included
    assert by_points.sensel_area_mm2 == pytest.approx(points[0].sensel_area_mm2)
    if method == "zvyagin":
        assert by_points.method_result.p_s_kPa == pytest.approx(
            by_points.saturation_pressure_kPa, rel=1e-12)


def test_the_command_line_defaults_are_the_option_classes():
    """No flag given: no option passed, so the library's defaults apply; help shows them."""
    parser = build_parser()
    for method in METHODS:
        args = parser.parse_args(["calibrate", "m.csv", "--method", method])
        assert fit_options(args) == {}
    assert parser.parse_args(["calibrate", "m.csv"]).method == DEFAULT_METHOD
    help_text = parser._subparsers._group_actions[0].choices["calibrate"].format_help()
    flat = " ".join(help_text.split())
    for f in dataclasses.fields(CommonOptions):
        flag = (f.metadata.get("flag") or (f"--{f.name.replace('_', '-')}",))[0]
        assert flag in flat
    assert "(default drop)" in flat and "power: l1" in flat and "polynomial: l2" in flat
    for options in METHOD_OPTIONS.values():
        for f in dataclasses.fields(options):
            assert f"--{f.name.replace('_', '-')}" in flat


def test_every_option_the_cli_passes_reaches_the_result(saturated, tmp_path, capsys):
    manifest, points = saturated
    out = tmp_path / "cal.json"
    assert main(["-q", "calibrate", str(manifest), "--method", "lut", "--objective", "l2",
                 "--smoothing", "0.5", "--knots", "0,8,64,255", "--out", str(out)]) == 0
    capsys.readouterr()
    stored = json.loads(out.read_text())["options"]
    api = tc.calibrate(points, method="lut", objective="l2", smoothing=0.5,
                       knots=(0, 8, 64, 255))
    assert stored == api.options
    assert stored["knots"] == [0, 8, 64, 255] and stored["saturated"] == "drop"


def test_an_option_no_method_takes_is_refused_naming_the_accepted_ones(saturated):
    _, points = saturated
    with pytest.raises(TypeError, match=r"method='power' does not take the option\(s\) "
                                        r"\['smoothing'\]; expected some of \['objective', "
                                        r"'b_bounds', 'saturated'"):
        tc.calibrate(points, method="power", smoothing=1.0)
