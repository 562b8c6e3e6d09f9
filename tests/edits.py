"""Hypothesis strategy shared by the property tests: a file's bytes, a few of them edited.

Imported by name (``from edits import byte_edits``): ``tests`` is on pytest's ``pythonpath``.
"""

from hypothesis import strategies as st

#: Bytes an edit writes (besides any one byte): the characters of numbers and CSV structure,
#: quotes, NUL and bytes that are not UTF-8.
EDIT_BYTES = b",.-+eE0123456789\r\n \t\"_\x00\xff\x81"


@st.composite
def byte_edits(draw, raw, alphabet=EDIT_BYTES):
    """``raw`` with one to three bytes replaced, inserted or deleted (from ``alphabet``,
    or any byte)."""
    data = bytearray(raw)
    for _ in range(draw(st.integers(1, 3))):
        at = draw(st.integers(0, max(len(data) - 1, 0)))
        byte = draw(st.sampled_from(list(alphabet) + [draw(st.integers(0, 255))]))
        what = draw(st.sampled_from(["replace", "insert", "delete"]))
        if what == "replace" and data:
            data[at] = byte
        elif what == "insert":
            data.insert(at, byte)
        elif data:
            del data[at]
    return bytes(data)
