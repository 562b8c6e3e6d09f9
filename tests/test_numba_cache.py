"""The kernels' on-disk cache is optional: where numba can write none, they compile anyway."""

import numba
import pytest

from tactilecal._numba import njit

SOURCE = "def add_one(x):\n    return x + 1\n"


def _function_without_a_file():
    """A function whose source file does not exist: numba finds no folder to cache it in."""
    namespace = {}
    exec(compile(SOURCE, "<no file>", "exec"), namespace)
    return namespace["add_one"]


def test_numba_refuses_to_cache_a_function_it_cannot_place():
    """The failure the helper guards against: numba's own error, at decoration time."""
    with pytest.raises(RuntimeError, match="cannot cache function 'add_one'"):
        numba.njit(cache=True)(_function_without_a_file())


def test_no_writable_cache_location_falls_back_to_an_uncached_kernel():
    kernel = njit(nogil=True)(_function_without_a_file())
    assert kernel(41) == 42
    assert kernel.py_func.__name__ == "add_one"


def test_a_kernel_with_a_source_file_is_cached():
    kernel = njit()(_cached_example)
    assert kernel(2) == 4
    assert kernel._cache.__class__.__name__ != "NullCache"


def _cached_example(x):
    return 2 * x
