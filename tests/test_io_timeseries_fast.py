"""The fast check of a load-cell CSV's rows (:mod:`tactilecal._plaincsv`) against the checker.

For generated CSVs, valid and broken (ragged rows, blank and space-only lines, quotes,
non-ASCII bytes, NaN and inf, CR LF, encodings, a lowered field limit, tiny read pieces, and
random byte edits), :func:`read_timeseries` with the fast check gives bitwise the same
arrays and attributes, or the same error with the same message, as with every row checked
line by line; and the fast check is what reads the plain files.
"""

import contextlib
import csv
import itertools
from unittest import mock

import numpy as np
import pytest
from edits import byte_edits
from hypothesis import given, settings
from hypothesis import strategies as st

from tactilecal import _plaincsv, _textfile
from tactilecal._textfile import TextFile
from tactilecal.io import read_timeseries

_COUNT = itertools.count()


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    return tmp_path_factory.mktemp("fast")


def _new(folder, raw):
    """A new file of ``raw`` (a new name: replacing a file's bytes costs a disk flush)."""
    path = folder / f"{next(_COUNT)}.csv"
    path.write_bytes(raw)
    return path


HEADERS = ["Time (ms)", "Load (N)", "t", "F [kN]", "note", "Zeit (µs)", '"a,b"', " x ",
           "Mass (kg)", ""]
CELLS = ["", " ", "1", "-2.5", "3e2", "1e400", " 4 ", "\t5", "nan", "inf", "x", "1_0", '"6"',
         "é", "7,", "0x1", "+.5", "1.", "--1"]
BLANKS = ["", " ", ",", " , ", "\t", ",,,"]


@st.composite
def csv_files(draw):
    """Bytes of a CSV: header, rows mostly numeric and as wide as it, edits, an encoding."""
    width = draw(st.integers(1, 4))
    header = [draw(st.sampled_from(HEADERS)) for _ in range(width)]
    if draw(st.booleans()):  # columns as read_timeseries wants them, most of the time
        header[:2] = ["Time (s)", "Load (N)"][:width]
    lines = [",".join(header)]
    time, n = 0.0, draw(st.integers(0, 12))
    late = draw(st.integers(0, 4 * n))  # the row whose time does not increase, if any
    for k in range(n):
        time += draw(st.sampled_from([0.0, -1.0])) if k == late else draw(
            st.sampled_from([0.5, 1.0, 1e-3, 250.0]))
        cells = [repr(time)] + [repr(draw(st.floats(-1e6, 1e6, allow_nan=False)))
                                for _ in range(width - 1)]
        if draw(st.integers(0, 5)) == 0:  # a departure from the plain form
            what = draw(st.sampled_from(["cell", "wider", "narrower", "blank"]))
            if what == "cell":
                cells[draw(st.integers(0, width - 1))] = draw(st.sampled_from(CELLS))
            elif what == "wider":
                cells.append(draw(st.sampled_from(CELLS)))
            elif what == "narrower":
                cells.pop()
            else:
                lines.append(draw(st.sampled_from(BLANKS)))
        lines.append(",".join(cells))
    if draw(st.integers(0, 4)) == 0:
        lines.insert(0, draw(st.sampled_from(BLANKS)))
    newline = draw(st.sampled_from(["\n", "\r\n"]))
    text = newline.join(lines) + draw(st.sampled_from([newline, "", newline * 2]))
    encoding = draw(st.sampled_from(["utf-8", "utf-8", "utf-8-sig", "cp1252", "utf-16"]))
    try:
        raw = text.encode(encoding)
    except UnicodeEncodeError:
        raw = text.encode("utf-8")
    if draw(st.integers(0, 3)) == 0:
        raw = draw(byte_edits(raw))
    return raw


#: Cells of plain rows, then cells that each depart from the plain form.
PLAIN = ["1", "-2.5e3", "x", "", " ", "\t", " 7 "]
ODD = ['"', '"a,b"', '"a\nb"', '"x""y"', "\x01", "\x0b", "\x1c", "\x1f", "\x7f", "\x85",
       "\xa0", "é", "\u2028", "\ufeff", "\x00", "\r"]


@st.composite
def csv_rows(draw):
    """Bytes of a CSV of rows of PLAIN cells, mostly as wide as the header; some ODD cells."""
    width = draw(st.integers(1, 4))

    def row(odd):
        cells = [draw(st.sampled_from(PLAIN))
                 for _ in range(max(0, width + draw(st.sampled_from([0, 0, 0, -1, 1]))))]
        if odd:
            cells.insert(draw(st.integers(0, len(cells))), draw(st.sampled_from(ODD)))
            cells = cells[:width] if draw(st.booleans()) else cells
        return ",".join(cells)

    lines = [draw(st.sampled_from(["", " ", ","])) for _ in range(draw(st.integers(0, 2)))]
    lines += [row(draw(st.integers(0, 7)) == 0) for _ in range(draw(st.integers(1, 10)))]
    newline = draw(st.sampled_from(["\n", "\r\n"]))
    text = newline.join(lines) + draw(st.sampled_from(["", newline]))
    encoding = draw(st.sampled_from(["utf-8", "utf-8", "utf-8-sig", "cp1252", "utf-16"]))
    try:
        return text.encode(encoding)
    except UnicodeEncodeError:
        return text.encode("utf-8")


def _headers(path):
    """The checked header of ``path`` (or the error and its message), fast and line by line."""
    try:
        text = TextFile(path)
    except Exception:  # noqa: BLE001 - refused before any row is read: nothing to compare
        return None, None
    fast = _header(text)
    with mock.patch.object(_plaincsv, "_plain_after", return_value=False):
        return fast, _header(text)


def _header(text):
    try:
        return _plaincsv.checked_header(text)
    except Exception as exc:  # noqa: BLE001 - the class and message are compared
        return type(exc).__name__, str(exc)


@settings(max_examples=3 * settings.default.max_examples)
@given(raw=csv_rows(), piece_bytes=st.sampled_from([1, 5, 64, _textfile.PIECE_BYTES]),
       field_limit=st.sampled_from([csv.field_size_limit(), 3, 8]))
def test_fast_check_passes_and_fails_as_the_line_by_line_check(folder, raw, piece_bytes,
                                                               field_limit):
    path = _new(folder, raw)
    with _reading(piece_bytes, field_limit):
        fast, checked = _headers(path)
        assert fast == checked


def test_every_byte_is_read_as_the_line_by_line_check_reads_it(folder):
    """Each ASCII byte (and a few others) alone, padded and between commas, as a row."""
    for byte in map(int.to_bytes, [*range(128), 0x81, 0x85, 0xA0, 0xFF]):
        for row in (byte, b" " + byte + b" ", b",".join([byte] * 3)):
            path = _new(folder, b"a,b\n" + row + b"\n")
            fast, checked = _headers(path)
        assert fast == checked, row


def _outcome(path, **kwargs):
    """What a read gives: its arrays as bytes and its attributes, or its error and message."""
    try:
        series = read_timeseries(path, **kwargs)
    except Exception as exc:  # noqa: BLE001 - the class and message are compared
        return type(exc).__name__, str(exc)
    return (series.values.dtype, series.values.tobytes(), series.time.values.tobytes(),
            series.name, series.attrs)


@contextlib.contextmanager
def _reading(piece_bytes, field_limit):
    """Pieces of ``piece_bytes`` and the csv module's field limit ``field_limit``."""
    before = csv.field_size_limit(field_limit)
    try:
        with mock.patch.object(_textfile, "PIECE_BYTES", piece_bytes):
            yield
    finally:
        csv.field_size_limit(before)


def _checked(path, **kwargs):
    """The outcome with every row checked line by line (the fast check proves nothing)."""
    with mock.patch.object(_plaincsv, "_plain_after", return_value=False):
        return _outcome(path, **kwargs)


@given(raw=csv_files(), piece_bytes=st.sampled_from([1, 7, 64, _textfile.PIECE_BYTES]),
       field_limit=st.sampled_from([csv.field_size_limit(), 5, 12]),
       value_col=st.sampled_from([None, 0, -1]))
def test_fast_check_reads_and_fails_as_the_line_by_line_check(folder, raw, piece_bytes,
                                                              field_limit, value_col):
    path = _new(folder, raw)
    with _reading(piece_bytes, field_limit):
        fast = _outcome(path, value_col=value_col)
        checked = _checked(path, value_col=value_col)
    assert fast == checked


@st.composite
def plain_files(draw):
    """A valid load-cell CSV of the plain form: numbers, spaces, LF or CR LF, blank lines."""
    width = draw(st.integers(2, 5))
    header = ["Time (ms)", "Load (µN)"] + [f"c{k}" for k in range(width - 2)]
    n = draw(st.integers(2, 20))
    times = np.cumsum(draw(st.lists(st.floats(1e-3, 1e3), min_size=n, max_size=n)))
    values = draw(st.lists(st.floats(-1e300, 1e300), min_size=n * (width - 1),
                           max_size=n * (width - 1)))
    pad = draw(st.sampled_from(["", " ", "\t"]))
    rows = [pad + ",".join(map(repr, [t, *values[k * (width - 1):(k + 1) * (width - 1)]]))
            for k, t in enumerate(times.tolist())]
    for _ in range(draw(st.integers(0, 2))):
        rows.insert(draw(st.integers(0, n)), draw(st.sampled_from(BLANKS)))
    newline = draw(st.sampled_from(["\n", "\r\n"]))
    text = newline.join([",".join(header), *rows]) + draw(st.sampled_from(["", newline]))
    return text.encode(draw(st.sampled_from(["utf-8", "utf-8-sig", "cp1252"])))


@given(raw=plain_files(), piece_bytes=st.sampled_from([3, 64, _textfile.PIECE_BYTES]))
def test_plain_files_are_read_by_the_fast_check(folder, raw, piece_bytes):
    path = _new(folder, raw)
    with _reading(piece_bytes, csv.field_size_limit()):
        with mock.patch.object(_textfile.TextFile, "rows", side_effect=AssertionError):
            header = _plaincsv.checked_header(TextFile(path))  # never line by line
        assert header[:2] == ["Time (ms)", "Load (µN)"]
        assert _outcome(path) == _checked(path)


def test_a_line_at_the_field_limit_is_left_to_the_checker(tmp_path):
    limit = _plaincsv.MAX_FIELD_CHARS
    for size, proved in ((limit - 1, True), (limit, False), (limit + 1, False)):  # before LF
        path = _new(tmp_path, b"t,F\n0,1\n1," + b"2" * (size - 2) + b"\n")
        assert _plaincsv._plain_after(TextFile(path), 1, 2) is proved, size
        assert _outcome(path) == _checked(path)
