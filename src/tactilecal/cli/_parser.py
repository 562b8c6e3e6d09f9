"""The argument parser of ``tactilecal``: every ``_cmd_<name>`` module adds its command."""

import argparse
import pkgutil
from importlib import import_module
from pathlib import Path

from tactilecal._errors import TactilecalError
from tactilecal._version import __version__

__all__ = ["BadFlagValue", "build_parser"]


class _Parser(argparse.ArgumentParser):
    """An ArgumentParser for which a flag's bad *value* is bad input (exit 1, one line).

    A malformed command line (unknown flag, missing argument) stays a usage error (exit 2,
    with the usage); a value refused by one of the flag types of ``_types`` (marked
    ``checks_value``) is bad input like a bad file, and exits 1 with one line naming the flag.
    """

    def defer(self, setup):
        """Add this parser's arguments with ``setup(parser)`` only when it is used.

        A command whose flags are made from the library's option classes (``calibrate``)
        would import the library to build them; deferred, ``tactilecal info`` does not pay
        for it. Several setups run in the order they were deferred.
        """
        self._deferred = [*getattr(self, "_deferred", []), setup]

    def _complete(self):
        setups, self._deferred = getattr(self, "_deferred", []), []
        for setup in setups:
            setup(self)

    def parse_known_args(self, args=None, namespace=None):
        self._complete()
        return super().parse_known_args(args, namespace)

    def format_help(self):
        self._complete()
        return super().format_help()

    def _get_value(self, action, arg_string):
        try:
            return super()._get_value(action, arg_string)
        except argparse.ArgumentError as exc:
            if getattr(action.type, "checks_value", False):
                raise BadFlagValue(f"{self.prog}: error: {exc}") from None
            raise


class BadFlagValue(TactilecalError):
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
    parser.add_argument("--debug", action="store_true",
                        help="show the traceback of every error, also of bad input")
    subparsers = parser.add_subparsers(dest="command", metavar="COMMAND")
    package = Path(__file__).parent
    for info in sorted(pkgutil.iter_modules([str(package)]), key=lambda m: m.name):
        if info.name.startswith("_cmd_"):
            import_module(f"tactilecal.cli.{info.name}").register(subparsers)
    _add_quiet(subparsers)
    return parser


def _add_quiet(subparsers):
    """Accept ``-q/--quiet`` and ``--debug`` after every (sub-)command too, not only before it."""
    for sub in subparsers.choices.values():
        nested = [a for a in sub._actions if isinstance(a, argparse._SubParsersAction)]
        if nested:
            _add_quiet(nested[0])
        else:  # SUPPRESS: absent after the command, the top-level value stands
            sub.add_argument("-q", "--quiet", action="store_true", default=argparse.SUPPRESS,
                             help="no progress bars or informational messages")
            sub.add_argument("--debug", action="store_true", default=argparse.SUPPRESS,
                             help="show the traceback of every error, also of bad input")
