"""Command-line interface: ``tactilecal COMMAND ...``.

Each command lives in its own module ``_cmd_<name>.py`` in this package and defines
``register(subparsers)``, which adds its parser and sets ``func`` (a callable taking the
parsed arguments and returning an exit code). Commands are discovered by name, so adding
a command never touches this file.

Exit codes: 0 success, 1 failure (bad input, a bad flag value, failed fit: the message says
why, in one line), 2 usage error (argparse: unknown flag, missing argument).
"""

import argparse
import pkgutil
import sys
import warnings
from functools import partial
from importlib import import_module
from pathlib import Path

from tactilecal._version import __version__

__all__ = ["main", "build_parser"]


class _Parser(argparse.ArgumentParser):
    """An ArgumentParser for which a flag's bad *value* is bad input (exit 1, one line).

    A malformed command line (unknown flag, missing argument) stays a usage error (exit 2,
    with the usage); a value refused by the flag types of ``_common`` ("...; expected ...")
    is bad input like a bad file, and exits 1 with one line naming the flag.
    """

    def error(self, message):
        if "; expected" in message:
            raise _BadFlagValue(f"{self.prog}: error: {message}")
        super().error(message)


class _BadFlagValue(ValueError):
    """A flag value refused while parsing; ``main`` prints it and returns 1."""


def build_parser():
    """Return the top-level :class:`argparse.ArgumentParser` with every command."""
    parser = _Parser(
        prog="tactilecal",
        description="Calibrate and analyse matrix tactile pressure sensors.",
    )
    parser.add_argument("--version", action="version", version=f"tactilecal {__version__}")
    parser.add_argument("-q", "--quiet", action="store_true",
                        help="no progress bars or informational messages")
    subparsers = parser.add_subparsers(dest="command", metavar="COMMAND")
    for info in sorted(pkgutil.iter_modules(__path__), key=lambda m: m.name):
        if info.name.startswith("_cmd_"):
            import_module(f"{__name__}.{info.name}").register(subparsers)
    _add_quiet(subparsers)
    return parser


def _add_quiet(subparsers):
    """Accept ``-q/--quiet`` after every (sub-)command too, not only before it."""
    for sub in subparsers.choices.values():
        nested = [a for a in sub._actions if isinstance(a, argparse._SubParsersAction)]
        if nested:
            _add_quiet(nested[0])
        else:  # SUPPRESS: absent after the command, the top-level value stands
            sub.add_argument("-q", "--quiet", action="store_true", default=argparse.SUPPRESS,
                             help="no progress bars or informational messages")


def main(argv=None):
    """Run the CLI; return the exit code (also used as the console-script entry point)."""
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except _BadFlagValue as exc:
        print(exc, file=sys.stderr)
        return 1
    if args.command is None:
        parser.print_help(sys.stderr)
        return 2
    try:
        check_outputs(args)
        with warnings.catch_warnings():  # the CLI shows warnings (one line), never raises them
            warnings.simplefilter("default")
            warnings.showwarning = partial(_print_warning, args.command)
            code = args.func(args)
    except BrokenPipeError:  # the reader went away (`tactilecal info F | head`): stop quietly
        _silence_stdout()
        return 1
    except (ValueError, TypeError, KeyError, RuntimeError, OSError) as exc:
        print(f"tactilecal {args.command}: error: {_one_line(exc)}", file=sys.stderr)
        return 1
    return 0 if code is None else int(code)


def _print_warning(command, message, category, filename, lineno, file=None, line=None):
    """Show a library warning as one line naming the command (not Python's two lines)."""
    print(f"tactilecal {command}: warning: {' '.join(str(message).split())}", file=sys.stderr)


def _one_line(exc):
    """Return the message of ``exc`` on one line; an OSError names the path the user gave."""
    if isinstance(exc, KeyError) and exc.args:
        text = str(exc.args[0])
    elif isinstance(exc, OSError) and exc.filename is not None and exc.strerror:
        text = f"{exc.filename}: {exc.strerror}"
    else:
        text = str(exc)
    return " ".join(text.split())


def check_outputs(args):
    """Refuse an output path that is one of the command's inputs (it would be replaced).

    Every string (or list of strings) among the parsed arguments that names an existing
    file counts as an input; the outputs are ``--out`` and ``OUTDIR``.
    """
    outputs = [getattr(args, key, None) for key in ("out", "outdir")]
    for out in filter(None, outputs):
        out_path = Path(out)
        if not out_path.exists():
            continue
        for key, value in vars(args).items():
            if key in ("out", "outdir"):
                continue
            for item in value if isinstance(value, list) else [value]:
                if isinstance(item, str) and Path(item).is_file() and \
                        out_path.resolve() == Path(item).resolve():
                    raise ValueError(f"--out {out} is the input {item}; expected a new path "
                                     "(the input would be replaced)")


def _silence_stdout():
    """Point stdout at /dev/null so the interpreter's last flush does not fail again.

    The recipe of the Python documentation (signal module, "Note on SIGPIPE").
    """
    import os

    devnull = os.open(os.devnull, os.O_WRONLY)
    os.dup2(devnull, sys.stdout.fileno())


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
