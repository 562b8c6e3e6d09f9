"""Command-line interface: ``tactilecal COMMAND ...``.

Each command lives in its own module ``_cmd_<name>.py`` in this package and defines
``register(subparsers)``, which adds its parser and sets ``func`` (a callable taking the
parsed arguments and returning an exit code). Commands are discovered by name, so adding
a command never touches this file.

Exit codes: 0 success, 1 failure (bad input, a bad flag value, failed fit: the message says
why, in one line), 2 usage error (argparse: unknown flag, missing argument).
"""

import argparse
import re
import sys
import warnings
from functools import partial

from tactilecal.cli._outputs import check_outputs, silence_stdout
from tactilecal.cli._parser import BadFlagValue, build_parser

__all__ = ["main", "build_parser"]


def main(argv=None):
    """Run the CLI; return the exit code (also used as the console-script entry point)."""
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except BadFlagValue as exc:
        print(exc, file=sys.stderr)
        return 1
    if args.command is None:
        parser.print_help(sys.stderr)
        return 2
    try:
        check_outputs(args)
        with warnings.catch_warnings():  # the CLI shows warnings (one line), never raises them
            warnings.simplefilter("default")
            warnings.showwarning = partial(_print_warning, args.command, parser)
            code = args.func(args)
    except BrokenPipeError:  # the reader went away (`tactilecal info F | head`): stop quietly
        silence_stdout()
        return 1
    except (ValueError, TypeError, KeyError, RuntimeError, OSError) as exc:
        print(f"tactilecal {args.command}: error: {_as_flags(_one_line(exc), _flags(parser))}",
              file=sys.stderr)
        return 1
    return 0 if code is None else int(code)


def _print_warning(command, parser, message, category, filename, lineno, file=None, line=None):
    """Show a library warning as one line naming the command (not Python's two lines)."""
    text = _as_flags(" ".join(str(message).split()), _flags(parser))
    print(f"tactilecal {command}: warning: {text}", file=sys.stderr)


def _flags(parser):
    """Map each option's keyword (``keep_saturated``) to its flag (``--keep-saturated``)."""
    flags, todo = {}, [parser]
    while todo:
        for action in todo.pop()._actions:
            if isinstance(action, argparse._SubParsersAction):
                todo.extend(action.choices.values())
            elif action.option_strings and action.option_strings[-1].startswith("--"):
                flags.setdefault(action.dest, action.option_strings[-1])
    return flags


def _as_flags(text, flags):
    """Say ``--keep-saturated True`` where the library's message says ``keep_saturated=True``.

    The library names its keyword arguments; a command-line user typed flags.
    """
    return re.sub(r"\b([a-z][a-z0-9_]*)=(?=\S)",
                  lambda m: f"{flags[m.group(1)]} " if m.group(1) in flags else m.group(0), text)


def _one_line(exc):
    """Return the message of ``exc`` on one line; an OSError names the path the user gave."""
    if isinstance(exc, KeyError) and exc.args:
        text = str(exc.args[0])
    elif isinstance(exc, OSError) and exc.filename is not None and exc.strerror:
        text = f"{exc.filename}: {exc.strerror}"
    else:
        text = str(exc)
    return " ".join(text.split())


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
