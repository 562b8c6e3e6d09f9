"""The NumPy reader of plain exports (issue 16) against the numba reader it stands in for.

Known truth: the numba reader (forced with ``PLAIN_MAX_BYTES = 0``) defines the result and
every error message; the NumPy reader must give an identical DataArray, or hand the file
over (``read_plain`` returns None) so that the numba reader's message is raised unchanged.
"""

import math
import random
import re
import subprocess
import sys

import numpy as np
import pytest
from hypothesis import example, given
from hypothesis import strategies as st

from tactilecal.io import _tekscan_numpy, _tekscan_read, read_tekscan
from tactilecal.io._tekscan_layout import read_header


def _numba_read(path, monkeypatch):
    with monkeypatch.context() as patch:
        patch.setattr(_tekscan_read, "PLAIN_MAX_BYTES", 0)
        return read_tekscan(path)


def _plain(path):
    with open(path, "rb") as f:
        return _tekscan_numpy.read_plain(f, str(path), read_header(f, str(path)))


def _outcome(read, path):
    try:
        return read(path)
    except (ValueError, TypeError) as exc:
        return f"{type(exc).__name__}: {exc}"


def _movie(tmp_path, values, *, newline="\n", units="raw", frame_lines=True, name="m.csv",
           text=lambda v: str(int(v))):
    n, rows, cols = values.shape
    lines = [f"ROWS {rows}", f"COLS {cols}", f"UNITS {units}", "SECONDS_PER_FRAME 0.01",
             "START_FRAME 1", f"END_FRAME {n}", "ASCII_DATA @@", ""]
    for k in range(n):
        if frame_lines:
            lines.append(f"Frame {k + 1}, {k * 0.01:.2f},, 1/1/2020 1:00:00.00PM,,,"
                         f"Raw Sum=,,{np.nansum(values[k]):.0f}")
        lines += [",".join("B" if np.isnan(v) else text(v) for v in row)
                  for row in values[k]]
        lines.append("")
    path = tmp_path / name
    path.write_bytes((newline.join(lines + ["@@"]) + newline).encode())
    return path


def _raw(n=12, rows=5, cols=7, seed=0, high=256):
    values = np.random.default_rng(seed).integers(0, high, size=(n, rows, cols)).astype(float)
    values[:, 0, :2] = np.nan
    return values


@pytest.mark.parametrize("newline", ["\n", "\r\n"])
@pytest.mark.parametrize("block_bytes", [1, 37, 1000, 2**21])
def test_plain_movie_reads_as_the_numba_reader_reads_it(tmp_path, monkeypatch, newline,
                                                        block_bytes):
    values = _raw()
    path = _movie(tmp_path, values, newline=newline)
    expected = _numba_read(path, monkeypatch)
    monkeypatch.setattr(_tekscan_numpy, "BLOCK_BYTES", block_bytes)
    assert _plain(path) is not None  # the NumPy reader took it
    data = read_tekscan(path)
    np.testing.assert_array_equal(data.values, values)
    assert data.identical(expected)


@pytest.mark.parametrize("frame_line", ["I-Scan", "F-Scan"])
@pytest.mark.parametrize("newline", ["\n", "\r\n"])
@pytest.mark.parametrize("cores", [2, 3, 5])
def test_parts_on_threads_read_as_the_numba_reader_reads_it(tmp_path, monkeypatch, cores,
                                                            newline, frame_line):
    """The data cut into one part per core, at frame lines found after evenly spaced bytes."""
    from tactilecal.io._tekscan_index import index_export

    values = _raw(n=40, seed=cores)
    path = _movie(tmp_path, values, newline=newline)
    if frame_line == "F-Scan":  # "Frame N" alone
        path.write_bytes(re.sub(rb"(Frame \d+),[^\r\n]*", rb"\1", path.read_bytes()))
    expected = _numba_read(path, monkeypatch)
    monkeypatch.setattr(_tekscan_numpy.os, "cpu_count", lambda: cores)
    monkeypatch.setattr(_tekscan_numpy, "PART_BYTES", 64)
    monkeypatch.setattr(_tekscan_numpy, "BLOCK_BYTES", 300)
    parts = []
    run = _tekscan_numpy._run
    monkeypatch.setattr(_tekscan_numpy, "_run",
                        lambda parsers, fd: parts.append(len(parsers)) or run(parsers, fd))
    _, plain = _plain(path)
    assert parts == [cores]
    assert read_tekscan(path).identical(expected)
    with open(path, "rb") as f:
        numba = index_export(f, str(path), whole=True, header=read_header(f, str(path)))
    np.testing.assert_array_equal(plain.lines, numba.lines)
    np.testing.assert_array_equal(plain.starts, numba.starts)


@pytest.mark.parametrize("old, new", [
    (b"Frame 21,", b"Frame 22,"),  # a cut's frame number that does not follow
    (b"\nFrame 21,", b"\n1,2,3,4,5,6,7\nFrame 21,"),  # a row too many before a cut
    (b"\n@@", b"\nFrame 41,\n@@"),  # a frame line too many at the end
])
def test_parts_that_do_not_join_go_to_the_numba_reader(tmp_path, monkeypatch, old, new):
    values = _raw(n=40)
    path = _movie(tmp_path, values)
    path.write_bytes(path.read_bytes().replace(old, new, 1))
    monkeypatch.setattr(_tekscan_numpy.os, "cpu_count", lambda: 2)
    monkeypatch.setattr(_tekscan_numpy, "PART_BYTES", 64)
    assert _plain(path) is None
    assert str(_outcome(read_tekscan, path)) == str(
        _outcome(lambda p: _numba_read(p, monkeypatch), path))


def test_a_part_that_departs_stops_the_others(tmp_path, monkeypatch):
    """A decimal in the first part: the second stops at its next block, not at its end."""
    values = _raw(n=40)
    values[:, 1:, :2] = 17
    path = _movie(tmp_path, values)
    path.write_bytes(path.read_bytes().replace(b"\n17,", b"\n17.5,", 1))
    monkeypatch.setattr(_tekscan_numpy.os, "cpu_count", lambda: 2)
    monkeypatch.setattr(_tekscan_numpy, "PART_BYTES", 64)
    monkeypatch.setattr(_tekscan_numpy, "BLOCK_BYTES", 200)
    parsed = []
    block = _tekscan_numpy._Parser._block

    def slow_block(parser, padded, base, last):
        if parser.k0:  # the second part waits for the first to fail
            assert parser.failed.wait(timeout=30)
        parsed.append(parser.k0)
        return block(parser, padded, base, last)

    monkeypatch.setattr(_tekscan_numpy._Parser, "_block", slow_block)
    assert _plain(path) is None
    assert 1 <= sum(k > 0 for k in parsed) <= 2  # a block in hand when it was told to stop


@pytest.mark.parametrize("block_bytes", [1, 1000, 2**21])
def test_plain_reader_numbers_lines_and_offsets_as_the_numba_reader(tmp_path, monkeypatch,
                                                                     block_bytes):
    """Error messages after the parse (frame times, frame range) cite these line numbers."""
    from tactilecal.io._tekscan_index import index_export

    path = _movie(tmp_path, _raw(), newline="\r\n")
    monkeypatch.setattr(_tekscan_numpy, "BLOCK_BYTES", block_bytes)
    _, plain = _plain(path)
    with open(path, "rb") as f:
        numba = index_export(f, str(path), whole=True, header=read_header(f, str(path)))
    np.testing.assert_array_equal(plain.lines, numba.lines)
    np.testing.assert_array_equal(plain.starts, numba.starts)
    np.testing.assert_array_equal(plain.numbers, numba.numbers)


@pytest.mark.parametrize("new", [
    b"Sum=,,",  # a frame line without its Raw Sum: the block is parsed line by line
    b"Raw Sum=,,{sum},,Raw Sum=,,",  # two in one line (the first is the sum)
])
def test_frame_lines_with_and_without_raw_sum_read_as_numba_reads_them(tmp_path, monkeypatch,
                                                                        new):
    values = _raw()
    path = _movie(tmp_path, values)
    text = path.read_bytes()
    at = text.index(b"Frame 3")
    new = new.replace(b"{sum}", b"%d" % np.nansum(values[2]))
    path.write_bytes(text[:at] + text[at:].replace(b"Raw Sum=,,", new, 1))
    assert _plain(path) is not None  # the NumPy reader took it
    assert read_tekscan(path).identical(_numba_read(path, monkeypatch))


@pytest.mark.parametrize("high, units", [(10**4, "kPa"), (10**8, "kPa"), (10**15, "kPa")])
def test_whole_numbers_of_up_to_15_digits_read_exactly(tmp_path, monkeypatch, high, units):
    """4, 8 and 15 digits: the 32-bit and 64-bit words, and past 8 digits the decimal
    reader's words."""
    values = _raw(high=high, seed=3)
    values[0, 1, :3] = [0, high - 1, 7]
    path = _movie(tmp_path, values, units=units)
    assert _plain(path) is not None
    data = read_tekscan(path)
    np.testing.assert_array_equal(data.values, values)
    assert data.identical(_numba_read(path, monkeypatch))


def test_single_frame_without_frame_line(tmp_path, monkeypatch):
    values = _raw(n=1)
    path = _movie(tmp_path, values, frame_lines=False)
    assert _plain(path) is not None
    assert read_tekscan(path).identical(_numba_read(path, monkeypatch))


@pytest.mark.parametrize("fixture", ["iscan_csv", "fscan_asf", "fscan_right_asf"])
def test_real_exports_are_plain_and_read_the_same(request, monkeypatch, fixture):
    path = request.getfixturevalue(fixture)
    assert _plain(path) is not None
    assert read_tekscan(path).identical(_numba_read(path, monkeypatch))


@pytest.mark.parametrize("old, new", [
    (b"\n17,", b"\n17.5,"),           # a decimal
    (b"\n17,", b"\n+17,"),            # a sign
    (b"\n17,", b"\n 17,"),            # a space
    (b",17,", b",1_7,"),              # an underscore
    (b",17,", b",17\r,"),             # a lone CR
    (b",17,", b",,"),                 # an empty value
    (b",17,", b",17,1,"),             # one value too many
    (b",17,", b",256,"),              # not a raw reading
    (b"Raw Sum=,,", b"Raw Sum=,,1"),  # a Raw Sum that is not the frame's sum
    (b"Frame 2,", b"Frame 1,"),       # frame numbers not increasing
    (b"Frame 2,", b"Frame \xc2\xb2,"),  # not ASCII
    (b"\n@@", b"\n@@ end"),           # a bad terminator
    (b"\n@@", b"\nnot a row\n@@"),    # an unknown line
])
def test_a_departure_from_the_plain_form_goes_to_the_numba_reader(tmp_path, monkeypatch,
                                                                   old, new):
    values = _raw(n=3, rows=4, cols=5)
    values[:, 1:, :2] = 17
    path = _movie(tmp_path, values)
    text = path.read_bytes()
    assert old in text
    path.write_bytes(text.replace(old, new, 1))
    assert _plain(path) is None
    assert str(_outcome(read_tekscan, path)) == str(
        _outcome(lambda p: _numba_read(p, monkeypatch), path))


def test_huge_rows_and_cols_are_refused_before_allocating(tmp_path):
    path = _movie(tmp_path, _raw(n=2))
    path.write_bytes(path.read_bytes().replace(b"ROWS 5", b"ROWS 100000000"))
    assert _plain(path) is None  # 2e9 values cannot fit in the file: not even allocated


@pytest.mark.parametrize("cores", [1, 2])
@pytest.mark.parametrize("n_mutations", [150, pytest.param(600, marks=pytest.mark.slow)])
def test_mutated_exports_read_or_fail_as_with_the_numba_reader(fuzz, tmp_path, monkeypatch,
                                                               cores, n_mutations):
    """Seeded mutations (byte flips, lines dropped or repeated, lone CR, hostile cells), read
    as one part, or as one part per core of two; a longer run with -m slow."""
    monkeypatch.setattr(_tekscan_numpy.os, "cpu_count", lambda: cores)
    monkeypatch.setattr(_tekscan_numpy, "PART_BYTES", 64)
    seeds = [path for kind, path in fuzz.make_seeds(tmp_path / "seeds") if kind == "recording"]
    rng = random.Random(16)
    taken = 0
    for k in range(n_mutations):
        source = seeds[k % len(seeds)]
        mutated, what = fuzz.mutate(rng, "recording", source.read_bytes())
        path = tmp_path / f"mutant{source.suffix}"
        path.write_bytes(mutated)
        try:
            taken += _plain(path) is not None
        except ValueError:  # the header is refused: one function for both readers
            pass
        ours = _outcome(read_tekscan, path)
        theirs = _outcome(lambda p: _numba_read(p, monkeypatch), path)
        if isinstance(ours, str) or isinstance(theirs, str):
            assert ours == theirs, what
        else:
            assert ours.identical(theirs), what
    assert 0.1 * n_mutations <= taken <= 0.9 * n_mutations  # both readers were exercised


def test_a_plain_export_is_read_without_importing_numba_dask_scipy_or_matplotlib(tmp_path):
    """What a cold read pays for: xarray's dask check alone imported dask.array and SciPy."""
    path = _movie(tmp_path, _raw())
    code = ("import sys; from tactilecal.io import read_tekscan; "
            f"read_tekscan({str(path)!r}); "
            "print(*[m in sys.modules for m in ('numba', 'dask', 'scipy', 'matplotlib')])")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True)
    assert out.stdout.split() == ["False"] * 4


def test_frames_missing_from_the_numbering_go_to_the_numba_reader(tmp_path, monkeypatch):
    """END_FRAME - START_FRAME + 1 sizes the result; a gap (frames 1, 2, 4) is no plain file,
    and the numba reader refuses it naming the line."""
    path = _movie(tmp_path, _raw(n=3))
    text = path.read_bytes().replace(b"Frame 3,", b"Frame 4,").replace(b"END_FRAME 3",
                                                                        b"END_FRAME 4")
    path.write_bytes(text)
    assert _plain(path) is None
    with pytest.raises(ValueError, match=r"line \d+ of .*: frame 4 follows frame 2"):
        read_tekscan(path)


def test_an_export_above_the_size_limit_goes_to_the_numba_reader(tmp_path, monkeypatch):
    path = _movie(tmp_path, _raw())
    expected = read_tekscan(path)

    def refuse(*args):
        raise AssertionError("the NumPy reader was tried")

    monkeypatch.setattr(_tekscan_numpy, "read_plain", refuse)
    monkeypatch.setattr(_tekscan_read, "PLAIN_MAX_BYTES", path.stat().st_size // 2)
    assert read_tekscan(path).identical(expected)


_TOKEN = st.one_of(st.from_regex(rb"\A[0-9]{1,10}\Z"), st.just(b"B"),
                   st.binary(min_size=1, max_size=10).filter(lambda t: b"," not in t))


@given(st.lists(_TOKEN, min_size=1, max_size=40))
def test_whole_numbers_are_the_tokens_or_the_block_is_handed_over(tokens):
    """Up to 8 digits a token: its whole number (``B``: blank); any other byte, or more
    digits, hands the tokens to the decimal reader (``_NotWhole``)."""
    text = b",".join(tokens) + b","
    b = np.frombuffer(b"\0" * 8 + text, dtype=np.uint8)  # 8 bytes before the block
    stops = np.flatnonzero(b[8:] == ord(","))
    length = np.array([len(t) for t in tokens])
    short = all(t == b"B" or t.isdigit() and t.isascii() and len(t) <= 8 for t in tokens)
    if not short:
        with pytest.raises(_tekscan_numpy._NotWhole):
            _tekscan_numpy._whole_numbers(b, stops, length)
        return
    whole, blank = _tekscan_numpy._whole_numbers(b, stops, length)
    assert blank.tolist() == [t == b"B" for t in tokens]
    assert whole.tolist() == [0 if t == b"B" else int(t) for t in tokens]


_SHORT_TOKEN = st.one_of(
    st.from_regex(rb"\A[0-9]{1,3}\Z"), st.just(b"B"),
    st.binary(min_size=1, max_size=3).filter(lambda t: b"," not in t),
    # bytes next to the digits (/ and :), B beside digits, signs and points
    st.lists(st.sampled_from(b"0123456789/:B-. \x00\xff"), min_size=1, max_size=3).map(bytes))


@given(st.lists(_SHORT_TOKEN, min_size=1, max_size=40), st.binary(min_size=8, max_size=8))
@example([b"1B"], b"\0" * 8)  # B beside a digit is no blank
@example([b"B1", b"25"], b"\0" * 8)
@example([b"7:"], b"9" * 8)  # the byte after 9
@example([b"/"], b"B" * 8)  # the byte before 0
def test_tokens_of_up_to_three_bytes_are_read_digit_by_digit(tokens, before):
    """Raw readings (1 to 3 bytes a token) take their own path: the same whole numbers
    and blanks as the 8-digit words, whatever bytes precede the block, and the same
    hand-over for any other byte."""
    text = b",".join(tokens) + b","
    b = np.frombuffer(before + text, dtype=np.uint8)
    stops = np.flatnonzero(b[8:] == ord(","))
    length = np.array([len(t) for t in tokens])
    if not all(t == b"B" or t.isdigit() and t.isascii() for t in tokens):
        with pytest.raises(_tekscan_numpy._NotWhole):
            _tekscan_numpy._three_digits(b, stops, length, _tekscan_numpy._Scratch())
        return
    whole, blank = _tekscan_numpy._three_digits(b, stops, length, _tekscan_numpy._Scratch())
    words, word_blank = _tekscan_numpy._swar(b.copy(), stops, length,
                                             _tekscan_numpy._Scratch(), "")
    assert whole.tolist() == words.tolist() == [0 if t == b"B" else int(t) for t in tokens]
    assert blank.tolist() == word_blank.tolist() == [t == b"B" for t in tokens]


_DECIMAL = re.compile(rb"-?([0-9]+(\.[0-9]*)?|\.[0-9]+)")


def _parse_tokens(tokens):
    """``_numbers`` of ``tokens`` as one block: the values, or None when not plain."""
    text = b",".join(tokens) + b","
    b = np.frombuffer(b"\0" * 8 + text, dtype=np.uint8)  # 8 bytes before the block
    stops = np.flatnonzero(b[8:] == ord(","))
    length = np.array([len(t) for t in tokens])
    out = np.empty(len(tokens))
    try:
        _tekscan_numpy._numbers(b, stops, length, out, _tekscan_numpy._Scratch())
    except _tekscan_numpy._NotPlain:
        return None
    return out


def _assert_tokens_read_as_float(tokens):
    """Each token's value is ``float(token)`` to the bit (B: NaN), or the block is handed over
    when a token is neither ``B`` nor ``[-](digits[.digits] | .digits)``."""
    out = _parse_tokens(tokens)
    plain = all(t == b"B" or _DECIMAL.fullmatch(t) for t in tokens)
    assert (out is not None) == plain, tokens
    if plain:
        expected = np.array([np.nan if t == b"B" else float(t) for t in tokens])
        assert out.tobytes() == expected.tobytes() or (
            np.array_equal(out, expected, equal_nan=True)
            and (np.signbit(out) == np.signbit(expected)).all()), tokens


# a token has a byte at least: the rows' check refuses an empty one before
_SHORT = st.one_of(st.from_regex(rb"\A-?[0-9]{0,4}(\.[0-9]{0,4})?\Z").filter(len), st.just(b"B"),
                   st.sampled_from([b".", b"-", b"-.", b"1.2.3", b"1-2", b"B.", b"-B", b"+1",
                                    b"1e5", b" 1", b"1_0"]))
_LONG = st.one_of(st.from_regex(rb"\A-?[0-9]{0,24}(\.[0-9]{0,24})?\Z").filter(len),
                  st.floats(allow_nan=False, allow_infinity=False).map(
                      lambda v: np.format_float_positional(v, trim="-").encode()[:40]),
                  st.floats(0, 1e6).map(lambda v: repr(v).encode()))


@given(st.lists(_SHORT, min_size=1, max_size=30))
def test_short_decimals_are_their_float_or_the_block_is_handed_over(tokens):
    """Up to 8 bytes a token: its point found and dropped within one word."""
    _assert_tokens_read_as_float(tokens)


@given(st.lists(st.one_of(_SHORT, _LONG), min_size=1, max_size=30))
def test_long_decimals_are_their_float_or_the_block_is_handed_over(tokens):
    """Beyond 2**53 and beyond 19 digits: rounded once, exactly as ``float``."""
    _assert_tokens_read_as_float(tokens)


@pytest.mark.parametrize("tokens", [
    [b"9007199254740993", b"9007199254740995", b"18014398509481985"],  # ties at 2**53, 2**54
    [b"9999999999999999999", b"1234567890123456789.", b"0.1000000000000000055511151231257827"],
    [b"1.00000000000000011102230246251565404", b"-0", b"-0.0", b".5", b"5.", b"-.5"],
])
def test_decimals_near_halfway_between_doubles_read_as_float(tokens):
    _assert_tokens_read_as_float(tokens)


def _near_midpoint(x, places, step, below):
    """The whole number ``step`` away from the midpoint above ``x`` (below a power of 2 with
    ``below``), in units of ``10**-places``."""
    from fractions import Fraction

    gap = Fraction(float(np.spacing(x)))
    mid = Fraction(x) - gap / 4 if below else Fraction(x) + gap / 2
    scaled = mid * 10**places
    return scaled.numerator // scaled.denominator + step


@given(st.lists(st.tuples(st.integers(2**53, 10**19 - 1), st.integers(0, 19)), min_size=1,
                max_size=20))
def test_big_mantissas_round_once(cases):
    """``m / 10**places`` for 2**53 <= m < 10**19: ``float`` of ``f"{m}e-{places}"``."""
    m = np.array([m for m, _ in cases], dtype=np.uint64)
    places = np.array([places for _, places in cases])
    expected = [float(f"{m}e-{places}") for m, places in cases]
    assert _tekscan_numpy._round_big(m, places).tolist() == expected


@given(st.lists(st.tuples(st.integers(0, 19), st.floats(0, 1), st.integers(-2, 2),
                          st.booleans(), st.floats(1, 2, exclude_max=True)),
                min_size=1, max_size=20))
def test_mantissas_by_a_midpoint_between_doubles_round_once(cases):
    """Within 2 units of a midpoint (below a power of 2 too) and on it: ``float``'s ties."""
    tokens = []
    for places, where, step, below, fraction in cases:
        low, high = 53 - places * math.log2(10), 63 - places * math.log2(10)  # 2**53..2**63
        x = 2.0 ** math.floor(low + where * (high - low)) * (1.0 if below else fraction)
        whole = _near_midpoint(x, places, step, below)
        if 2**53 <= whole < 10**19:
            tokens.append((whole, places))
    if tokens:
        m = np.array([m for m, _ in tokens], dtype=np.uint64)
        places = np.array([places for _, places in tokens])
        expected = [float(f"{m}e-{places}") for m, places in tokens]
        assert _tekscan_numpy._round_big(m, places).tolist() == expected


def _decimal_movie(tmp_path, text, seed=0, **kwargs):
    values = np.random.default_rng(seed).integers(0, 256, size=(12, 5, 7)) * 5.9379
    values[:, 0, :2] = np.nan
    values[:, 1, 1] = 0.0
    return _movie(tmp_path, values, units="KPa", text=text, **kwargs)


@pytest.mark.parametrize("text", [
    lambda v: f"{v:.2f}",  # a fixed number of decimals
    lambda v: repr(float(v)),  # the shortest that reads back (up to 17 digits)
    lambda v: f"{-v:.3f}",  # negative
    lambda v: f"{v:.9f}",  # more than 8 bytes a value
    lambda v: "0" if v == 0 else f"{v:g}",  # whole numbers among decimals
], ids=["fixed", "repr", "negative", "long", "mixed"])
@pytest.mark.parametrize("cores, block_bytes", [(1, 1), (1, 300), (2, 300)])
def test_decimal_exports_read_as_the_numba_reader_reads_them(tmp_path, monkeypatch, text,
                                                             cores, block_bytes):
    path = _decimal_movie(tmp_path, text, newline="\r\n")
    expected = _numba_read(path, monkeypatch)
    monkeypatch.setattr(_tekscan_numpy.os, "cpu_count", lambda: cores)
    monkeypatch.setattr(_tekscan_numpy, "PART_BYTES", 64)
    monkeypatch.setattr(_tekscan_numpy, "BLOCK_BYTES", block_bytes)
    assert _plain(path) is not None  # the NumPy reader took it
    assert read_tekscan(path).identical(expected)


def test_a_decimal_export_is_read_without_importing_numba(tmp_path):
    path = _decimal_movie(tmp_path, lambda v: repr(float(v)))
    code = ("import sys; from tactilecal.io import read_tekscan; "
            f"read_tekscan({str(path)!r}); print('numba' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True)
    assert out.stdout.split() == ["False"]


def test_a_frame_time_past_400_characters_is_refused_by_both_readers(tmp_path, monkeypatch):
    """The frame line's format has one owner (``_tekscan_frames``): a number the per-line
    parser refuses is no plain frame line for the NumPy reader either."""
    path = _movie(tmp_path, _raw(n=3))
    long_time = b"0." + b"0" * 400 + b"1"
    path.write_bytes(path.read_bytes().replace(b"Frame 2, 0.01", b"Frame 2, " + long_time, 1))
    assert _plain(path) is None
    message = str(_outcome(read_tekscan, path))
    assert "the frame time" in message
    assert message == str(_outcome(lambda p: _numba_read(p, monkeypatch), path))


@pytest.mark.parametrize("units", ["raw", "KPa"])
def test_a_frame_larger_than_a_block_reads_in_runs(tmp_path, monkeypatch, units):
    """One row of many values is parsed in runs of about BLOCK_BYTES of text (the memory of
    a block, whatever the frame's size); a raw file's Raw Sum is still checked."""
    values = _raw(n=3, rows=2, cols=400, seed=5)
    text = (lambda v: str(int(v))) if units == "raw" else (lambda v: repr(float(v) * 5.9379))
    path = _movie(tmp_path, values, units=units, text=text)
    expected = _numba_read(path, monkeypatch)
    monkeypatch.setattr(_tekscan_numpy, "BLOCK_BYTES", 64)
    runs = []
    monkeypatch.setattr(_tekscan_numpy, "_runs",
                        lambda stops, f=_tekscan_numpy._runs: runs.append(f(stops)) or runs[-1])
    assert _plain(path) is not None
    assert read_tekscan(path).identical(expected)
    assert max(len(r) for r in runs) > 10
    if units == "raw":  # a Raw Sum that is not the frame's sum: handed over, and refused
        path.write_bytes(path.read_bytes().replace(b"Raw Sum=,,", b"Raw Sum=,,1", 1))
        assert _plain(path) is None
        assert "Raw Sum" in str(_outcome(read_tekscan, path))
