"""Command-line interface: ``tactilecal COMMAND ...``.

Each command lives in its own module ``_cmd_<name>.py`` in this package and defines
``register(subparsers)``, which adds its parser and sets ``func`` (a callable taking the
parsed arguments and returning an exit code). Commands are discovered by name, so adding
a command never touches this file.

Exit codes: 0 success, 1 failure (bad input, failed fit: the message says why),
2 usage error (argparse).
"""

import argparse
import pkgutil
import sys
from importlib import import_module

from tactilecal._version import __version__

__all__ = ["main", "build_parser"]


def build_parser():
    """Return the top-level :class:`argparse.ArgumentParser` with every command."""
    parser = argparse.ArgumentParser(
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
    return parser


def main(argv=None):
    """Run the CLI; return the exit code (also used as the console-script entry point)."""
    parser = build_parser()
    args = parser.parse_args(argv)
    if args.command is None:
        parser.print_help(sys.stderr)
        return 2
    try:
        code = args.func(args)
    except (ValueError, FileNotFoundError, IsADirectoryError, KeyError, RuntimeError) as exc:
        msg = exc.args[0] if isinstance(exc, KeyError) and exc.args else exc
        print(f"tactilecal {args.command}: error: {msg}", file=sys.stderr)
        return 1
    except BrokenPipeError:  # the reader went away (`tactilecal info F | head`): stop quietly
        _silence_stdout()
        return 1
    return 0 if code is None else int(code)


def _silence_stdout():
    """Point stdout at /dev/null so the interpreter's last flush does not fail again.

    The recipe of the Python documentation (signal module, "Note on SIGPIPE").
    """
    import os

    devnull = os.open(os.devnull, os.O_WRONLY)
    os.dup2(devnull, sys.stdout.fileno())


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
