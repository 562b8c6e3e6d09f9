"""Reader for Tekscan I-Scan / F-Scan ASCII exports (``.csv``, ``.asf``, any extension).

Layout, as written by Tekscan I-Scan 6.10I and F-Scan 6.33 (the two real exports in
``shared/realdata``, see its README)::

    KEY value                 header lines (ROWS, COLS, UNITS, ...)
    ASCII_DATA @@
    Frame 1, 0,, 12/2/2019 6:21:52.34PM,,,Raw Sum=,,310     (I-Scan; F-Scan: "Frame 1")
    B,B,5,0,...               ROWS lines of COLS comma-separated values, B = no sensel
    ...
    @@

The numeric block is parsed in one call of pandas' C parser; the line structure (frame lines,
rows per frame, values per row) is checked with vectorised NumPy operations on the bytes.
"""

import csv
import io
import re
import warnings
from pathlib import Path

import numpy as np
import pandas as pd
import xarray as xr

from tactilecal._validate import check_size
from tactilecal.io._header import header_attrs, integer, parse_header_lines

__all__ = ["read_tekscan"]

_MARKER = re.compile(rb"^[ \t]*ASCII_DATA[ \t]*@@[ \t]*\r?$", re.MULTILINE)
_FRAME = re.compile(r"Frame[ \t]+(\d+)[ \t]*(?:,[ \t]*([^,]*?)[ \t]*(?:,|$))?")
_RAW_SUM = re.compile(r"Raw Sum[ \t]*=[ \t,]*([-+]?\d+(?:\.\d*)?)")
_NL = b"\n"
_DATA_START = np.zeros(256, dtype=bool)
_DATA_START[list(b"0123456789B-+.")] = True


def read_tekscan(path):
    r"""Read a Tekscan I-Scan or F-Scan ASCII export into a DataArray.

    Parameters
    ----------
    path : str or os.PathLike
        The export (movie or single frame, LF or CRLF line endings, any extension).

    Returns
    -------
    xarray.DataArray
        float64, dims ``("frame", "row", "col")``, NaN where the file has ``B``; coords
        ``frame`` (the file's frame numbers), ``time`` (s: the frame line's time where it
        carries one, else frame index x ``SECONDS_PER_FRAME``), ``row``, ``col``; attributes
        as in ``docs/data-model.md`` (all ``str``/``int``/``float``, so ``to_netcdf`` works).

    Raises
    ------
    ValueError
        Empty file, missing ``ASCII_DATA @@``, ``ROWS`` or ``COLS``, a frame with the wrong
        number of rows, a row with the wrong number of values, a non-numeric value, a
        ``Raw Sum`` in a frame line that differs from the frame's sum (raw files), an unknown
        unit, no ``@@`` terminator. Messages name the file and line.

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
    """
    path = Path(path)
    name = str(path)
    raw = path.read_bytes()
    if not raw or raw.isspace():
        raise ValueError(f"{name} is empty; expected a Tekscan ASCII export "
                         "('KEY value' header, 'ASCII_DATA @@', frames, '@@')")
    marker = _MARKER.search(raw)
    if marker is None:
        raise ValueError(f"{name} has no 'ASCII_DATA @@' line (after "
                         f"{len(raw.splitlines())} lines); expected a Tekscan ASCII export")
    header = parse_header_lines(_decode(raw[:marker.start()]).splitlines(), name)
    for key in ("ROWS", "COLS"):
        if key not in header:
            raise ValueError(f"{name} has no {key} line in its header (lines 1-"
                             f"{raw.count(_NL, 0, marker.start()) + 1}); expected "
                             f"'{key} <number of sensel {key.lower()}>'")
    rows = integer(header, "ROWS", name, minimum=1)
    cols = integer(header, "COLS", name, minimum=1)
    attrs = header_attrs(header, name)
    first_line = raw.count(b"\n", 0, marker.end()) + 1
    frames, values, data_lines = _read_body(raw, marker.end(), first_line, rows, cols, header,
                                            name)
    numbers, times, raw_sums, lines = frames
    _check_values(values, attrs.get("units"), data_lines, name)
    if "units" not in attrs:  # the values were just checked to be raw readings
        attrs["units"] = "raw"
        attrs["units_note"] = ("no UNITS line: read as raw (every value a whole number "
                               "0..255)")
    _check_frames(numbers, times, lines, header, name)
    data = values.reshape(len(numbers), rows, cols)
    if attrs.get("units", "raw") == "raw":
        _check_raw_sums(data, numbers, raw_sums, lines, name)
    # without SECONDS_PER_FRAME only the first frame's time (0 s) is known; the rest are NaN
    index_time = np.arange(len(numbers)) * attrs.get("seconds_per_frame", np.nan)
    index_time[0] = 0.0
    times = np.where(np.isnan(times), index_time, times)
    attrs["source"] = name
    return xr.DataArray(
        data, dims=("frame", "row", "col"),
        coords={"frame": np.asarray(numbers, dtype=np.int64), "time": ("frame", times),
                "row": np.arange(rows, dtype=np.int64), "col": np.arange(cols, dtype=np.int64)},
        attrs=attrs)


def _decode(header_bytes):
    try:
        return header_bytes.decode("utf-8")
    except UnicodeDecodeError:
        return header_bytes.decode("cp1252", errors="replace")


def _line_table(body):
    """Start/end byte offsets of each line of ``body`` (end excludes CR/LF) and its bytes."""
    buf = np.frombuffer(body, dtype=np.uint8)
    newlines = np.flatnonzero(buf == 10)
    starts = np.concatenate(([0], newlines + 1))
    ends = np.concatenate((newlines, [buf.size]))
    has_cr = (ends > starts) & (buf[np.maximum(ends - 1, 0)] == 13) if buf.size else ends > 0
    ends = ends - has_cr
    return buf, starts, ends


def _read_body(raw, offset, first_line, rows, cols, header, name):
    """Frames and values from the bytes after ``ASCII_DATA @@`` (line ``first_line``)."""
    body = memoryview(raw)[offset:]  # no copy of the (possibly large) data block
    buf, starts, ends = _line_table(body)
    empty = ends == starts
    first = np.where(empty, 0, buf[np.minimum(starts, max(buf.size - 1, 0))] if buf.size else 0)
    terminators = np.flatnonzero(first == ord("@"))
    if terminators.size == 0:
        raise ValueError(f"{name} ends at line {first_line + len(starts) - 1} without the "
                         "'@@' terminator; expected '@@' after the last frame (truncated file?)")
    stop = terminators[0]
    if bytes(body[starts[stop]:ends[stop]]).strip() != b"@@":
        raise ValueError(f"line {first_line + stop} of {name}: "
                         f"{_text(body, starts, ends, stop)!r}; expected '@@' (end of data)")
    _check_after_terminator(body, starts, ends, stop, first_line, name)
    end = int(starts[stop])
    starts, ends, empty, first = starts[:stop], ends[:stop], empty[:stop], first[:stop]
    is_frame = first == ord("F")
    is_data = ~empty & _DATA_START[first]
    other = np.flatnonzero(~(empty | is_frame | is_data))
    if other.size:
        i = other[0]
        raise ValueError(f"line {first_line + i} of {name}: {_text(body, starts, ends, i)!r}; "
                         "expected a 'Frame N' line, a row of values or '@@'")
    frame_idx, data_idx = np.flatnonzero(is_frame), np.flatnonzero(is_data)
    frames = _frame_lines(body, starts, ends, frame_idx, data_idx, stop, first_line, rows,
                          header, name)
    _check_bytes(raw, offset, offset + end, buf, starts, ends, data_idx, first_line, name)
    # COLS is checked against the data before pandas allocates a column per name
    widest = int((ends[data_idx] - starts[data_idx]).max()) if data_idx.size else 0
    if cols > (widest + 1) // 2:
        _check_row_lengths(buf, starts, ends, data_idx, frame_idx, first_line, rows, cols,
                           name)
    check_size(data_idx.size * cols, name)
    # Fast path: one parse, then one count. A short row is padded with NaN by pandas and a
    # stray "F" (comment character) truncates a row: both leave more NaN than "B"s. A long
    # row, a non-numeric value or an empty value make pandas raise. Only then do the exact
    # per-line checks run, to say which line is wrong.
    # ", "-separated rows (not Tekscan's own layout) cost the C parser 40 %: only when seen
    spaced = bool(data_idx.size) and b", " in bytes(body[starts[data_idx[0]]:ends[data_idx[0]]])
    expected_nan = (np.count_nonzero(buf[:end] == ord("B"))
                    - sum(bytes(body[starts[i]:ends[i]]).count(b"B") for i in frame_idx))
    try:
        values = _parse_values(raw, offset, data_idx.size, cols, spaced)
    except (ValueError, pd.errors.ParserWarning) as exc:
        failure = ValueError(f"{name}: {exc}")
    else:
        found_nan = values.size - np.count_nonzero(np.isfinite(values))
        if found_nan == expected_nan:
            return frames, values, first_line + data_idx
        failure = ValueError(f"{name}: {found_nan} values read as NaN or infinite; "
                             f"expected {expected_nan} NaN, one per 'B'")
    _check_row_lengths(buf, starts, ends, data_idx, frame_idx, first_line, rows, cols, name)
    _check_stray_comment(body, buf[:end], starts, ends, data_idx, first_line, name)
    _raise_bad_value(body, starts, ends, data_idx, first_line, name, spaced)
    raise failure


def _check_bytes(raw, start, stop, buf, starts, ends, data_idx, first_line, name):
    """Refuse what pandas would read as something else: ``1_0`` (read as 10) and a lone CR.

    A carriage return not followed by LF ends a row for pandas but not for the line table,
    so a row would silently shift; both are searched with ``bytes`` methods (C speed).
    """
    underscore = raw.find(b"_", start, stop)
    while underscore >= 0:
        i = np.searchsorted(starts, underscore - start, side="right") - 1
        if np.isin(i, data_idx):
            raise ValueError(f"line {first_line + i} of {name}: "
                             f"{bytes(buf[starts[i]:ends[i]])[:60]!r} has '_' inside a "
                             "value; expected numbers or 'B' separated by commas")
        underscore = raw.find(b"_", start + int(ends[i]), stop)
    if raw.count(b"\r", start, stop) > raw.count(b"\r\n", start, stop):
        lone = np.flatnonzero((buf[:stop - start - 1] == 13) & (buf[1:stop - start] != 10))
        i = np.searchsorted(starts, lone[0], side="right") - 1
        raise ValueError(f"line {first_line + i} of {name}: a carriage return (CR) inside the "
                         "line; expected CR only before the line feed (CRLF line ends)")


def _check_values(values, units, data_lines, name):
    """Raw readings are whole numbers 0..255 (8-bit sensels).

    A file without ``UNITS`` is read as raw (I-Scan writes ``UNITS raw`` for raw exports,
    but hand-made files omit it), so its values must be raw readings too. Calibrated values
    are not range-checked: filtered or drift-corrected pressures may dip below zero.
    """
    if values.size == 0 or units not in (None, "raw"):
        return
    lo, hi = np.fmin.reduce(values, axis=None), np.fmax.reduce(values, axis=None)
    fraction = np.floor(values) < values  # False for NaN ("B"); np.fmod is 10x slower
    if lo >= 0 and hi <= 255 and not fraction.any():
        return
    bad = (values < 0) | (values > 255) | fraction
    expected = ("a whole number 0..255 (UNITS raw)" if units else
                "a whole number 0..255: the file has no UNITS line, so it is read as raw; "
                "add e.g. 'UNITS kPa' before ASCII_DATA if its values are calibrated")
    row, col = np.unravel_index(np.flatnonzero(bad)[0], values.shape)
    raise ValueError(f"line {data_lines[row]} of {name}, value {col + 1}: "
                     f"{values[row, col]:.17g}; expected {expected}")


def _check_frames(numbers, times, lines, header, name):
    """Frame times finite and increasing; START_FRAME/END_FRAME match the frames present."""
    given = np.flatnonzero(~np.isnan(times))
    bad = given[~np.isfinite(times[given])]
    if bad.size:
        k = bad[0]
        raise ValueError(f"frame {numbers[k]} of {name} (line {lines[k]}): time "
                         f"{times[k]}; expected a finite time in s")
    steps = np.flatnonzero(np.diff(times[given]) <= 0)
    if steps.size:
        k = given[steps[0] + 1]
        raise ValueError(f"frame {numbers[k]} of {name} (line {lines[k]}): time "
                         f"{times[k]:g} s does not come after the previous frame's "
                         f"{times[given[steps[0]]]:g} s; expected increasing frame times")
    for key, k in (("START_FRAME", 0), ("END_FRAME", -1)):
        if key in header and len(numbers) > 1:
            value, line = header[key]
            if value.strip() != str(numbers[k]):
                raise ValueError(f"line {line} of {name}: {key} is {value!r} but the "
                                 f"{'first' if k == 0 else 'last'} frame is {numbers[k]} "
                                 "(frames missing, or the header edited?); expected them "
                                 "to agree")


def _text(body, starts, ends, i):
    return bytes(body[starts[i]:ends[i]]).decode("utf-8", errors="replace")[:60]


def _check_after_terminator(body, starts, ends, stop, first_line, name):
    rest = np.flatnonzero(ends[stop + 1:] > starts[stop + 1:])
    for i in rest + stop + 1:
        if bytes(body[starts[i]:ends[i]]).strip():
            raise ValueError(f"line {first_line + i} of {name}: "
                             f"{_text(body, starts, ends, i)!r} after the '@@' terminator on "
                             f"line {first_line + stop}; expected the end of the file "
                             "(one ASCII_DATA block per file)")


def _frame_lines(body, starts, ends, frame_idx, data_idx, stop, first_line, rows, header,
                 name):
    """Parse the ``Frame N`` lines; check each frame has ``rows`` data rows."""
    if frame_idx.size == 0:
        if data_idx.size != rows:
            raise ValueError(f"{name} has {data_idx.size} rows of values and no 'Frame N' "
                             f"line; expected {rows} rows (ROWS) for a single frame")
        number = int(header["START_FRAME"][0]) if "START_FRAME" in header else 1
        return [number], np.full(1, np.nan), np.full(1, np.nan), np.array([first_line])
    if data_idx.size and data_idx[0] < frame_idx[0]:
        raise ValueError(f"line {first_line + data_idx[0]} of {name}: a row of values before "
                         "the first 'Frame N' line; expected 'Frame N' first")
    bounds = np.searchsorted(data_idx, np.concatenate((frame_idx, [stop])))
    counts = np.diff(bounds)
    numbers, times, sums = [], np.full(frame_idx.size, np.nan), np.full(frame_idx.size, np.nan)
    for k, i in enumerate(frame_idx):
        text = bytes(body[starts[i]:ends[i]]).decode("utf-8", errors="replace")
        match = _FRAME.match(text)
        if match is None:
            raise ValueError(f"line {first_line + i} of {name}: {text[:60]!r}; expected "
                             "'Frame N' optionally followed by ', <time in s>, ...'")
        numbers.append(int(match.group(1)))
        if match.group(2):
            times[k] = _float(match.group(2), f"the time in line {first_line + i} of {name}")
        raw_sum = _RAW_SUM.search(text)
        if raw_sum:
            sums[k] = float(raw_sum.group(1))
    bad = np.flatnonzero(counts != rows)
    if bad.size:
        k = bad[0]
        raise ValueError(f"frame {numbers[k]} of {name} (line {first_line + frame_idx[k]}) "
                         f"has {counts[k]} rows of values; expected {rows} (ROWS)"
                         + (" (truncated file?)" if k == len(numbers) - 1 else ""))
    order = np.flatnonzero(np.diff(numbers) <= 0)
    if order.size:
        k = order[0] + 1
        raise ValueError(f"line {first_line + frame_idx[k]} of {name}: frame {numbers[k]} "
                         f"follows frame {numbers[k - 1]}; expected increasing frame numbers")
    return numbers, times, sums, first_line + frame_idx


def _float(text, where):
    try:
        return float(text)
    except ValueError:
        raise ValueError(f"{where} is {text!r}; expected a number") from None


def _check_row_lengths(buf, starts, ends, data_idx, frame_idx, first_line, rows, cols, name):
    commas = np.flatnonzero(buf == ord(","))
    n_values = (np.searchsorted(commas, ends[data_idx])
                - np.searchsorted(commas, starts[data_idx]) + 1)
    bad = np.flatnonzero(n_values != cols)
    if bad.size:
        k = bad[0]
        line = first_line + data_idx[k]
        where = f"line {line} of {name}"
        if frame_idx.size:
            frame_line = frame_idx[np.searchsorted(frame_idx, data_idx[k]) - 1]
            where = (f"row {k % rows} of the frame on line {first_line + frame_line} "
                     f"of {name} (line {line})")
        raise ValueError(f"{where} has {n_values[k]} values; expected {cols} (COLS)")


def _check_stray_comment(body, block, starts, ends, data_idx, first_line, name):
    """Frame lines are skipped as comments ("F"): an "F" inside a data row must not be."""
    positions = np.flatnonzero(block == ord("F"))
    line_of_f = np.searchsorted(starts, positions, side="right") - 1
    stray = line_of_f[np.isin(line_of_f, data_idx)]
    _raise_bad_value(body, starts, ends, stray[:1], first_line, name, False)


def _parse_values(raw, offset, n_rows, cols, spaced):
    """Parse the ``n_rows`` data rows after byte ``offset`` of ``raw`` (C parser).

    Returns a float64 ``(n_rows, cols)`` array. Frame lines start with "F", which no number
    or "B" contains, so they are read as comment lines; the "@@" terminator comes after
    ``n_rows`` rows and is not read. A first row longer than ``cols`` makes pandas warn and
    drop values: that warning is an error.
    """
    if n_rows == 0:
        return np.empty((0, cols))
    with warnings.catch_warnings():
        warnings.simplefilter("error", pd.errors.ParserWarning)
        stream = io.BytesIO(raw)  # shares raw's buffer; skiprows would cost ~15 %
        stream.seek(offset)
        table = pd.read_csv(
            stream, header=None, names=range(cols), comment="F", nrows=n_rows,
            na_values=["B"], keep_default_na=False, dtype=np.float64, engine="c",
            quoting=csv.QUOTE_NONE, skip_blank_lines=True, index_col=False,
            skipinitialspace=spaced)
    values = table.to_numpy(dtype=np.float64)
    if values.shape[0] != n_rows:
        raise ValueError(f"parsed {values.shape[0]} rows of values; expected {n_rows}")
    return values


def _raise_bad_value(body, starts, ends, data_idx, first_line, name, spaced):
    """Find the first non-numeric value (slow path, only on error) and raise."""
    for i in data_idx:
        for col, token in enumerate(bytes(body[starts[i]:ends[i]]).split(b",")):
            token = token.lstrip() if spaced else token
            if token == b"B":
                continue
            try:
                value = float(token)
            except ValueError:
                value = None
            if value is None or not np.isfinite(value):
                raise ValueError(
                    f"line {first_line + i} of {name}, value {col + 1}: "
                    f"{token.decode('utf-8', errors='replace')!r} is not a finite number; "
                    "expected a number or 'B' (no sensel)")


def _check_raw_sums(data, numbers, raw_sums, lines, name):
    """Compare each frame line's ``Raw Sum`` with the sum of the frame's readings."""
    sums = np.sum(data, axis=(1, 2), where=~np.isnan(data))
    bad = np.flatnonzero(~np.isnan(raw_sums) & (np.abs(sums - raw_sums) > 0.5))
    if bad.size:
        k = bad[0]
        raise ValueError(f"frame {numbers[k]} of {name} (line {lines[k]}): Raw Sum in the "
                         f"frame line is {raw_sums[k]:g}; expected {sums[k]:g}, the sum of "
                         "the frame's readings")
