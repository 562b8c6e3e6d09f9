"""Atomic writes of files and folders, and the rule that no writer replaces what it did not write.

Every file or folder the toolkit writes is written under a temporary name next to its
target and renamed onto it at the end (:func:`atomic_path`, :func:`atomic_folder`), so a
reader never sees a partial output and an error leaves the target as it was. Before that, a
writer calls :func:`check_target` (a file) or :func:`check_folder` (a folder of outputs): an
existing target is replaced only with ``overwrite=True`` (``--overwrite`` on the command
line), and then only if it looks like an output of that writer (:data:`OUTPUT_KINDS`,
sniffed by :func:`tactilecal._sniff.sniff`), so that a Tekscan export is never replaced by a
table, nor a folder of data by a folder of figures.
"""

import contextlib
import glob
import os
import shutil
import sys
import tempfile
import time
from pathlib import Path

from tactilecal._errors import TactilecalError
from tactilecal._sniff import is_zarr_store, sniff

__all__ = ["atomic_path", "atomic_folder", "write_text_atomic", "make_folder", "check_target",
           "check_folder", "OUTPUT_KINDS", "OUTPUT_FOLDERS", "OVERWRITE_HINT", "remove_stale",
           "dask_tasks_finished", "distributed_client", "compute_drained", "DRAIN_TIMEOUT_S"]

#: kind of output -> (what it is, the sniffed kinds an existing file of it may be).
OUTPUT_KINDS = {
    "json": ("a JSON file", ("json",)),
    "csv": ("a CSV table", ("text",)),
    "html": ("an HTML page", ("html",)),
    "netcdf": ("a NetCDF file", ("netcdf",)),
    "zarr": ("a Zarr store", ("zarr",)),
    "tekscan": ("a Tekscan export", ("tekscan",)),
    "png": ("a PNG image", ("png",)),
    "movie": ("a movie", ("movie",)),
}

#: kind of output folder -> the keyword arguments of :func:`check_folder` for it: the kinds
#: of file its writer puts there, and the file that marks it as that writer's folder.
OUTPUT_FOLDERS = {
    "figures": {"kinds": ("png",)},
    "evaluation": {"kinds": ("json", "png")},
    "session": {"kinds": ("tekscan", "csv", "json"), "marker": "truth.json"},
    "demo": {"kinds": ("json", "csv", "tekscan", "netcdf", "html", "png"),
             "marker": "summary.json"},
}

OVERWRITE_HINT = "pass overwrite=True to replace it"
"""How the library says to replace an existing output (the CLI says ``--overwrite``)."""

_FOUND = {"zarr": "a Zarr store", "folder": "a folder", "netcdf": "a NetCDF file",
          "png": "a PNG image",
          "movie": "a movie (GIF or MP4)", "tekscan": "a Tekscan export", "json": "a JSON file",
          "html": "an HTML page", "text": "a text file", "empty": "an empty file",
          "binary": "a binary file", "special": "a device, pipe or socket"}


def check_target(path, *, overwrite=False, kind, hint=OVERWRITE_HINT):
    r"""Raise unless ``path`` may be written: new, or with ``overwrite`` an output of ``kind``.

    Parameters
    ----------
    path : str or os.PathLike
        The output a writer is about to write.
    overwrite : bool, keyword-only
        Whether an existing output may be replaced.
    kind : str, keyword-only
        A key of :data:`OUTPUT_KINDS`: what the writer writes. An existing file of another
        kind (a Tekscan export where a CSV table goes) is never replaced.
    hint : str, keyword-only
        How to replace it, for the message.

    Raises
    ------
    TactilecalError
        ``path`` exists and ``overwrite`` is False, or it is not an output of ``kind``.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> export = pathlib.Path(tempfile.mkdtemp()) / "knee.csv"
    >>> _ = export.write_text("ROWS 1\nCOLS 1\nASCII_DATA @@\nFrame 1\n3\n@@\n")
    >>> check_target(export, overwrite=True, kind="csv")
    Traceback (most recent call last):
    ...
    tactilecal.TactilecalError: ...knee.csv is a Tekscan export, not a CSV table ...
    """
    found = sniff(path)
    if found is None:
        return
    what, allowed = OUTPUT_KINDS[kind]
    if not overwrite:
        raise TactilecalError(f"{path} exists; expected a new path ({hint})")
    if found not in allowed:
        raise TactilecalError(f"{path} is {_FOUND[found]}, not {what} written before; expected a "
                              "new path (it would be replaced)")


def check_folder(path, *, overwrite=False, kinds, marker=None, hint=OVERWRITE_HINT):
    """Raise unless folder ``path`` may receive outputs: new, empty, or with ``overwrite``.

    With ``overwrite`` an existing folder is written into only when every file in it
    (hidden ones left aside) is of ``kinds`` (keys of :data:`OUTPUT_KINDS`) and, when
    ``marker`` is given, the folder holds that file (the writer's own output, such as
    ``truth.json``): a folder of the user's data is not one of the writer's outputs.

    Raises
    ------
    TactilecalError
        ``path`` is a file, or holds files and ``overwrite`` is False, or holds a file that
        is not an output of the writer.
    """
    found = sniff(path)
    if found is None:
        return
    if found != "folder":
        raise TactilecalError(f"{path} is {_FOUND[found]}; expected a folder (or a new name)")
    files = [p for p in Path(path).rglob("*") if p.is_file() and not p.name.startswith(".")]
    if not files:
        return
    if not overwrite:
        raise TactilecalError(f"folder {path} holds {len(files)} files; expected a new or empty "
                              f"folder ({hint})")
    if marker is not None and not (Path(path) / marker).is_file():
        raise TactilecalError(f"folder {path} holds files but no {marker}, so they are not an "
                              "earlier output of this command; expected a new or empty folder")
    allowed = {k for kind in kinds for k in OUTPUT_KINDS[kind][1]}
    for file in files:
        if sniff(file) not in allowed:
            what = " or ".join(OUTPUT_KINDS[kind][0] for kind in kinds)
            raise TactilecalError(f"folder {path} holds {file.name}, {_FOUND[sniff(file)]}, not "
                                  f"{what} written before; expected a new or empty folder (it "
                                  "could be replaced)")


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
    """Remove the temporary files or folders a killed writer of ``path`` left; return them.

    Temporary names carry the writer's process id (``.NAME.tmpPID.XXXX``); a file whose
    process no longer runs is stale (``kill -9`` skips the clean-up of :func:`atomic_path`).
    Each removal is reported on standard error.
    """
    stale = []
    for tmp in Path(path).parent.glob(f".{glob.escape(Path(path).name)}.tmp*"):
        pid = tmp.name[len(Path(path).name) + 5:].split(".", 1)[0]
        if pid.isdigit() and not _running(int(pid)):
            with contextlib.suppress(OSError):
                if tmp.is_dir() and not tmp.is_symlink():
                    shutil.rmtree(tmp)
                else:
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


@contextlib.contextmanager
def atomic_folder(path):
    """Yield a temporary folder next to ``path``; rename it onto ``path`` on success.

    The folder analogue of :func:`atomic_path`: on any exception the temporary folder is
    removed and ``path`` is left as it was. An existing ``path`` is replaced only if it is
    a Zarr store (the writer checks, with :func:`check_target`, that it may be).
    """
    path = Path(path)
    if not path.parent.is_dir():
        raise FileNotFoundError(f"cannot write {path}: folder {path.parent} does not exist")
    if path.exists() and not is_zarr_store(path):
        raise TactilecalError(f"output {path} exists and is no Zarr store; expected a new path or "
                              "a Zarr store to replace")
    remove_stale(path)
    try:
        tmp = Path(tempfile.mkdtemp(prefix=f".{path.name}.tmp{os.getpid()}.",
                                    dir=path.parent))
    except OSError as exc:  # name the path the user gave, not the hidden temporary folder
        raise type(exc)(exc.errno, f"cannot write here ({exc.strerror})", str(path)) from None
    try:
        yield tmp
        tmp.chmod(0o777 & ~_umask())  # mkdtemp makes 0700
        if path.exists():
            old = tmp.with_name(tmp.name + ".old")
            os.replace(path, old)
            os.replace(tmp, path)
            shutil.rmtree(old, ignore_errors=True)
        else:
            os.replace(tmp, path)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise


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
