"""The progress protocol: library loops report progress through a callable they are given.

A library function that loops over many items takes ``progress=None``. When given, it is a
callable ``progress(iterable, *, total=None, desc=None)`` that returns an iterable yielding
the same items (e.g. wrapped in a progress bar); ``None`` means no bar. The library never
chooses a bar itself: the command line supplies :func:`terminal_bar`, a notebook may pass
``tqdm.auto.tqdm``, a test a recorder.

One convention for the command line, loops and dask computations alike
(:func:`terminal_bar`, :func:`dask_progress`): a tqdm bar on standard error when it is a
terminal; when it is redirected to a log, one short line per 10 % (a bar's carriage returns
would make one line of many kilobytes); nothing with ``quiet``, and nothing for work done
within ``DELAY_S``.
"""

import sys
import threading
import time
from contextlib import contextmanager

__all__ = ["no_progress", "resolve", "terminal_bar", "dask_progress", "STEP"]

#: Share of the work between two lines of a redirected progress report.
STEP = 0.1
#: Seconds before anything is shown: work that ends sooner says nothing.
DELAY_S = 1.0


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


class _Lines:
    """Progress as lines on ``stream``: one each time another ``STEP`` of the work is done."""

    def __init__(self, total, desc, stream):
        self.total, self.desc, self.stream = total, desc or "progress", stream
        self.done, self.shown, self.start = 0, 0, time.monotonic()

    def update(self, n=1):
        self.done += n
        if not self.total:
            return
        step = int(min(self.done / self.total, 1.0) / STEP + 1e-9)
        if step > self.shown and time.monotonic() - self.start >= DELAY_S:
            self.shown = step
            print(f"{self.desc}: {round(100 * step * STEP)}% ({self.done} of {self.total}, "
                  f"{time.monotonic() - self.start:.1f} s)", file=self.stream, flush=True)

    def close(self):
        if not self.total and self.done and time.monotonic() - self.start >= DELAY_S:
            print(f"{self.desc}: {self.done} done ({time.monotonic() - self.start:.1f} s)",
                  file=self.stream, flush=True)


def _reporter(total, desc, quiet):
    """Return a tqdm bar on a terminal, :class:`_Lines` on a redirected stream, or None."""
    if quiet:
        return None
    if sys.stderr.isatty():
        from tqdm.auto import tqdm

        return tqdm(total=total, desc=desc, file=sys.stderr, leave=False, delay=DELAY_S)
    return _Lines(total, desc, sys.stderr)


class _Silent:
    """A progress report that says nothing (``quiet``)."""

    def update(self, n=1):
        pass

    def close(self):
        pass


def terminal_bar(iterable=None, *, total=None, desc=None, quiet=False):
    """Yield the items of ``iterable``, reporting progress the command line's way.

    A tqdm bar on standard error when it is a terminal; one line per 10 % when it is
    redirected (``total`` or ``len(iterable)`` known); nothing when ``quiet``. Without an
    iterable, return the report itself, advanced by its ``update()`` and ended by
    ``close()``.

    Examples
    --------
    >>> list(terminal_bar(range(3), total=3, quiet=True))
    [0, 1, 2]
    """
    if total is None and hasattr(iterable, "__len__"):
        total = len(iterable)
    reporter = _reporter(total, desc, quiet)
    if iterable is None:
        return _Silent() if reporter is None else reporter
    if reporter is None:
        return iterable
    return _report(iterable, reporter)


def _report(iterable, reporter):
    try:
        for item in iterable:
            yield item
            reporter.update(1)
    finally:
        reporter.close()


@contextmanager
def dask_progress(*, desc=None, quiet=False, refresh_s=1.0):
    """Report the progress of the dask computations run inside, the command line's way.

    Counts finished tasks against the graph's tasks (as dask's own ``ProgressBar``) with
    :func:`terminal_bar`'s convention; on a terminal the bar is redrawn every ``refresh_s``
    so its elapsed time moves while one long task runs.
    """
    if quiet:
        yield
        return
    from dask.callbacks import Callback

    state = {"reporter": None, "done": 0}
    stop = threading.Event()

    def start(dsk, dask_state):  # each compute inside gets its own report
        if state["reporter"] is not None:
            state["reporter"].close()
        total = sum(len(dask_state[k]) for k in ("ready", "waiting", "running", "finished"))
        state["reporter"] = _reporter(total, desc, quiet)

    def posttask(key, result, dsk, dask_state, worker_id):
        state["reporter"].update(1)

    def refresh():
        while not stop.wait(refresh_s):
            if hasattr(state["reporter"], "refresh"):
                state["reporter"].refresh()

    ticker = threading.Thread(target=refresh, daemon=True)
    ticker.start()
    try:
        with Callback(start_state=start, posttask=posttask):
            yield
    finally:
        stop.set()
        if state["reporter"] is not None:
            state["reporter"].close()
