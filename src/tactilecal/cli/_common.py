"""Helpers shared by the CLI commands: JSON and aligned output, progress bars, messages."""

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


def print_aligned(summary, *, float_format=None):
    """Print ``summary`` as aligned ``key  value`` lines, a dict value as indented lines.

    ``float_format`` (e.g. ``".6g"``) formats the float values; else they print as they are.
    """
    width = max(map(len, summary))

    def text(value):
        return format(value, float_format) if float_format and isinstance(value, float) \
            else value

    for key, value in summary.items():
        if isinstance(value, dict):
            print(f"{key}:")
            for k, v in value.items():
                print(f"  {k:<{width}}  {text(v)}")
        else:
            print(f"{key:<{width}}  {text(value)}")
