"""A flag's default is the library's: the command line keeps no copy of it."""

import inspect

import pytest

from tactilecal._png import FIGURE_DPI
from tactilecal.cli._parser import build_parser


def _library(target):
    """The function (or class) whose keyword ``target`` names: ``module:attribute[.attr]``."""
    from importlib import import_module

    module, _, path = target.partition(":")
    value = import_module(module)
    for part in path.split("."):
        value = getattr(value, part)
    return value


#: (command line, destination, library function, its keyword)
FLAGS = [
    (["convert", "in.csv", "out.zarr"], "chunks", "tactilecal.io:convert", "chunks"),
    (["convert", "in.csv", "out.zarr"], "dtype", "tactilecal.io:convert", "dtype"),
    (["report", "in.csv", "--out", "r.html"], "threshold_kPa", "tactilecal.report:write_report",
     "threshold_kPa"),
    (["report", "in.csv", "--out", "r.html"], "align", "tactilecal.report:write_report",
     "align"),
    (["apply", "cal.json", "in.csv", "--out", "o.nc"], "units",
     "tactilecal.calibration:CalibrationResult.apply", "units"),
    (["simulate", "deadweight", "out"], "n_patches", "tactilecal.simulate:deadweight_session",
     "n_patches"),
    (["simulate", "deadweight", "out"], "saturated_share",
     "tactilecal.simulate:deadweight_session", "saturated_share"),
    (["simulate", "deadweight", "out"], "seed", "tactilecal.simulate:deadweight_session",
     "seed"),
    (["simulate", "deadweight", "out"], "model", "tactilecal.simulate:make_sensor", "model"),
    (["simulate", "ramp-hold", "out"], "hold_s", "tactilecal.simulate:ramp_hold", "hold_s"),
    (["simulate", "ramp-hold", "out"], "loadcell_rate_hz", "tactilecal.simulate:ramp_hold",
     "loadcell_rate_hz"),
    (["simulate", "uniform", "out"], "frames_per_level", "tactilecal.simulate:uniform_load",
     "frames_per_level"),
    (["simulate", "blind", "out"], "seed", "tactilecal.simulate:random_sine_sets", "seed"),
]


def _set_default(function, name, value, monkeypatch):
    """Change the default of ``function``'s keyword ``name`` for the test."""
    kwdefaults = function.__kwdefaults__ or {}
    if name in kwdefaults:
        monkeypatch.setitem(kwdefaults, name, value)
        return
    positional = [p.name for p in inspect.signature(function).parameters.values()
                  if p.default is not inspect.Parameter.empty
                  and p.kind is not inspect.Parameter.KEYWORD_ONLY]
    defaults = list(function.__defaults__)
    defaults[positional.index(name)] = value
    monkeypatch.setattr(function, "__defaults__", tuple(defaults))


@pytest.mark.parametrize(("argv", "dest", "target", "name"), FLAGS,
                         ids=[f"{' '.join(f[0][:2])}:{f[1]}" for f in FLAGS])
def test_a_flag_follows_the_library_default(argv, dest, target, name, monkeypatch):
    function = _library(target)
    default = inspect.signature(function).parameters[name].default
    assert vars(build_parser().parse_args(argv))[dest] == default
    moved = "elsewhere" if isinstance(default, str) else default + 1  # the library moves it
    _set_default(function, name, moved, monkeypatch)
    assert vars(build_parser().parse_args(argv))[dest] == moved


def test_figures_are_written_at_one_resolution():
    from tactilecal.analysis import TactileAccessor
    from tactilecal.calibration import CalibrationResult

    functions = [TactileAccessor.save_figures, CalibrationResult.save_figures]
    assert [inspect.signature(f).parameters["dpi"].default for f in functions] == \
        [FIGURE_DPI] * 2
    assert build_parser().parse_args(["plot", "in.json", "--out", "figs"]).dpi == FIGURE_DPI


def test_every_deferred_setup_of_a_command_runs_in_order():
    from tactilecal.cli._parser import _Parser

    parser = _Parser(prog="t")
    parser.defer(lambda p: p.add_argument("--first", default="1"))
    parser.defer(lambda p: p.add_argument("--second", default=p.get_default("first") + "2"))
    assert vars(parser.parse_args([])) == {"first": "1", "second": "12"}


@pytest.mark.parametrize(("command", "constant", "said"), [
    ("report", "CONTACT_FORCE_SHARE", "--cof-min-force-n N draw the centre-of-force path only "
     "where the total force is at least N newtons (default 7% of the peak force)"),
    ("analyze", "DEFAULT_GAP_MM", "one contact (default 7)"),
    ("plot", "DEFAULT_GAP_MM", "one contact (default 7)"),
])
def test_a_help_says_the_library_constant(command, constant, said, monkeypatch, capsys):
    """A flag whose value None lets the library decide says the library's value, moved."""
    from tactilecal import _contact

    monkeypatch.setattr(_contact, constant, 0.07 if "SHARE" in constant else 7.0)
    with pytest.raises(SystemExit):
        build_parser().parse_args([command, "--help"])
    assert said in " ".join(capsys.readouterr().out.split())
