"""What a file holds, from its first bytes: the one place that sniffs file contents.

:func:`tactilecal.io.recording_format` tells recordings apart with it, and the writers
(:mod:`tactilecal._atomic`) with it refuse to replace a file that is not an output of theirs.
"""

from pathlib import Path

__all__ = ["SNIFF_BYTES", "NETCDF_MAGIC", "ZARR_METADATA", "sniff", "is_zarr_store"]

SNIFF_BYTES = 1 << 16
"""Bytes read from the start of a file to tell what it is."""

NETCDF_MAGIC = (b"\x89HDF\r\n\x1a\n", b"CDF\x01", b"CDF\x02", b"CDF\x05")
ZARR_METADATA = ("zarr.json", ".zgroup", ".zarray")
_PNG_MAGIC = b"\x89PNG\r\n\x1a\n"
_GIF_MAGIC = b"GIF8"
_UTF16_BOMS = (b"\xff\xfe", b"\xfe\xff")


def is_zarr_store(path):
    """Return True if the folder ``path`` holds Zarr metadata (format 2 or 3)."""
    path = Path(path)
    return path.is_dir() and any((path / name).is_file() for name in ZARR_METADATA)


def sniff(path):
    r"""Return what ``path`` holds: a kind below, or None when it does not exist.

    ``"zarr"`` (a folder with Zarr metadata), ``"folder"`` (any other folder), ``"netcdf"``
    (HDF5 or NetCDF3 signature), ``"png"``, ``"movie"`` (a GIF or an MP4), ``"tekscan"``
    (``ASCII_DATA`` in the first 64 KiB, in UTF-8, cp1252 or UTF-16 with its byte-order
    mark), ``"json"`` (text starting with ``{`` or ``[``), ``"html"`` (text starting with
    ``<!doctype html`` or ``<html``),
    ``"text"`` (any other text), ``"empty"``, ``"binary"`` (NUL bytes without a UTF-16
    byte-order mark) or ``"special"`` (a device, pipe or socket).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> folder = pathlib.Path(tempfile.mkdtemp())
    >>> _ = (folder / "a.csv").write_text("ROWS 1\nCOLS 1\nASCII_DATA @@\nFrame 1\n3\n@@\n")
    >>> _ = (folder / "cal.json").write_text('{"format": "tactilecal-calibration/1"}')
    >>> sniff(folder / "a.csv"), sniff(folder / "cal.json"), sniff(folder / "none.csv")
    ('tekscan', 'json', None)
    """
    path = Path(path)
    if path.is_dir():
        return "zarr" if is_zarr_store(path) else "folder"
    if not path.exists():
        return None
    if not path.is_file():
        return "special"
    with path.open("rb") as fh:
        head = fh.read(SNIFF_BYTES)
    if not head:
        return "empty"
    if head.startswith(NETCDF_MAGIC):
        return "netcdf"
    if head.startswith(_PNG_MAGIC):
        return "png"
    if head.startswith(_GIF_MAGIC) or head[4:8] == b"ftyp":  # GIF87a/89a, ISO base media
        return "movie"
    if head.startswith(_UTF16_BOMS):
        head = head[:len(head) // 2 * 2].decode("utf-16", errors="replace").encode("utf-8")
    elif b"\x00" in head:
        return "binary"
    if b"ASCII_DATA" in head.upper():
        return "tekscan"
    start = head.removeprefix(b"\xef\xbb\xbf").lstrip()[:16].lower()
    if start.startswith((b"{", b"[")):
        return "json"
    if start.startswith((b"<!doctype html", b"<html")):
        return "html"
    return "text"
