"""Helpers shared by the CLI commands: JSON output, progress bars, messages."""

import sys

from tactilecal._jsonutil import dumps


def print_json(obj):
    """Print ``obj`` as JSON on standard output (NumPy types converted)."""
    print(dumps(obj))


def progress(iterable=None, *, total=None, desc=None, quiet=False):
    """Wrap ``iterable`` in a tqdm progress bar on standard error unless ``quiet``."""
    from tqdm.auto import tqdm

    return tqdm(iterable, total=total, desc=desc, disable=quiet, file=sys.stderr,
                leave=False)


def info(args, message):
    """Print an informational message on standard error unless ``--quiet``."""
    if not getattr(args, "quiet", False):
        print(message, file=sys.stderr)
