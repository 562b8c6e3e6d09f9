"""TextFile: a text file read in pieces checks and decodes as read_text does whole.

Every check (NUL, bytes that are no text, the byte-order mark's encoding, a carriage return
inside a line), its message and line, the CSV rows and the UTF-8 text must not depend on
where the pieces are cut: each case is read with pieces of 1 byte up to the default.
"""

import re

import pytest
from hypothesis import given
from hypothesis import strategies as st

from tactilecal import _textfile
from tactilecal._textfile import TextFile
from tactilecal._validate import csv_rows, read_text

PIECES = [1, 2, 3, 5, 8, _textfile.PIECE_BYTES]


def _whole(path):
    """What the whole-text helpers give: rows and UTF-8 text, or the error message."""
    try:
        text = read_text(path, expected="a CSV")
        return list(csv_rows(text, str(path))), text.encode("utf-8")
    except ValueError as exc:
        return str(exc)


def _pieces(path):
    try:
        text = TextFile(path, expected="a CSV")
        with text.utf8() as f:
            return list(text.rows()), f.read()
    except ValueError as exc:
        return str(exc)


def _check_alike(path, monkeypatch):
    expected = _whole(path)
    for size in PIECES:
        monkeypatch.setattr(_textfile, "PIECE_BYTES", size)
        assert _pieces(path) == expected, size
    return expected


@pytest.mark.parametrize(("raw", "outcome"), [
    (b"t,F\r\n0,1\r\n\r\n1,2\r\n", [(1, ["t", "F"]), (2, ["0", "1"]), (4, ["1", "2"])]),
    ("t (µs),F\n0,1\n".encode("cp1252"), [(1, ["t (µs)", "F"]), (2, ["0", "1"])]),
    ("\ufefft,F\r\n0,1\r\n".encode("utf-16"), [(1, ["t", "F"]), (2, ["0", "1"])]),
    (b"\xef\xbb\xbf\xef\xbb\xbft,F\n", [(1, ["t", "F"])]),  # a second mark is dropped too
    (b't,"F\nG"\n0,1\n', [(2, ["t", "F\nG"]), (3, ["0", "1"])]),  # a quoted line end
    (b"t,F\n0,1\r", "line 2 of .*: a carriage return"),  # at the end of the file
    (b"t,F\r\n0,1\r\r\n", "line 2 of .*: a carriage return"),
    (b"t,F\n0,1\x00\n\x81\n", "line 2 of .*: a NUL byte"),  # NUL before a byte no text
    (b"t,F\n0,\xc3\n\x81\n", r"line 2 of .*: byte 0xc3 is not text"),
    (b"\xef\xbb\xbft\n\n,\xff\n", "line 3 of .*: bytes that are not UTF-8-SIG"),
    ("t\r\n\x00\r\n".encode("utf-16") + b"\x00", "line 3 of .*: bytes that are not UTF-16"),
    ("t\r\n\x00\r\r\n".encode("utf-16"), "line 2 of .*: a NUL character"),
    ("t\r\n0\r1\r\n".encode("utf-16"), "line 2 of .*: a carriage return"),
    (b"", []),
])
def test_pieces_read_as_the_whole_text(tmp_path, monkeypatch, raw, outcome):
    path = tmp_path / "lc.csv"
    path.write_bytes(raw)
    found = _check_alike(path, monkeypatch)
    if isinstance(outcome, str):
        assert isinstance(found, str) and re.match(outcome, found), found
    else:
        assert found[0] == outcome


BYTES = st.sampled_from([b"a", b",", b"1", b"\n", b"\r", b"\r\n", b"\x00", b'"', b" ",
                         b"\xef\xbb\xbf", b"\xff\xfe", b"\xfe\xff", b"\x81", b"\xe9",
                         b"\xc3\xa9", b"\xc3", b"\xed\xa0\x80", b"\xf0\x9f\x98\x80", b"\x0a\x00",
                         b"\x0d\x00", b"\x00\xd8", b"\x3d\xd8\x00\xde"])
TEXT = st.lists(st.sampled_from(["a", ",", "1", "\n", "\r\n", "\r", "\x00", "é", "\ufeff",
                                 "\U0001f600", '"']), max_size=20).map("".join)


@st.composite
def files(draw):
    """Bytes of any kind, or text in an encoding with or without its byte-order mark."""
    if draw(st.booleans()):
        return b"".join(draw(st.lists(BYTES, max_size=30)))
    return draw(TEXT).encode(draw(st.sampled_from(["utf-8", "utf-8-sig", "utf-16"])))


@given(raw=files())
def test_any_file_reads_in_pieces_as_whole(tmp_path_factory, raw):
    path = tmp_path_factory.mktemp("text") / "f.csv"
    path.write_bytes(raw)
    with pytest.MonkeyPatch.context() as monkeypatch:
        _check_alike(path, monkeypatch)
