"""A text file checked and decoded in pieces, as :func:`tactilecal._validate.read_text` would.

:func:`~tactilecal._validate.read_text` holds a file's bytes and then its text (and a
reader of CSV often a third copy for its parser). :class:`TextFile` reads the file three
times instead, a piece at a time, for readers whose memory must not grow with the file:

1. when it is opened, every check of :func:`~tactilecal._validate.decode_text` and
   :func:`~tactilecal._validate.check_line_ends`, in their order and with their messages
   (a NUL, bytes that are no text in UTF-8 or cp1252, or not in the encoding of the
   byte-order mark, a carriage return inside a line), which also chooses the encoding;
2. :meth:`TextFile.lines` and :meth:`TextFile.rows`: the text line by line;
3. :meth:`TextFile.utf8`: the text as UTF-8 bytes, for ``pandas.read_csv``.

Memory is a piece (:data:`PIECE_BYTES`) and a line, whatever the file's size.
"""

import codecs
import io
import os
import re

from tactilecal._validate import _BOMS, TextFault, csv_lines_rows, without_bom

__all__ = ["TextFile", "PIECE_BYTES"]

PIECE_BYTES = 2**22
"""Bytes of the file checked, or transcoded to UTF-8, at a time."""

_CP1252_UNDEFINED = re.compile(rb"[\x81\x8d\x8f\x90\x9d]")
_LONE_CR = {str: re.compile("\r(?!\n)"), bytes: re.compile(b"\r(?!\n)")}


class TextFile:
    r"""A text file, checked as it is opened; its lines, CSV rows and UTF-8 bytes on demand.

    Parameters
    ----------
    path : str or os.PathLike
    expected : str, keyword-only
        What the file should be, to complete the messages.

    Attributes
    ----------
    codec : str
        The encoding its text is read in: ``utf-8``, ``utf-8-sig`` or ``utf-16`` (a
        byte-order mark), else ``cp1252``.

    Raises
    ------
    ValueError
        As :func:`~tactilecal._validate.read_text` (a folder or a device, a NUL, bytes that
        are no text) and then :func:`~tactilecal._validate.check_line_ends` (a carriage
        return inside a line) raise, with their messages.
    OSError
        The file cannot be read.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "lc.csv"
    >>> _ = path.write_bytes("t (µs),F\r\n0,1\r\n\r\n1,2\r\n".encode("cp1252"))
    >>> text = TextFile(path, expected="a CSV file")
    >>> text.codec, list(text.rows())
    ('cp1252', [(1, ['t (µs)', 'F']), (2, ['0', '1']), (4, ['1', '2'])])
    >>> _ = path.write_bytes(b"t,F\n0,1\r2\n")
    >>> TextFile(path)
    Traceback (most recent call last):
    ...
    tactilecal.TactilecalError: line 2 of ...lc.csv: a carriage return (CR) inside the line; ...
    """

    def __init__(self, path, *, expected="a text file"):
        if os.path.exists(path) and not os.path.isfile(path):
            raise TextFault.not_a_file(path, expected)
        self.path, self.name = path, str(path)
        with open(path, "rb") as f:
            first = f.read(max(PIECE_BYTES, 4))  # room for a byte-order mark
            pieces = _pieces(f, first)
            codec = next((codec for bom, codec in _BOMS if first.startswith(bom)), None)
            if codec is None:
                self.codec, lone_cr = self._check_plain(pieces, expected)
            else:
                self.codec, lone_cr = codec, self._check_bom(pieces, codec, expected)
        if lone_cr is not None:
            raise TextFault.lone_cr(lone_cr, self.name)

    def _check_plain(self, pieces, expected):
        """Bytes without byte-order mark: NUL first, then UTF-8, else cp1252; the first lone CR."""
        decoder = codecs.getincrementaldecoder("utf-8")()
        read, lines, not_utf8, cp1252, lone_cr = 0, 0, None, True, _LoneCR()
        for piece in pieces:
            nul = piece.find(b"\x00")
            if nul >= 0:
                raise TextFault.nul_byte(lines + piece.count(b"\n", 0, nul) + 1, self.name,
                                         expected)
            read += len(piece)
            if not_utf8 is None:
                try:
                    decoder.decode(piece, final=not piece)
                except UnicodeDecodeError as exc:
                    not_utf8 = read - len(exc.object) + exc.start
            cp1252 = cp1252 and (piece.isascii() or not _CP1252_UNDEFINED.search(piece))
            lone_cr.feed(piece, lines, not piece)
            lines += piece.count(b"\n")
        if not_utf8 is None:
            return "utf-8", lone_cr.line
        if not cp1252:
            with open(self.path, "rb") as f:
                f.seek(not_utf8)
                byte = f.read(1)[0]
            raise TextFault.not_text(self._line_of(not_utf8), self.name, byte, expected)
        return "cp1252", lone_cr.line

    def _check_bom(self, pieces, codec, expected):
        """Text after a byte-order mark: ``codec`` first, then NUL; return the first lone CR."""
        decoder = codecs.getincrementaldecoder(codec)()
        read, lines, nul_line, lone_cr, start = 0, 0, None, _LoneCR(), True
        for piece in pieces:
            read += len(piece)
            try:
                text = decoder.decode(piece, final=not piece)
            except UnicodeDecodeError as exc:
                line = self._line_of(read - len(exc.object) + exc.start)
                raise TextFault.not_in_bom_codec(line, self.name, codec, expected) from None
            if start and text:
                text, start = without_bom(text), False
            nul = text.find("\x00") if nul_line is None else -1
            if nul >= 0:
                nul_line = lines + text.count("\n", 0, nul) + 1
            lone_cr.feed(text, lines, not piece)
            lines += text.count("\n")
        if nul_line is not None:
            raise TextFault.nul_character(nul_line, self.name, expected)
        return lone_cr.line

    def _line_of(self, offset):
        """Line of the byte at ``offset``: LF bytes before it + 1 (as ``decode_text`` counts)."""
        count = 0
        with open(self.path, "rb") as f:
            while offset > 0:
                piece = f.read(min(PIECE_BYTES, offset))
                if not piece:
                    break
                count += piece.count(b"\n")
                offset -= len(piece)
        return count + 1

    def _text(self):
        return io.TextIOWrapper(open(self.path, "rb"), encoding=self.codec, newline="\n")

    def lines(self):
        """Yield the lines of the text with their line ends (LF or CR LF), one at a time."""
        with self._text() as text:
            first = next(text, "")
            first = without_bom(first)
            if first:
                yield first
            yield from text

    def rows(self):
        """Yield ``(line number, cells)`` as :func:`~tactilecal._validate.csv_rows` does."""
        return csv_lines_rows(self.lines(), self.name)

    def utf8(self):
        """Return a binary file of the text in UTF-8 (the file itself when it is UTF-8)."""
        if self.codec == "utf-8":
            return open(self.path, "rb")
        return io.BufferedReader(_Utf8(self._text()), buffer_size=2**16)


def _pieces(f, first):
    """Yield ``first``, then pieces of ``f`` until its end, then ``b""`` once."""
    piece = first
    while piece:
        yield piece
        piece = f.read(PIECE_BYTES)
    yield b""


class _LoneCR:
    """The line of the first CR not followed by LF, found piece by piece (str or bytes)."""

    def __init__(self):
        self.line, self._pending = None, None

    def feed(self, piece, lines, final):
        """Look at the next ``piece``, ``lines`` LF before it (``final``: the file ends)."""
        if self.line is not None or not (piece or final):
            return
        if self._pending is not None:  # the last piece ended with CR
            if piece[:1] in ("\n", b"\n"):
                self._pending = None
            else:
                self.line = self._pending
                return
        found = _LONE_CR[type(piece)].search(piece)
        if found is None:
            return
        line = lines + piece.count("\n" if isinstance(piece, str) else b"\n", 0,
                                   found.start()) + 1
        if found.start() == len(piece) - 1:
            self._pending = line  # LF may start the next piece
        else:
            self.line = line


class _Utf8(io.RawIOBase):
    """The text of a ``TextIOWrapper`` as UTF-8 bytes, a piece at a time."""

    def __init__(self, text):
        super().__init__()
        self._text, self._data, self._at, self._start = text, b"", 0, True

    def readable(self):
        return True

    def readinto(self, buffer):
        while self._at == len(self._data):
            text = self._text.read(max(1, PIECE_BYTES // 4))
            if not text:
                return 0
            if self._start:
                text, self._start = without_bom(text), False
            self._data, self._at = text.encode("utf-8"), 0
        n = min(len(buffer), len(self._data) - self._at)
        buffer[:n] = self._data[self._at:self._at + n]
        self._at += n
        return n

    def close(self):
        if not self.closed:
            self._text.close()
        super().close()
