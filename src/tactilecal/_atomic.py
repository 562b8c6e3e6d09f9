"""Atomic file writes: write to a temporary name in the target folder, then rename."""

import contextlib
import glob
import os
import sys
import tempfile
import time
from pathlib import Path

from tactilecal._errors import TactilecalError


@contextlib.contextmanager
def atomic_path(path, *, suffix=None):
    """Yield a temporary path next to ``path``; rename it onto ``path`` on success.

    On any exception the temporary file is removed and ``path`` is left untouched,
    so a reader never sees a partly written output file.

    Parameters
    ----------
    path : str or os.PathLike
        Final destination.
    suffix : str, optional
        Suffix of the temporary file (default: the suffix of ``path``), which
        matters for writers that choose a format from the extension.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> out = pathlib.Path(tempfile.mkdtemp()) / "a.txt"
    >>> with atomic_path(out) as tmp:
    ...     _ = tmp.write_text("hello")
    >>> out.read_text()
    'hello'
    """
    path = Path(path)
    if not path.parent.exists():
        raise FileNotFoundError(f"cannot write {path}: folder {path.parent} does not exist")
    remove_stale(path)
    try:
        fd, tmp_name = tempfile.mkstemp(
            prefix=f".{path.name}.tmp{os.getpid()}.",
            suffix=path.suffix if suffix is None else suffix, dir=path.parent,
        )
    except OSError as exc:  # name the path the user gave, not the hidden temporary file
        raise type(exc)(exc.errno, f"cannot write here ({exc.strerror})", str(path)) from None
    os.close(fd)
    tmp = Path(tmp_name)
    try:
        yield tmp
        tmp.chmod(0o666 & ~_umask())  # mkstemp makes 0600; give the file the usual mode
        try:
            os.replace(tmp, path)
        except OSError as exc:
            raise type(exc)(exc.errno, f"cannot replace it ({exc.strerror})", str(path)) \
                from None
    except BaseException:
        with contextlib.suppress(FileNotFoundError):
            tmp.unlink()
        raise


@contextlib.contextmanager
def dask_tasks_finished():
    """Run dask's local computations inside the block on a pool drained before it exits.

    When a task fails, dask's threaded scheduler raises at once while the tasks already
    running go on: a writer's clean-up (removing its temporary output) would run before
    them, and they would write into, or create again, what it removed. Here the block's
    computations run on a thread pool whose shutdown waits for the running tasks, so an
    exception leaves the block only after them. A distributed client or a scheduler the
    caller chose is left as it is.
    """
    import dask
    import dask.threaded
    from dask.base import get_scheduler

    if get_scheduler() not in (None, dask.threaded.get):
        yield
        return
    from concurrent.futures import ThreadPoolExecutor

    with ThreadPoolExecutor(max_workers=os.cpu_count() or 1) as pool, \
            dask.config.set(scheduler=pool):
        yield


#: Seconds to wait, after a failure on a distributed client, for the tasks still running.
DRAIN_TIMEOUT_S = 120.0
#: Worker task states of a task that runs or may still start (:mod:`distributed`'s
#: worker state machine); ``memory``, ``error`` and ``released`` ones do not write.
_LIVE_STATES = frozenset({"waiting", "ready", "constrained", "executing", "long-running",
                          "cancelled", "resumed", "fetch", "flight"})


def distributed_client():
    """Return the :mod:`dask.distributed` client dask computes on now, or None."""
    from dask.base import get_scheduler

    owner = getattr(get_scheduler(), "__self__", None)
    return owner if type(owner).__module__.startswith("distributed") else None


def compute_drained(client, delayed, *, timeout_s=DRAIN_TIMEOUT_S):
    """Compute ``delayed`` on a distributed ``client``; on failure, raise after its tasks.

    The counterpart of :func:`dask_tasks_finished` for :mod:`dask.distributed`: a running
    task cannot be interrupted, so on an exception the computation is cancelled and the
    workers are polled until none of its tasks (the future's dependencies, as the
    scheduler names them after fusion) runs or waits to run, at most ``timeout_s``
    seconds. A writer's clean-up after that finds no task writing into its temporary
    output any more.
    """
    future = client.compute(delayed)
    try:
        return future.result()
    except BaseException:
        keys = client.run_on_scheduler(_task_keys, key=future.key)
        client.cancel(future)
        deadline = time.monotonic() + timeout_s
        while time.monotonic() < deadline and any(
                client.run(_live_tasks, keys=keys).values()):
            time.sleep(0.02)
        raise


def _task_keys(dask_scheduler, key):
    """Keys of task ``key`` and everything it depends on (run on the scheduler)."""
    stack, seen = [dask_scheduler.tasks.get(key)], set()
    while stack:
        ts = stack.pop()
        if ts is not None and ts.key not in seen:
            seen.add(ts.key)
            stack.extend(ts.dependencies)
    return seen


def _live_tasks(dask_worker, keys):
    """How many of ``keys`` run or may still start on this worker (run on each worker)."""
    tasks = dask_worker.state.tasks
    return sum(1 for key in keys if key in tasks and tasks[key].state in _LIVE_STATES)


def remove_stale(path):
    """Remove the temporary files a killed writer of ``path`` left behind; return them.

    Temporary names carry the writer's process id (``.NAME.tmpPID.XXXX``); a file whose
    process no longer runs is stale (``kill -9`` skips the clean-up of :func:`atomic_path`).
    Each removal is reported on standard error.
    """
    stale = []
    for tmp in Path(path).parent.glob(f".{glob.escape(Path(path).name)}.tmp*"):
        pid = tmp.name[len(Path(path).name) + 5:].split(".", 1)[0]
        if pid.isdigit() and not _running(int(pid)):
            with contextlib.suppress(OSError):
                tmp.unlink()
                stale.append(tmp)
                print(f"removed {tmp}, left by an interrupted write of {path}",
                      file=sys.stderr)
    return stale


def _running(pid):
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # another user's process
        return True
    return True


def make_folder(path, *, what="output folder"):
    """Create folder ``path`` (and its parents) unless it exists; a file there is an error.

    Returns the folder as a :class:`pathlib.Path`.
    """
    path = Path(path)
    if path.exists() and not path.is_dir():
        raise TactilecalError(f"{what} {path} is a file; expected a folder (or a new name)")
    path.mkdir(parents=True, exist_ok=True)
    return path


def _umask():
    mask = os.umask(0)
    os.umask(mask)
    return mask


def write_text_atomic(path, text):
    """Write ``text`` to ``path`` atomically (UTF-8)."""
    with atomic_path(path) as tmp:
        tmp.write_text(text, encoding="utf-8")
