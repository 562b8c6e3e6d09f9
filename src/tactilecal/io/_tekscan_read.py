"""Reader for Tekscan I-Scan / F-Scan ASCII exports (``.csv``, ``.asf``, any extension).

Layout, as written by Tekscan I-Scan 6.10I and F-Scan 6.33 (the two real exports in
``shared/realdata``, see its README)::

    KEY value                 header lines (ROWS, COLS, UNITS, ...)
    ASCII_DATA @@
    Frame 1, 0,, 12/2/2019 6:21:52.34PM,,,Raw Sum=,,310     (I-Scan; F-Scan: "Frame 1")
    B,B,5,0,...               ROWS lines of COLS comma-separated values, B = no sensel
    ...
    @@

An export in the plain form every real export seen has (numbers without exponent or spaces,
and ``B``), read eagerly, is read in one pass by NumPy alone (``_tekscan_numpy``), without
importing numba
(:data:`PLAIN_MAX_BYTES` can bound its size). Any other file and every lazy read go to the
numba reader, which defines the checks and the messages (the NumPy reader hands over at the
first departure, raising nothing): the file is read twice, in blocks, by numba kernels over
its bytes (``_tekscan_kernels``): once to index the frames and check the structure
(``_tekscan_index``), once to parse the values of whole frames straight into the result
(``_tekscan_blocks``). Memory is the result plus a few blocks of bytes; with ``chunks`` the
second pass is left to dask, block by block.
"""

import os

import numpy as np
import xarray as xr

from tactilecal._errors import TactilecalError
from tactilecal._validate import TextFault, check_size, shorten
from tactilecal.io._header import integer

__all__ = ["read_tekscan"]

PLAIN_MAX_BYTES = None
"""Largest data block (bytes after ``ASCII_DATA @@``) the NumPy reader tries; None: any.

From a cold start the NumPy reader was faster than numba's (its import and the load of its
cached kernels) at every size measured, to 40,000 frames of 44 x 44
(``benchmarks/bench_cold_read.py``).
"""


def read_tekscan(path, *, chunks=None):
    r"""Read a Tekscan I-Scan or F-Scan ASCII export into a DataArray.

    Parameters
    ----------
    path : str or os.PathLike
        The export (movie or single frame, LF or CRLF line endings, any extension), in
        ASCII, UTF-8 (with or without byte-order mark), Windows cp1252 or UTF-16 with its
        byte-order mark.
    chunks : int, optional
        Frames per block of a lazy, dask-backed result: the file is indexed (every check
        that needs no value is done) and each block parses its own byte range when
        computed, so a recording larger than memory can be streamed (e.g. to Zarr with
        :func:`tactilecal.io.convert`). Default: read everything now into NumPy. (A UTF-16
        export is converted to UTF-8 in a temporary file and read into memory first.)

    Returns
    -------
    xarray.DataArray
        float64, dims ``("frame", "row", "col")``, NaN where the file has ``B``; coords
        ``frame`` (the file's frame numbers), ``time`` (s: the frame line's time where it
        carries one, else frame index x ``SECONDS_PER_FRAME``), ``row``, ``col``; attributes
        as in ``docs/data-model.md`` (all ``str``/``int``/``float``, so ``to_netcdf`` works).
        Values are correctly rounded (``float(token)``).

    Raises
    ------
    ValueError
        A path that is no regular file (a folder, device or pipe), an empty file, missing
        ``ASCII_DATA @@``, ``ROWS`` or ``COLS``, a frame with the wrong
        number of rows, a row with the wrong number of values, a non-numeric value, a
        ``Raw Sum`` in a frame line that is not a number or differs from the frame's sum
        (raw files), frames not numbered one by one or disagreeing with ``START_FRAME`` /
        ``END_FRAME``, frame times on some frame lines only, or not finite, negative or not
        increasing, an unknown unit or one that is no pressure or force (``UNITS mm``), a NUL
        byte, a byte that is no text, a carriage return inside a line, no ``@@``
        terminator. Messages name the file and line. With ``chunks``, faults
        in the values (not a number, not a raw reading, ``Raw Sum``) raise when the block
        holding them is computed.
    TypeError
        ``chunks`` is not an integer.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> f = pathlib.Path(tempfile.mkdtemp()) / "tiny.csv"
    >>> _ = f.write_text("ROWS 2\nCOLS 3\nUNITS raw\nSECONDS_PER_FRAME 0.5\n"
    ...                  "ASCII_DATA @@\n\nFrame 1\n0,5,B\n1,2,3\n\nFrame 2\n"
    ...                  "4,0,B\n0,0,7\n@@\n")
    >>> data = read_tekscan(f)
    >>> data.dims, data.shape, data.time.values.tolist()
    (('frame', 'row', 'col'), (2, 2, 3), [0.0, 0.5])
    >>> data.sel(frame=2).values.tolist()
    [[4.0, 0.0, nan], [0.0, 0.0, 7.0]]
    >>> lazy = read_tekscan(f, chunks=1)
    >>> lazy.chunks[0], bool(lazy.equals(data))
    ((1, 1), True)
    """
    from pathlib import Path

    name = str(path)
    chunks = _check_chunks(chunks)
    if os.path.exists(path) and not os.path.isfile(path):  # a FIFO would block the read
        raise TextFault.not_a_file(name, "a Tekscan ASCII export")
    with open(Path(path), "rb") as f:
        utf16 = f.read(2) in UTF16_BOMS
    if utf16:
        return _read_utf16(Path(path), name, chunks)
    return _read(Path(path), name, chunks)


UTF16_BOMS = (b"\xff\xfe", b"\xfe\xff")
_TRANSCODE_BYTES = 2**24


def _read_utf16(path, name, chunks):
    """Read a UTF-16 export: transcoded to UTF-8 in a temporary file (lines kept), eagerly."""
    import codecs
    import tempfile

    decoder = codecs.getincrementaldecoder("utf-16")()
    with tempfile.TemporaryDirectory(prefix="tactilecal-utf16-") as folder:
        tmp = os.path.join(folder, "export.txt")
        lines = 1
        with open(path, "rb") as src, open(tmp, "wb") as out:
            while True:
                chunk = src.read(_TRANSCODE_BYTES)
                try:
                    text = decoder.decode(chunk, final=not chunk)
                except UnicodeDecodeError:
                    raise TactilecalError(f"line {lines} of {name} or the next: bytes that are "
                                          "not UTF-16 after its byte-order mark; expected a "
                                          "Tekscan ASCII export") from None
                lines += text.count("\n")
                out.write(text.encode("utf-8"))
                if not chunk:
                    break
        data = _read(tmp, name, None)
    return data if chunks is None else data.chunk({"frame": chunks})


def _read(path, name, chunks):
    """Read the (ASCII-compatible) export at ``path``; messages name it ``name``."""
    from pathlib import Path

    from tactilecal.io._tekscan_layout import check_line_lengths, read_header

    with open(path, "rb") as f:
        head = read_header(f, name)
        check_line_lengths(f, head, name)  # before numba, and before a line is held whole
        size = os.fstat(f.fileno()).st_size - head.body
        if chunks is None and (PLAIN_MAX_BYTES is None or size <= PLAIN_MAX_BYTES):
            # a plain export is read by NumPy alone, without numba's start-up
            from tactilecal.io._tekscan_numpy import read_plain

            plain = read_plain(f, name, head)
            if plain is not None:
                values, index = plain
                _check_frames(index.numbers, index.times, index.lines, index.header, name)
                return _recording(values, index)
        # numba is imported with the kernels, on the first read that needs them
        from tactilecal.io._tekscan_blocks import check_block_sums, check_stray_f, raise_range
        from tactilecal.io._tekscan_index import index_export

        index = index_export(f, name, whole=chunks is None, header=head)
        check_stray_f(f, index)
        if chunks is not None:
            check_size(min(chunks, len(index.numbers)) * index.rows * index.cols,
                       f"{name}: a block of {chunks} frames (chunks)")
            _check_frames(index.numbers, index.times, index.lines, index.header, name)
            # absolute: a task may run in another working directory (a dask worker)
            return _recording(_lazy_values(Path(path).absolute(), index, chunks), index)
        values = np.empty((len(index.numbers), index.rows, index.cols))
    sums, bad = _parse_all(Path(path), index, values)
    if bad is not None:
        raise_range(*bad)
    _check_frames(index.numbers, index.times, index.lines, index.header, name)
    for block, part in sums:
        check_block_sums(block, part)
    return _recording(values, index)


def _check_chunks(chunks):
    if chunks is None:
        return None
    if isinstance(chunks, bool) or not isinstance(chunks, int | np.integer):
        raise TypeError(f"chunks is {chunks!r}; expected a whole number of frames per block")
    if chunks < 1:
        raise TactilecalError(f"chunks is {chunks}; expected at least 1 frame per block")
    return int(chunks)


def _parse_all(path, index, values):
    """Parse every frame into ``values``, in blocks of about ``BLOCK_BYTES`` of the file.

    The blocks are parsed on a pool of one thread per core (the kernels release the GIL),
    each straight into its slice of ``values``; faults are then raised in file order, as a
    one-thread read would find them. Returns ``(block, frame sums)`` per block and the first
    value that is no raw reading (or None). A plain thread pool, not ``dask.compute``: with
    a string scheduler dask imports ``distributed`` when it is installed, to look for a
    client (0.6-1.2 s in a new process here, more than the whole read of 10,000 frames).
    """
    import os
    from concurrent.futures import ThreadPoolExecutor

    from tactilecal.io import _tekscan_index
    from tactilecal.io._tekscan_blocks import blocks, parse_into

    parts = blocks(index, max_bytes=_tekscan_index.BLOCK_BYTES)
    with ThreadPoolExecutor(max_workers=min(os.cpu_count() or 1, len(parts)) or 1) as pool:
        results = list(pool.map(
            lambda block: parse_into(str(path), block,
                                     values[block.k0:block.k0 + block.n_frames]), parts))
    for _, _, error in results:
        if error is not None:
            raise error
    bad = next(((found, block) for block, (_, found, _) in zip(parts, results, strict=True)
                if found is not None), None)
    return [(block, part) for block, (part, _, _) in zip(parts, results, strict=True)], bad


def _lazy_values(path, index, chunks):
    """Return a dask array over blocks of ``chunks`` frames; each block parses its byte range."""
    import dask
    import dask.array as da

    from tactilecal.io._tekscan_blocks import blocks, read_block

    parts = []
    for block in blocks(index, chunks):
        task = dask.delayed(read_block, pure=True)(str(path), block,
                                                    dask_key_name=_key(index, block))
        parts.append(da.from_delayed(task, shape=(block.n_frames, index.rows, index.cols),
                                     dtype=np.float64, meta=np.empty((0, 0, 0))))
    return da.concatenate(parts, axis=0) if parts else da.empty((0, index.rows, index.cols))


def _key(index, block):
    from dask.base import tokenize

    return f"read_tekscan-{tokenize(index.name, index.stat, block.k0, block.n_frames)}"


def _recording(values, index):
    """Return the DataArray of ``values`` with the coordinates and attributes of ``index``."""
    attrs = dict(index.attrs)
    if "units" not in attrs:  # the values are (or, lazily, will be) checked as raw readings
        attrs["units"] = "raw"
        attrs["units_note"] = ("no UNITS line: read as raw (every value a whole number "
                               "0..255)")
    # without SECONDS_PER_FRAME only the first frame's time (0 s) is known; the rest are NaN
    index_time = np.arange(len(index.numbers)) * attrs.get("seconds_per_frame", np.nan)
    index_time[0] = 0.0
    times = np.where(np.isnan(index.times), index_time, index.times)
    attrs["source"] = index.name
    dims = {"frame": np.asarray(index.numbers, dtype=np.int64),
            "row": np.arange(index.rows, dtype=np.int64),
            "col": np.arange(index.cols, dtype=np.int64)}
    if not isinstance(values, np.ndarray):  # lazy: dask is imported already
        data = xr.DataArray(values, dims=tuple(dims), coords={**dims, "time": ("frame", times)},
                            attrs=attrs)
        data.name = None  # xarray names a DataArray after a dask array's graph key
        return data
    return xr.DataArray(_variable(tuple(dims), values), coords=_coordinates(dims, times),
                        attrs=attrs)


def _variable(dims, values):
    """Return the ``xarray.Variable`` of a NumPy array as it is (no conversion, no import)."""
    return xr.Variable(dims, values, fastpath=True)


def _coordinates(dims, times):
    """Return the recording's coordinates, their indexes built here.

    Building them from NumPy arrays, xarray asks whether each is a dask array, which imports
    dask and, for the data, ``dask.array`` and SciPy: in a new process more than the whole
    read of a 6,000-frame export, for a reader that uses neither.
    """
    import pandas as pd

    indexes = {dim: xr.indexes.PandasIndex(pd.Index(values, name=dim), dim)
               for dim, values in dims.items()}
    variables = {dim: _variable((dim,), values) for dim, values in dims.items()}
    return xr.Coordinates({**variables, "time": _variable(("frame",), times)}, indexes=indexes)


def _check_frames(numbers, times, lines, header, name):
    """Frame times and the header's frame range (the index checked the numbering).

    Times are on every frame line (I-Scan) or on none (F-Scan); given, they are finite,
    not negative and increasing. ``START_FRAME`` and ``END_FRAME``, when given, are the
    first and last frame numbers, so no frame block is missing at either end (a missing one
    inside breaks the numbering).
    """
    given = ~np.isnan(times)
    if given.any() and not given.all():
        k = int(np.flatnonzero(given != given[0])[0])
        has = "a time" if given[k] else "no time"
        other = "none" if given[k] else "one"
        raise TactilecalError(f"line {lines[k]} of {name}: frame {numbers[k]} has {has} in its "
                              f"frame line but frame {numbers[0]} has {other}; expected a time on "
                              "every frame line or on none")
    if given.all():
        bad = np.flatnonzero(~np.isfinite(times) | (times < 0))
        if bad.size:
            k = bad[0]
            raise TactilecalError(f"line {lines[k]} of {name}: frame {numbers[k]} has the time "
                                  f"{times[k]:g} s; expected a finite time >= 0 s")
        steps = np.flatnonzero(np.diff(times) <= 0)
        if steps.size:
            k = steps[0] + 1
            raise TactilecalError(f"line {lines[k]} of {name}: frame {numbers[k]} has the time "
                                  f"{times[k]:g} s, not after frame {numbers[k - 1]}'s "
                                  f"{times[k - 1]:g} s; expected increasing frame times")
    for key, k in (("START_FRAME", 0), ("END_FRAME", -1)):
        if key in header:
            value, line = header[key]
            if integer(header, key, name, minimum=0) != numbers[k]:
                raise TactilecalError(f"line {line} of {name}: {key} is {shorten(value)} but the "
                                      f"{'first' if k == 0 else 'last'} frame is {numbers[k]} "
                                      f"({len(numbers)} frames: frames missing, or the header "
                                      "edited?); expected them to agree")
