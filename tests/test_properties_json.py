"""Property-based tests of every saved JSON kind through :func:`tactilecal.load` (Hypothesis).

Calibrations (several methods), equilibrations, non-working sensels, validations and dynamic
filters are generated from simulated data, saved with ``to_json`` and loaded back: the JSON
written again is the same text. Neutral edits (indentation, key order, byte-order mark,
UTF-16) load the same; edits the generic JSON layer must refuse (nesting, huge numbers, a
NUL, a wrong format tag, truncation, not an object) raise :class:`TactilecalError` naming the
file; any edit loads or raises that error on one line of at most 300 characters. The blind
test JSON of ``dynamic evaluate`` is checked the same way through ``Evaluation.from_json``.
"""

import itertools
import json

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

import tactilecal
from tactilecal import TactilecalError
from tactilecal._errors import MAX_MESSAGE
from tactilecal.calibration import (
    calibrate,
    equilibrate,
    find_dead_sensels,
    points_from_frames,
    validate,
)
from tactilecal.dynamic import CorrectionFilter, Evaluation

_COUNT = itertools.count()
KINDS = ("calibration", "equilibration", "non-working-sensels", "validation", "filter")


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    return tmp_path_factory.mktemp("properties")


def _path(folder, name="result.json"):
    return folder / f"{next(_COUNT)}-{name}"


def _points(draw):
    a = draw(st.floats(1e-3, 1e-2))
    b = draw(st.floats(1.0, 1.4))
    levels = sorted(draw(st.sets(st.integers(10, 200), min_size=3, max_size=5)))
    frames = np.zeros((len(levels), 4, 4))
    for k, level in enumerate(levels):
        frames[k, 1:3, 1:3] = level
    loads = [4 * a * v ** b for v in levels]
    return points_from_frames(frames, loads, sensel_area_mm2=1.6129)


@st.composite
def results(draw, kinds=KINDS):
    """A saved result of one of ``kinds`` built from simulated data."""
    kind = draw(st.sampled_from(kinds))
    if kind in ("calibration", "validation"):
        method = draw(st.sampled_from(["power", "linear", "lut", "piecewise", "power-2pt"]))
        points = _points(draw)
        try:
            cal = calibrate(points, method=method)
        except TactilecalError:
            assume(False)
        return validate(cal, points) if kind == "validation" else cal
    if kind == "equilibration":
        rows, cols = draw(st.integers(2, 4)), draw(st.integers(2, 4))
        levels = [np.array(draw(st.lists(st.integers(20, 250), min_size=rows * cols,
                                         max_size=rows * cols)), float).reshape(1, rows, cols)
                  for _ in range(draw(st.integers(1, 3)))]
        return equilibrate(levels)
    if kind == "non-working-sensels":
        frames = np.full((2, 4, 4), 50.0)
        dead = draw(st.lists(st.tuples(st.integers(1, 2), st.integers(1, 2)), max_size=2))
        for r, c in dead:
            frames[:, r, c] = 0.0
        return find_dead_sensels(frames)
    fs = draw(st.sampled_from([400.0, 1000.0, 4000.0]))
    if draw(st.booleans()):
        return CorrectionFilter.from_model(("log10", {"A": draw(st.floats(0.01, 0.3))}),
                                           fs_hz=fs, band_hz=(1.0, fs / 4))
    gains = draw(st.lists(st.floats(0.8, 2.0), min_size=2, max_size=5))
    f_hz = np.linspace(5.0, fs / 5, len(gains))
    return CorrectionFilter.from_response(f_hz, gains, fs_hz=fs)


def _saved(folder, result):
    path = _path(folder)
    result.to_json(path)
    return path


def _assert_clean_error(exc, path):
    message = str(exc)
    assert isinstance(exc, TactilecalError), f"{type(exc).__name__}: {message}"
    assert path.name in message, message
    assert "\n" not in message and len(message) <= MAX_MESSAGE, message


def _same_text(folder, loaded, path):
    again = _path(folder)
    loaded.to_json(again)
    assert again.read_text() == path.read_text()


@given(results())
def test_saved_results_load_back_to_the_same_json(folder, result):
    path = _saved(folder, result)
    loaded = tactilecal.load(path)
    assert type(loaded) is type(result)
    _same_text(folder, loaded, path)


@given(st.data())
def test_neutral_json_edits_load_the_same(folder, data):
    path = _saved(folder, data.draw(results()))
    original = path.read_text()
    obj = json.loads(original)
    kind = data.draw(st.sampled_from(["compact", "reversed keys", "utf-8-sig", "utf-16",
                                      "crlf"]))
    if kind == "compact":
        path.write_text(json.dumps(obj, separators=(",", ":")))
    elif kind == "reversed keys":
        path.write_text(json.dumps(dict(reversed(list(obj.items()))), indent=1))
    elif kind in ("utf-8-sig", "utf-16"):
        path.write_bytes(original.encode(kind))
    else:
        path.write_bytes(original.replace("\n", "\r\n").encode())
    again = _path(folder)
    tactilecal.load(path).to_json(again)
    assert again.read_text() == original


def _nested(obj, depth):
    return {**obj, "provenance": {"x": json.loads("[" * depth + "]" * depth)}}


@st.composite
def generic_breaks(draw, text):
    """Edits the generic JSON layer refuses whatever the kind: ``(name, bytes)``."""
    obj = json.loads(text)
    kind = draw(st.sampled_from(["nesting", "long number", "nul", "format tag", "truncated",
                                 "not an object", "no format", "huge string", "not json"]))
    if kind == "nesting":
        return kind, json.dumps(_nested(obj, draw(st.integers(33, 5000)))).encode()
    if kind == "long number":
        key = draw(st.sampled_from(sorted(obj)))
        digits = "9" * draw(st.integers(401, 6000))
        return kind, json.dumps({**obj, key: "@"}).replace('"@"', digits).encode()
    if kind == "nul":
        return kind, json.dumps({**obj, "provenance": {"x": "a\x00b"}}).encode()
    if kind == "format tag":
        tag = draw(st.sampled_from(["tactilecal-nothing/1", "tactilecal-calibration/99", "x",
                                    "tactilecal-equilibration/0x"]))
        return kind, json.dumps({**obj, "format": tag}).encode()
    if kind == "truncated":
        return kind, text[:draw(st.integers(0, len(text) - 2))].encode()
    if kind == "not an object":
        return kind, json.dumps(draw(st.sampled_from([[obj], 3, "x", None]))).encode()
    if kind == "no format":
        return kind, json.dumps({k: v for k, v in obj.items() if k != "format"}).encode()
    if kind == "huge string":
        return kind, json.dumps({**obj, "provenance": {"x": "x" * 140_000}}).encode()
    return kind, b"\xff\xfe\x00" + text.encode()[:50]


@given(st.data())
def test_generic_json_breaks_are_errors_naming_the_file(folder, data):
    path = _saved(folder, data.draw(results()))
    kind, edited = data.draw(generic_breaks(path.read_text()))
    path.write_bytes(edited)
    with pytest.raises(TactilecalError) as info:
        tactilecal.load(path)
    _assert_clean_error(info.value, path)


HOSTILE = [None, -1, 0, -3.5, 1e308, float("nan"), float("inf"), "abc", "", [], [1, "x"], {},
           {"a": 1}, True, 10**30, 10**350]


def _paths(obj, prefix=()):
    if isinstance(obj, dict):
        for key, value in obj.items():
            yield prefix + (key,)
            yield from _paths(value, prefix + (key,))
    elif isinstance(obj, list) and 0 < len(obj) <= 8:
        for k, value in enumerate(obj):
            yield prefix + (k,)
            yield from _paths(value, prefix + (k,))


@st.composite
def key_edits(draw, text):
    """Return the JSON with one key deleted or given a hostile value."""
    obj = json.loads(text)
    path = draw(st.sampled_from([p for p in _paths(obj) if p[0] != "format"]))
    parent = obj
    for key in path[:-1]:
        parent = parent[key]
    if isinstance(parent, dict) and draw(st.booleans()):
        del parent[path[-1]]
    else:
        parent[path[-1]] = draw(st.sampled_from(HOSTILE))
    return json.dumps(obj).encode()


def _loads_or_clean_error(folder, path):
    try:
        loaded = tactilecal.load(path)
    except Exception as exc:  # noqa: BLE001 - the class is what is tested
        _assert_clean_error(exc, path)
        return None
    again = _path(folder)  # what loaded is written, and reads back the same
    loaded.to_json(again)
    tactilecal.load(again).to_json(path, overwrite=True)
    assert path.read_text() == again.read_text()
    return loaded


@given(st.data())
def test_any_key_edit_loads_or_is_a_clean_error(folder, data):
    path = _saved(folder, data.draw(results()))
    path.write_bytes(data.draw(key_edits(path.read_text())))
    _loads_or_clean_error(folder, path)


@given(st.data())
def test_any_byte_edit_loads_or_is_a_clean_error(folder, data):
    path = _saved(folder, data.draw(results()))
    raw = bytearray(path.read_bytes())
    for _ in range(data.draw(st.integers(1, 3))):
        at = data.draw(st.integers(0, len(raw) - 1))
        raw[at] = data.draw(st.sampled_from(list(b'{}[]",:0123456789.-eE ntfa\x00\xff')))
    path.write_bytes(bytes(raw))
    _loads_or_clean_error(folder, path)


# ----------------------------------------------------------------------------- blind test
EVALUATION = {"lag_s": 0.01, "static_factor": 1.2, "fs_hz": 100.0, "rms_before_N": 3.0,
              "rms_after_N": 1.0, "f_hz": [1.0, 2.0, 5.0, 10.0],
              "error_before_pct": [-1.0, -3.0, -8.0, -15.0],
              "error_after_pct": [0.1, -0.2, 0.3, 0.5],
              "phase_before_deg": [-1.0, -2.0, -5.0, -9.0],
              "phase_after_deg": [0.0, 0.1, -0.1, 0.2]}


@settings(max_examples=max(10, settings.default.max_examples // 2))
@given(st.data())
def test_any_blind_test_edit_loads_or_is_a_clean_error(folder, data):
    path = _path(folder, "evaluation.json")
    path.write_bytes(data.draw(key_edits(json.dumps(EVALUATION))))
    try:
        Evaluation.from_json(path)
    except Exception as exc:  # noqa: BLE001 - the class is what is tested
        _assert_clean_error(exc, path)


def _one_by_one(obj):
    """to_jsonable's rule element by element: arrays and NumPy scalars as Python values,
    non-finite floats as None."""
    if isinstance(obj, np.ndarray | list | tuple):
        return [_one_by_one(v) for v in obj] if np.ndim(obj) else _one_by_one(obj.item())
    value = obj.item() if isinstance(obj, np.generic) else obj
    return None if isinstance(value, float) and not np.isfinite(value) else value


@given(array=hnp.arrays(st.sampled_from(["f8", "f4", "f2", "i8", "u1", "i2", "bool"]),
                        hnp.array_shapes(min_dims=0, max_dims=3, min_side=0, max_side=4)))
def test_an_array_converts_as_its_elements_one_by_one(array):
    from tactilecal._jsonutil import to_jsonable

    got = to_jsonable({"a": array, "b": [array, (np.float64(np.nan), 1.5)]})
    want = _one_by_one(array)
    assert got == {"a": want, "b": [want, [None, 1.5]]}
    assert [type(x) for x in np.ravel(np.asarray(got["a"], dtype=object))] == \
        [type(x) for x in np.ravel(np.asarray(want, dtype=object))]
    json.dumps(got, allow_nan=False)  # what JSON holds: no NaN, no NumPy type


def test_the_suite_runs_the_hypothesis_profile_it_names(request):
    """conftest loads its profile as the first test file is collected: not the library's
    default (100 examples, a database, random), in a worker or a run without xdist; one
    named with --hypothesis-profile is kept."""
    import os

    from hypothesis import settings

    given = request.config.getoption("hypothesis_profile", None)
    name = given or os.environ.get("TACTILECAL_HYPOTHESIS", "fast")
    assert settings.get_current_profile_name() == name
    if name in ("fast", "long"):
        assert settings.default.max_examples == {"fast": 30, "long": 2000}[name]
