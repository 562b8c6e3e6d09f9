"""``njit`` with an on-disk cache where one can be written, and without it where none can.

numba's ``cache=True`` stores the compiled kernels next to their module (``__pycache__``)
or, when that folder is read-only (a system-wide install), in the user's cache folder
(``NUMBA_CACHE_DIR`` or ``~/.cache/numba``). When neither can be written (a read-only
install run by a user without a writable home, e.g. in a container) numba raises
``RuntimeError: cannot cache function ...`` as the kernel module is imported. :func:`njit`
then compiles the kernel without a cache, silently: it is compiled on first use in each
process instead of loaded from disk, which costs time, never correctness.

:func:`read_only` gives a kernel's inputs one type whatever their writability. Importing
this module does not import numba: :func:`njit` does.
"""

__all__ = ["njit", "read_only"]


def njit(**options):
    """Return ``numba.njit(cache=True, **options)``, or the uncached one if no cache fits.

    Parameters
    ----------
    **options
        Passed to :func:`numba.njit` (``nogil``, ``fastmath``, ``inline``, ...).

    Returns
    -------
    callable
        A decorator.

    Examples
    --------
    >>> @njit(nogil=True)
    ... def twice(x):
    ...     return 2 * x
    >>> twice(21)
    42
    """
    import numba

    def decorate(function):
        try:
            return numba.njit(cache=True, **options)(function)
        except RuntimeError as exc:  # numba: "cannot cache function ...: no locator ..."
            if "cannot cache" not in str(exc):
                raise
            return numba.njit(**options)(function)
    return decorate


def read_only(array):
    """Return a read-only view of ``array``, so that a kernel reading it compiles once.

    numba compiles a kernel again for every argument type, and a read-only array (a block
    of a file, a dask chunk, a remembered table) is another type than a writable one of the
    same dtype.

    Examples
    --------
    >>> import numpy as np
    >>> read_only(np.zeros(3)).flags.writeable
    False
    """
    view = array.view()
    view.flags.writeable = False
    return view
