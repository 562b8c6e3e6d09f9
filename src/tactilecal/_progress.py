"""The progress protocol: library loops report progress through a callable they are given.

A library function that loops over many items takes ``progress=None``. When given, it is a
callable ``progress(iterable, *, total=None, desc=None)`` that returns an iterable yielding
the same items (e.g. wrapped in a progress bar); ``None`` means no bar. The library never
chooses a bar itself: the command line supplies :func:`terminal_bar` (tqdm on standard error,
shown only on a terminal), a notebook may pass ``tqdm.auto.tqdm``, a test a recorder.
"""

import sys

__all__ = ["no_progress", "resolve", "terminal_bar"]


def no_progress(iterable, *, total=None, desc=None):
    """Return ``iterable`` unchanged: the ``progress=None`` of the protocol.

    Examples
    --------
    >>> list(no_progress(range(3), total=3, desc="counting"))
    [0, 1, 2]
    """
    return iterable


def resolve(progress):
    """Return ``progress``, or :func:`no_progress` for ``None``.

    Raises
    ------
    TypeError
        ``progress`` is neither None nor callable.
    """
    if progress is None:
        return no_progress
    if not callable(progress):
        raise TypeError(f"progress of type {type(progress).__name__}; expected None or a "
                        "callable progress(iterable, total=, desc=)")
    return progress


def terminal_bar(iterable=None, *, total=None, desc=None, quiet=False):
    """Wrap ``iterable`` in a tqdm bar on standard error, only on a terminal and unless quiet.

    Redirected to a log, tqdm's carriage returns are noise, so the bar is then disabled (the
    items pass through unchanged).
    """
    from tqdm.auto import tqdm

    return tqdm(iterable, total=total, desc=desc, disable=quiet or not sys.stderr.isatty(),
                file=sys.stderr, leave=False)

