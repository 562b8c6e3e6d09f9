"""Helpers shared by the CLI commands: JSON output, progress bars, messages, flag types."""

import argparse
import math
import sys
from functools import partial

from tactilecal._jsonutil import dumps
from tactilecal._progress import terminal_bar


def print_json(obj):
    """Print ``obj`` as JSON on standard output (NumPy types converted)."""
    print(dumps(obj))


def progress(iterable=None, *, total=None, desc=None, quiet=False):
    """Wrap ``iterable`` in a tqdm progress bar on standard error unless ``quiet``.

    A bar only on a terminal (see :func:`tactilecal._progress.terminal_bar`).
    """
    return terminal_bar(iterable, total=total, desc=desc, quiet=quiet)


def progress_for(args):
    """Return the ``progress`` callable the CLI passes to library loops (off with ``-q``)."""
    return partial(terminal_bar, quiet=getattr(args, "quiet", False))


def info(args, message):
    """Print an informational message on standard error unless ``--quiet``."""
    if not getattr(args, "quiet", False):
        print(message, file=sys.stderr)


def warn_saturated(n_frames, total, source):
    """Say on standard error (also with ``--quiet``) that saturated frames are lower bounds."""
    print(f"warning: {source}: {n_frames} of {total} frames have saturated sensels; their "
          "force and pressures are lower bounds (column saturated_sensels)", file=sys.stderr)


def info_grouped(args, messages, *, show=3):
    """Print ``messages`` unless ``--quiet``, grouping those of one kind with a count.

    Messages read ``"<source>: <kind>: <detail>"``; of each kind the first ``show`` are
    printed and the rest counted ("... and 27 more 'frame blank'").
    """
    groups = {}
    for message in messages:
        kind = message.split(": ")[1] if message.count(": ") >= 2 else message
        groups.setdefault(kind, []).append(message)
    for kind, group in groups.items():
        for message in group[:show]:
            info(args, message)
        if len(group) > show:
            info(args, f"... and {len(group) - show} more {kind!r} notes")


def _number(kind, minimum, inclusive, maximum=None):
    """Return an argparse ``type`` for a finite number in range (the error names the flag)."""
    bound = f"{'>=' if inclusive else '>'} {minimum:g}"
    bound += f" and <= {maximum:g}" if maximum is not None else ""
    what = "whole number" if kind is int else "finite number"

    def convert(text):
        try:
            value = kind(text)
        except ValueError:  # "; expected": bad input (exit 1, one line), like a bad range
            raise argparse.ArgumentTypeError(f"{text!r}; expected a {what} {bound}") from None
        if not math.isfinite(value) or value < minimum or (value == minimum and not inclusive) \
                or (maximum is not None and value > maximum):
            raise argparse.ArgumentTypeError(f"{text!r}; expected a finite number {bound}")
        return value
    convert.__name__ = kind.__name__  # argparse says "invalid int value" on a bare failure
    return convert


positive_int = _number(int, 0, False)
non_negative_int = _number(int, 0, True)
positive_float = _number(float, 0.0, False)
non_negative_float = _number(float, 0.0, True)
share = _number(float, 0.0, True, 1.0)
