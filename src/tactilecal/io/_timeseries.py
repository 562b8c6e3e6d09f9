"""Reader for load-cell / force-time CSV files with a header row.

The file is read in pieces, never whole (:class:`tactilecal._textfile.TextFile`): checked and
its encoding found as it is opened, its rows checked (:mod:`tactilecal._plaincsv`: NumPy over
blocks of a plain file's bytes, else line by line), its two columns parsed by pandas from the
file (or its text in UTF-8, a piece at a time). Memory is the two columns and a piece of the
file, however many columns and rows it has.
"""

import itertools
import math
import re
from pathlib import Path

import numpy as np
import pandas as pd
import xarray as xr

from tactilecal._atomic import check_target, write_text_atomic
from tactilecal._errors import TactilecalError
from tactilecal._plaincsv import checked_header
from tactilecal._textfile import TextFile
from tactilecal._units import (
    _HINT,
    force_to_N,
    mass_to_N,
    pressure_to_kPa,
    time_to_s,
    unit_from_column,
    unit_kind,
)
from tactilecal._validate import parse_number, shorten

__all__ = ["read_timeseries", "write_timeseries"]

def _pick(columns, choice, default, role, name):
    if choice is None:
        choice = default
    if isinstance(choice, str) and choice not in columns and re.fullmatch(r"-?\d+", choice):
        choice = int(choice)  # "2" from a command line: an index unless a column is named so
    if isinstance(choice, int | np.integer) and not isinstance(choice, bool):
        if not -len(columns) <= choice < len(columns):
            raise TactilecalError(f"{role}={choice} is out of range for {name}, which has "
                                  f"{len(columns)} columns {list(columns)}")
        return columns[choice]
    if choice not in columns:
        raise TactilecalError(f"{role}={choice!r} is not a column of {name}; expected one of "
                              f"{list(columns)} or a column index")
    return choice


def _first_bad_cell(text, column, index, name):
    """Slow path (only after the fast parse failed): raise naming the first bad cell's line."""
    for k, (line, cells) in enumerate(text.rows()):
        cell = cells[index]
        if k and not _finite(cell):
            found = "an empty cell" if cell == "" else shorten(cell)
            raise TactilecalError(f"line {line} of {name}, column {column!r}: {found}; expected "
                                  "a finite number")


def _finite(cell):
    try:
        return math.isfinite(parse_number(cell, "cell"))
    except ValueError:
        return False


def _columns(text, name):
    """Return the header's cells, every row checked (as wide as the header, no lone CR)."""
    header = checked_header(text)
    if header is None:
        raise TactilecalError(f"{name} is empty; expected a header row and at least 2 rows")
    return header


def _cells_of_rows(text, indices):
    """Slow path: the columns ``indices`` of the rows the checker keeps, as float64 arrays.

    Every cell is a finite number (:func:`_first_bad_cell` passed). Reached when pandas read
    what the checker skips as blank, a line of spaces and commas only (a spreadsheet's empty
    row): pandas makes it a row of NaN, the checker no row, as for every CSV read here.
    """
    rows = itertools.islice(text.rows(), 1, None)  # after the header
    table = np.array([[parse_number(cells[i], "cell") for i in indices] for _, cells in rows],
                     dtype=np.float64).reshape(-1, len(indices))
    return tuple(np.ascontiguousarray(column) for column in table.T)


def _line_of_row(text, row):
    """File line number of data row ``row`` (0-based; blank lines are no rows), for a message."""
    rows = text.rows()
    try:
        return next(itertools.islice(rows, row + 1, None))[0]
    finally:
        rows.close()


def read_timeseries(path, time_col=None, value_col=None):
    r"""Read a load-cell (force-time) CSV with a header row into a 1-D DataArray.

    Units written in the column names (``"Time (ms)"``, ``"Load (lbf)"``, ``"Force [kN]"``,
    ``"Pressure (kPa)"``) are converted: times to seconds, forces and dead-weight masses
    to newtons (g = 9.80665 m/s2), pressures to kPa. A time column without a unit is taken
    as seconds; a value column without one keeps its numbers with ``units = "unknown"``.

    Parameters
    ----------
    path : str or os.PathLike
        Comma-separated file, first line the column names.
    time_col, value_col : str or int, optional
        Column names or 0-based indices (default: the first and the second column). A
        string of digits (from a command line) is an index unless a column has that name.

    Returns
    -------
    xarray.DataArray
        float64 values with dim ``time`` (s); attributes ``units``, ``source``, ``column``
        (value column name) and ``time_column``.

    Raises
    ------
    ValueError
        Missing column, unknown unit, non-numeric or empty cell (with its line number),
        fewer than 2 rows, times not strictly increasing.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> f = pathlib.Path(tempfile.mkdtemp()) / "lc.csv"
    >>> _ = f.write_text("Time (ms),Load (kN)\n0,1.5\n250,2\n")
    >>> s = read_timeseries(f)
    >>> s.time.values.tolist(), s.values.tolist(), s.attrs["units"]
    ([0.0, 0.25], [1500.0, 2000.0], 'N')
    """
    path = Path(path)
    name = str(path)
    text = TextFile(path, expected="a CSV file with a header row")
    columns = _columns(text, name)
    t_name = _pick(columns, time_col, 0, "time_col", name)
    v_name = _pick(columns, value_col, 1, "value_col", name)
    t_unit = unit_from_column(t_name, where=f"column {t_name!r} of {name}") or "s"
    if unit_kind(t_unit) != "time":
        raise TactilecalError(f"time column {t_name!r} of {name} is in {t_unit!r}; expected a "
                              "time unit (s, ms, us, min)")
    raw_times, raw_values = _load_columns(text, columns, t_name, v_name, name)
    times = time_to_s(raw_times, t_unit)
    values, units = _convert_values(raw_values, v_name, name)
    steps = np.flatnonzero(np.diff(times) <= 0)
    if steps.size:
        i = steps[0] + 1
        raise TactilecalError(f"line {_line_of_row(text, i)} of {name}: time {times[i]:g} s "
                              f"follows {times[i - 1]:g} s; expected strictly increasing times")
    return xr.DataArray(values, dims="time", coords={"time": times}, name=str(v_name),
                        attrs={"units": units, "source": name, "column": str(v_name),
                               "time_column": str(t_name)})


def _read_csv(text, name, **kwargs):
    """pandas.read_csv of a :class:`TextFile`; a malformed row is a ValueError naming the file.

    pandas reads the text as UTF-8 bytes, a block at a time (a ``StringIO`` would hold it at
    4 bytes a character; memory of a read: 3x its array + 100 MB at most).
    """
    try:
        with text.utf8() as source:
            return pd.read_csv(source, encoding="utf-8", **kwargs)
    except pd.errors.ParserError as exc:
        detail = " ".join(str(exc).split()).replace("Error tokenizing data. C error: ", "")
        raise TactilecalError(f"{name}: {detail}; expected the same number of comma-separated "
                              "values on every line as in the header") from None


def _load_columns(text, columns, t_name, v_name, name):
    """Both columns as float64 in one C-parser pass; on any problem find the bad line."""
    wanted = sorted({columns.index(t_name), columns.index(v_name)})
    try:  # csv_rows checked that every row is as wide as the header: only the two are kept
        table = _read_csv(text, name, header=0, names=range(len(columns)), usecols=wanted,
                          dtype=dict.fromkeys(wanted, np.float64), keep_default_na=False,
                          skipinitialspace=True, engine="c")
        table = table[wanted]
        table.columns = [columns[i] for i in wanted]
        pair = table[t_name].to_numpy(), table[v_name].to_numpy()
        ok = np.isfinite(pair[0]).all() and np.isfinite(pair[1]).all()
    except ValueError:
        ok = False
    if not ok:
        _first_bad_cell(text, t_name, columns.index(t_name), name)
        _first_bad_cell(text, v_name, columns.index(v_name), name)
        pair = _cells_of_rows(text, (columns.index(t_name), columns.index(v_name)))
    if len(pair[0]) < 2:
        raise TactilecalError(f"{name} has {len(pair[0])} data rows; expected at least 2")
    return pair


def _convert_values(values, column, name):
    unit = unit_from_column(column, where=f"column {column!r} of {name}")
    if unit is None:
        return values, "unknown"
    kind = unit_kind(unit)
    if kind == "force":
        return force_to_N(values, unit), "N"
    if kind == "mass":
        return mass_to_N(values, unit), "N"
    if kind == "pressure":
        return pressure_to_kPa(values, unit), "kPa"
    return values, unit


def write_timeseries(series, path, *, overwrite=False):
    r"""Write a 1-D time series as a CSV that :func:`read_timeseries` reads back exactly.

    The header is ``Time (s),<name> (<units>)``: ``<name>`` is the series' ``column``
    attribute (its unit hint dropped) or its name, ``<units>`` its ``units`` attribute
    (left out when ``unknown``). Numbers are written with 17 significant digits, so the
    round trip is exact.

    Parameters
    ----------
    series : xarray.DataArray
        1-D with dim ``time`` in seconds (or another dim with a ``time`` coordinate), as
        returned by :func:`read_timeseries` or the simulators.
    path : str or os.PathLike
        Output CSV, written atomically (the folder must exist).
    overwrite : bool, keyword-only
        Replace an existing ``path`` (only a CSV table; default False: an error).

    Returns
    -------
    pathlib.Path

    Raises
    ------
    ValueError
        Not 1-D, no time coordinate, fewer than 2 samples, a time or value that is not
        finite (named by its position), times not strictly increasing.

    Examples
    --------
    >>> import tempfile, pathlib, xarray as xr
    >>> s = xr.DataArray([1500.0, 2000.0], dims="time", coords={"time": [0.0, 0.25]},
    ...                  attrs={"units": "N", "column": "Load (kN)"})
    >>> f = write_timeseries(s, pathlib.Path(tempfile.mkdtemp()) / "lc.csv")
    >>> f.read_text().splitlines()[0], read_timeseries(f).values.tolist()
    ('Time (s),Load (N)', [1500.0, 2000.0])
    """
    path = Path(path)
    check_target(path, overwrite=overwrite, kind="csv")
    name = str(series.attrs.get("source", series.name or "series"))
    if series.ndim != 1 or "time" not in series.coords:
        raise TactilecalError(f"{name}: dims {tuple(series.dims)} without a 'time' coordinate; "
                              f"expected a 1-D series with time in seconds (writing {path})")
    times = np.asarray(series["time"].values, dtype=np.float64)
    values = np.asarray(series.values, dtype=np.float64)
    if times.size < 2:
        raise TactilecalError(f"{name}: {times.size} samples; expected at least 2 (writing {path})")
    for what, column in (("time", times), ("value", values)):
        bad = np.flatnonzero(~np.isfinite(column))
        if bad.size:
            raise TactilecalError(f"{name}: {what} at position {bad[0]} is {column[bad[0]]}; "
                                  f"expected finite numbers (writing {path})")
    steps = np.flatnonzero(np.diff(times) <= 0)
    if steps.size:
        raise TactilecalError(f"{name}: time {times[steps[0] + 1]:g} s at position "
                              f"{steps[0] + 1} follows {times[steps[0]]:g} s; expected strictly "
                              f"increasing times (writing {path})")
    write_text_atomic(path, _header(series) + "".join(
        f"{t!r},{v!r}\n" for t, v in zip(times.tolist(), values.tolist(), strict=True)))
    return path


def _header(series):
    label = str(series.attrs.get("column") or series.name or "value")
    label = _HINT.sub("", label).strip() or "value"
    units = series.attrs.get("units", "unknown")
    return f"Time (s),{label}" + ("" if units == "unknown" else f" ({units})") + "\n"

