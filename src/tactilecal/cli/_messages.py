"""The CLI's words: a library error or warning as one line, in flags rather than keywords."""

import argparse
import re
import sys

__all__ = ["BUG_REPORT", "print_warning", "error_line"]

BUG_REPORT = ("please report it with the command line and the traceback above at "
              "https://github.com/tactilecal/tactilecal/issues")
"""What the CLI asks of a user who met a bug (any error that is not bad input)."""


def print_warning(command, parser, message, category, filename, lineno, file=None, line=None):
    """Show a library warning as one line naming the command (not Python's two lines)."""
    text = _as_flags(" ".join(str(message).split()), _flags(parser))
    print(f"tactilecal {command}: warning: {text}", file=sys.stderr)


def _flags(parser):
    """Map each option's keyword (``scale_by_working``) to its flag (``--scale-by-working``).

    A switch (an option that takes no value, like ``--force``) maps to ``(flag, True)``.
    """
    flags, todo = {}, [parser]
    while todo:
        for action in todo.pop()._actions:
            if isinstance(action, argparse._SubParsersAction):
                todo.extend(action.choices.values())
            elif action.option_strings and action.option_strings[-1].startswith("--"):
                flags.setdefault(action.dest, (action.option_strings[-1], action.nargs == 0))
    return flags


def _as_flags(text, flags):
    """Say ``--max-lag 3`` where the library's message says ``max_lag=3``.

    The library names its keyword arguments; a command-line user typed flags. A switch is
    said alone: ``force=True`` is ``--force``.
    """
    def flag(match):
        name, switch_on = match.group(1), match.group(2)
        if name not in flags:
            return match.group(0)
        text, switch = flags[name]
        return text if switch and switch_on else f"{text} "

    return re.sub(r"\b([a-z][a-z0-9_]*)=(?:(True)\b|(?=\S))", flag, text)


def _one_line(exc):
    """Return the message of ``exc`` on one line; an OSError names the path the user gave."""
    if isinstance(exc, OSError) and exc.filename is not None and exc.strerror:
        text = f"{exc.filename}: {exc.strerror}"
    else:
        text = str(exc)
    return " ".join(text.split())


def error_line(exc, parser):
    """Return the one-line message of a library error, its keywords said as the user's flags."""
    return _as_flags(_one_line(exc), _flags(parser))
