"""Property-based tests of the Tekscan reader (Hypothesis): exports of every layout.

Generated exports (I-Scan CSV with times and ``Raw Sum``, F-Scan ASF without, single frames
without a frame line; raw or kPa; LF or CRLF) are written here from their known values, so a
read is compared with the truth, not with another reader. Mutations of three kinds:

- neutral ones (byte-order mark, UTF-16, spaces around values and ``B``, blank lines, a
  lazy read) must read to the same recording;
- breaking ones (a frame block deleted or repeated, a bad time, NUL, a lone CR, a value out
  of range, a row too long or short, truncation) must raise :class:`TactilecalError` naming
  the file, on one line of at most 300 characters;
- arbitrary byte edits must do one or the other: read a recording the format allows, or
  raise that error.

The profile (``tests/conftest.py``) sets how many examples run: a few dozen in the suite,
thousands with ``TACTILECAL_HYPOTHESIS=long``.
"""

import itertools
from dataclasses import dataclass

import numpy as np
import pytest
from edits import byte_edits
from hypothesis import assume, given
from hypothesis import strategies as st

from tactilecal import TactilecalError
from tactilecal._errors import MAX_MESSAGE
from tactilecal.io import read_tekscan, write_tekscan

SPF = ("0.1", "0.032", "0.01")


@dataclass
class Export:
    """A generated export: its text and the recording it holds."""

    text: str
    values: np.ndarray
    frames: np.ndarray
    times: np.ndarray
    layout: str
    raw: bool
    newline: str


@st.composite
def exports(draw, layouts=("iscan", "fscan", "single")):
    layout = draw(st.sampled_from(layouts))
    rows, cols = draw(st.integers(1, 4)), draw(st.integers(1, 5))
    n = 1 if layout == "single" else draw(st.integers(1, 4))
    raw = draw(st.booleans())
    first = draw(st.integers(0, 10**6))
    spf = draw(st.sampled_from(SPF))
    shape = np.array(draw(st.lists(st.booleans(), min_size=rows * cols,
                                   max_size=rows * cols))).reshape(rows, cols)
    if raw:
        cells = st.integers(0, 255).map(str)
    else:  # calibrated values as Tekscan writes them: decimals, integers, 0
        cells = st.one_of(st.integers(0, 3000).map(str),
                          st.decimals(0, 2000, places=2).map(str))
    tokens = [[["B" if shape[r, c] else draw(cells) for c in range(cols)] for r in range(rows)]
              for _ in range(n)]
    values = np.array([[[np.nan if t == "B" else float(t) for t in row] for row in frame]
                       for frame in tokens], dtype=np.float64)
    steps = draw(st.lists(st.sampled_from([float(spf), float(spf) + 0.01]), min_size=n,
                          max_size=n))
    time_text = [f"{t:.3f}" for t in np.cumsum([0.0] + steps[:-1])]
    newline = draw(st.sampled_from(["\n", "\r\n"]))
    header = ["DATA_TYPE MOVIE", "SENSOR_TYPE 6900", f"ROWS {rows}", f"COLS {cols}",
              "ROW_SPACING 0.127 centimeters", "COL_SPACING 0.127 centimeters",
              "SENSEL_AREA 0.016129 cm2", "NOISE_THRESHOLD 3", f"SECONDS_PER_FRAME {spf}",
              f"START_FRAME {first}", f"END_FRAME {first + n - 1}",
              f"UNITS {'raw' if raw else 'KPa'}", "ASCII_DATA @@", ""]
    lines = list(header)
    for k in range(n):
        if layout == "iscan":
            line = f"Frame {first + k}, {time_text[k]},, 12/2/2019 6:21:52.34PM"
            if raw:
                line += f",,,Raw Sum=,,{int(np.nansum(values[k]))}"
            lines.append(line)
        elif layout == "fscan":
            lines.append(f"Frame {first + k}")
        lines.extend(",".join(row) for row in tokens[k])
        lines.append("")
    lines.append("@@")
    times = (np.array([float(t) for t in time_text]) if layout == "iscan"
             else np.arange(n) * float(spf))
    return Export(newline.join(lines) + newline, values, np.arange(first, first + n), times,
                  layout, raw, newline)


_COUNT = itertools.count()


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    """One folder for the module's files (Hypothesis runs many examples per test call)."""
    return tmp_path_factory.mktemp("properties")


def _write(folder, export, data=None, name="export.csv"):
    """Write the export (or ``data``) under a new name: a failing example's file is kept."""
    path = folder / f"{next(_COUNT)}-{name}"
    path.write_bytes(export.text.encode() if data is None else data)
    return path


def _assert_reads_as(data, export):
    np.testing.assert_array_equal(data.values, export.values)
    assert data.frame.values.tolist() == export.frames.tolist()
    assert data.time.values.tolist() == export.times.tolist()
    assert data.attrs["units"] == ("raw" if export.raw else "kPa")
    assert data.dims == ("frame", "row", "col")


def _assert_clean_error(exc, path):
    message = str(exc)
    assert isinstance(exc, TactilecalError), f"{type(exc).__name__}: {message}"
    assert path.name in message, message
    assert "\n" not in message and len(message) <= MAX_MESSAGE, message


def _assert_allowed(data, path):
    """What a read may hold: the format's rules (``docs/data-model.md``)."""
    values = data.values
    assert not np.isinf(values).any()
    if data.attrs["units"] == "raw":
        finite = values[np.isfinite(values)]
        assert ((finite >= 0) & (finite <= 255) & (finite == np.floor(finite))).all()
    frames, times = data.frame.values, data.time.values
    assert (np.diff(frames) == 1).all()
    if "seconds_per_frame" not in data.attrs:  # documented: only the first time is known
        times = times[np.isfinite(times)] if np.isnan(times[1:]).all() else times
    assert np.isfinite(times).all() and (times >= 0).all() and (np.diff(times) > 0).all()
    header = {k[len("tekscan_"):]: v for k, v in data.attrs.items() if k.startswith("tekscan_")}
    assert values.shape[1:] == (int(header["ROWS"]), int(header["COLS"]))
    if "START_FRAME" in header:
        assert int(header["START_FRAME"]) == frames[0]
    if "END_FRAME" in header:
        assert int(header["END_FRAME"]) == frames[-1]
    assert data.attrs["source"] == str(path)


# ----------------------------------------------------------------------------- round trips
@given(exports())
def test_generated_exports_read_to_their_values(folder, export):
    _assert_reads_as(read_tekscan(_write(folder, export)), export)


@given(exports(), st.integers(1, 3))
def test_a_lazy_read_is_the_eager_read(folder, export, chunks):
    path = _write(folder, export)
    assert read_tekscan(path, chunks=chunks).compute().identical(read_tekscan(path))


@given(exports(), st.sampled_from(["\n", "\r\n"]))
def test_write_tekscan_then_read_tekscan_is_the_identity(folder, export, newline):
    data = read_tekscan(_write(folder, export))
    out = folder / f"{next(_COUNT)}-written.asf"
    write_tekscan(data, out, newline=newline)
    back = read_tekscan(out)
    np.testing.assert_array_equal(back.values, data.values)
    assert back.frame.values.tolist() == data.frame.values.tolist()
    assert back.time.values.tolist() == data.time.values.tolist()
    assert {k: v for k, v in back.attrs.items() if k != "source"} == \
        {k: v for k, v in data.attrs.items() if k != "source"}


# ----------------------------------------------------------------------------- neutral edits
def _rows(lines):
    return [k for k, line in enumerate(lines) if line[:1].isdigit() or line[:1] == "B"]


@st.composite
def neutral_edits(draw, export):
    """Return ``(name, bytes)`` of an edit that must not change what the export holds."""
    kind = draw(st.sampled_from(["utf-8-sig", "utf-16", "utf-16-be", "spaces", "blank lines",
                                 "leading zeros", "trailing space"]))
    text, nl = export.text, export.newline
    if kind == "utf-8-sig":
        return kind, text.encode("utf-8-sig")
    if kind == "utf-16":
        return kind, text.encode("utf-16")
    if kind == "utf-16-be":
        return kind, b"\xfe\xff" + text.encode("utf-16-be")
    lines = text.split(nl)
    rows = _rows(lines)
    k = draw(st.sampled_from(rows))
    cells = lines[k].split(",")
    j = draw(st.integers(0, len(cells) - 1))
    if kind == "spaces":
        cells[j] = draw(st.sampled_from([" ", "\t", "  "])) + cells[j] + \
            draw(st.sampled_from(["", " ", "\t"]))
    elif kind == "leading zeros" and cells[j] != "B":
        cells[j] = "00" + cells[j]
    elif kind == "trailing space":
        cells[-1] += " "
    lines[k] = ",".join(cells)
    if kind == "blank lines":
        at = draw(st.sampled_from(rows + [len(lines) - 1]))
        lines.insert(at, "")
    return kind, nl.join(lines).encode()


@given(st.data())
def test_neutral_edits_read_to_the_same_recording(folder, data):
    export = data.draw(exports())
    kind, edited = data.draw(neutral_edits(export))
    path = _write(folder, export, edited)
    _assert_reads_as(read_tekscan(path), export)


# ----------------------------------------------------------------------------- breaking edits
@st.composite
def breaking_edits(draw, export):
    """Return ``(name, bytes)`` of an edit that makes the export invalid."""
    text, nl = export.text, export.newline
    lines = text.split(nl)
    frame_lines = [k for k, line in enumerate(lines) if line.startswith("Frame")]
    rows = _rows(lines)
    kinds = ["nul", "lone cr", "undefined byte", "long row", "short row", "truncated",
             "end frame", "not a number"]
    if export.raw:
        kinds.append("raw out of range")
    if len(frame_lines) >= 2:
        kinds += ["frame deleted", "frame repeated"]
    if export.layout == "iscan":
        kinds.append("bad time")
    if export.layout == "fscan" and len(frame_lines) >= 2:
        kinds.append("stray time")
    kind = draw(st.sampled_from(kinds))
    body = text.index("ASCII_DATA @@")
    if kind == "nul":
        at = draw(st.integers(0, len(text) - 1))
        return kind, (text[:at] + "\x00" + text[at:]).encode()
    if kind == "undefined byte":
        at = draw(st.integers(0, len(text) - 1))
        byte = draw(st.sampled_from([b"\x81", b"\x8d", b"\x8f", b"\x90", b"\x9d"]))
        return kind, text[:at].encode() + byte + text[at:].encode()
    if kind == "lone cr":
        at = draw(st.integers(0, len(text) - 2))
        assume(text[at] != "\n" and text[at:at + 1] != "\r" and text[at - 1:at] != "\r")
        return kind, (text[:at] + "\r" + text[at:]).encode()
    if kind == "truncated":
        at = draw(st.integers(body, text.rindex("@@") - 1))
        return kind, text[:at].encode()
    if kind == "end frame":
        shift = draw(st.sampled_from([-1, 1, 7]))
        assume(export.frames[-1] + shift >= 0)
        return kind, text.replace(f"END_FRAME {export.frames[-1]}",
                                  f"END_FRAME {export.frames[-1] + shift}").encode()
    if kind in ("frame deleted", "frame repeated"):
        i = draw(st.integers(0, len(frame_lines) - 1))
        start = frame_lines[i]
        stop = frame_lines[i + 1] if i + 1 < len(frame_lines) else lines.index("@@")
        block = lines[start:stop]
        lines[start:stop] = [] if kind == "frame deleted" else block + block
        return kind, nl.join(lines).encode()
    if kind == "bad time":
        k = draw(st.sampled_from(frame_lines))
        bad = draw(st.sampled_from(["nan", "inf", "-1", "x", "1_0", "-5"]))
        parts = lines[k].split(",")
        if bad == "-5" and k == frame_lines[0]:
            bad = "-1"
        parts[1] = " " + bad if bad != "-5" else " " + str(float(parts[1]) - 5)
        lines[k] = ",".join(parts)
        return kind, nl.join(lines).encode()
    if kind == "stray time":
        k = draw(st.sampled_from(frame_lines))
        lines[k] += draw(st.sampled_from([", -5", ", 1.5", ", nan"]))
        return kind, nl.join(lines).encode()
    k = draw(st.sampled_from(rows))
    cells = lines[k].split(",")
    j = draw(st.integers(0, len(cells) - 1))
    if kind == "long row":
        cells.insert(j, draw(st.sampled_from(["0", "B", ""])))
    elif kind == "short row":
        assume(len(cells) > 1)
        del cells[j]
    elif kind == "not a number":
        cells[j] = draw(st.sampled_from(["x", "nan", "inf", "1_0", "0x1", "--1", "1e", "BB"]))
    elif kind == "raw out of range":
        cells[j] = draw(st.sampled_from(["256", "-1", "0.5", "1e3", "300"]))
    lines[k] = ",".join(cells)
    return kind, nl.join(lines).encode()


@given(st.data())
def test_breaking_edits_are_errors_naming_the_file(folder, data):
    export = data.draw(exports())
    kind, edited = data.draw(breaking_edits(export))
    path = _write(folder, export, edited)
    try:
        read_tekscan(path)
    except Exception as exc:  # noqa: BLE001 - the class is what is tested
        _assert_clean_error(exc, path)
    else:
        raise AssertionError(f"{kind}: read without an error")


# ----------------------------------------------------------------------------- any edit
#: An export's bytes to edit in: a number's, a row's, a frame line's and the terminator's.
EXPORT_BYTES = b",.-+eE0123456789B\r\n \t@F_\x00\xff\x81"


@given(st.data())
def test_any_byte_edit_reads_to_allowed_values_or_is_a_clean_error(folder, data):
    export = data.draw(exports())
    path = _write(folder, export, data.draw(byte_edits(export.text.encode(), EXPORT_BYTES)))
    try:
        recording = read_tekscan(path)
    except Exception as exc:  # noqa: BLE001 - the class is what is tested
        _assert_clean_error(exc, path)
    else:
        _assert_allowed(recording, path)


@given(st.data())
def test_a_lazy_read_of_any_byte_edit_agrees_with_the_eager_read(folder, data):
    export = data.draw(exports(layouts=("iscan", "fscan")))
    path = _write(folder, export, data.draw(byte_edits(export.text.encode(), EXPORT_BYTES)))
    outcomes = []
    for chunks in (None, 2):
        try:
            outcomes.append(read_tekscan(path, chunks=chunks).compute())
        except TactilecalError as exc:
            _assert_clean_error(exc, path)
            outcomes.append("error")
    eager, lazy = outcomes
    if isinstance(eager, str) or isinstance(lazy, str):  # the same bytes are refused lazily
        assert isinstance(eager, str) and isinstance(lazy, str), (eager, lazy)
    else:
        assert eager.identical(lazy)
