"""The CLI's error policy: bad input is one line, a bug is a traceback and a request.

Bad input is a :class:`tactilecal.TactilecalError` (a ValueError) or an OSError; the exit
code depends on the exception's type, never on the wording of its message.
"""

import subprocess
import sys

import pytest

import tactilecal
from tactilecal import TactilecalError, TactilecalTypeError
from tactilecal.cli import main


def test_the_error_types_are_value_and_type_errors():
    assert issubclass(TactilecalError, ValueError)
    assert issubclass(TactilecalTypeError, TactilecalError)
    assert issubclass(TactilecalTypeError, TypeError)
    assert "TactilecalError" in tactilecal.__all__


def test_bad_input_is_one_line_and_exit_1(tmp_path, capsys):
    bad = tmp_path / "cal.json"
    bad.write_text('{"format": "tactilecal-calibration/1"}')
    assert main(["info", str(bad)]) == 1
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "Traceback" not in err, err
    assert err.startswith("tactilecal info: error: ") and "cal.json" in err


def test_debug_shows_the_traceback_of_bad_input(tmp_path, capsys):
    bad = tmp_path / "cal.json"
    bad.write_text('{"format": "tactilecal-calibration/1"}')
    assert main(["--debug", "info", str(bad)]) == 1
    err = capsys.readouterr().err
    assert "Traceback (most recent call last)" in err and "TactilecalError" in err
    assert err.strip().splitlines()[-1].startswith("tactilecal info: error: ")
    assert main(["info", str(bad), "--debug"]) == 1  # after the command too
    assert "Traceback" in capsys.readouterr().err


@pytest.mark.parametrize("exc", [KeyError("sensor_type"), TypeError("bad operand"),
                                 RuntimeError("boom"), ValueError("not our message")])
def test_a_bug_is_a_traceback_and_a_request_to_report_it(monkeypatch, tmp_path, capsys, exc):
    """A KeyError inside the library is not 'bad input': it is shown as what it is."""
    from tactilecal.cli import _cmd_info

    def broken(args):
        raise exc
    monkeypatch.setattr(_cmd_info, "run", broken)
    assert main(["info", str(tmp_path / "x.csv")]) == 1
    err = capsys.readouterr().err
    assert "Traceback (most recent call last)" in err and type(exc).__name__ in err
    assert "internal error (a bug in tactilecal, not in your input)" in err
    assert "please report it" in err


def test_a_flag_value_is_judged_by_its_type_not_its_wording(capsys):
    # a refused value of a checked flag type: bad input, exit 1, one line
    assert main(["simulate", "deadweight", "out", "--patches", "0"]) == 1
    assert capsys.readouterr().err.strip() == ("tactilecal simulate deadweight: error: argument "
                                               "--patches: '0'; expected a finite number > 0")
    # an unknown flag or a bad choice: a usage error, exit 2
    with pytest.raises(SystemExit) as stop:
        main(["simulate", "deadweight", "out", "--no-such-flag"])
    assert stop.value.code == 2


def test_the_console_script_prints_no_traceback_for_bad_input(tmp_path):
    bad = tmp_path / "m.csv"
    bad.write_text("file,frame\n")
    run = subprocess.run([sys.executable, "-m", "tactilecal", "calibrate", str(bad)],
                         capture_output=True, text=True)
    assert run.returncode == 1
    assert "Traceback" not in run.stderr and "m.csv" in run.stderr, run.stderr


def test_the_command_returns_mains_code_and_leaves_its_objects_to_the_exit(tmp_path,
                                                                          monkeypatch, capsys):
    """The console script (and ``python -m tactilecal``) exits with :func:`main`'s code,
    after freezing the garbage collector: the interpreter's exit then skips its objects."""
    from tactilecal import cli

    frozen = []
    monkeypatch.setattr(cli.gc, "freeze", lambda: frozen.append(True))
    monkeypatch.setattr(sys, "argv", ["tactilecal", "info", str(tmp_path / "missing.csv")])
    assert cli.console_main() == 1 and frozen == [True]
    assert "missing.csv" in capsys.readouterr().err
    monkeypatch.setattr(sys, "argv", ["tactilecal", "--help"])
    with pytest.raises(SystemExit) as done:  # argparse's own exit: nothing to freeze after
        cli.console_main()
    assert done.value.code == 0 and frozen == [True]


def test_building_the_parser_imports_no_library_subpackage():
    """``tactilecal info`` must not pay for the calibration's option classes."""
    code = ("import sys; from tactilecal.cli import build_parser; build_parser(); "
            "print(sorted(m for m in sys.modules if m.split('.')[0] in "
            "('pandas', 'xarray', 'scipy') or m.startswith('tactilecal.calibration')))")
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True)
    assert run.stdout.strip() == "[]"
