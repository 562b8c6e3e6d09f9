"""The toolkit's exception for bad input: one type that every door raises and the CLI knows.

A file, value or option that tactilecal cannot use raises :class:`TactilecalError` (a
:class:`ValueError`), or :class:`TactilecalTypeError` (also a :class:`TypeError`) when an
input holds a value of the wrong type, with a one-line message that names the file, line,
key or parameter, says what was found and what was expected. The command line prints such
an error, and any :class:`OSError`, as one line and exits 1; any other exception is a bug in
tactilecal and is shown with its traceback.
"""

__all__ = ["TactilecalError", "TactilecalTypeError"]


class TactilecalError(ValueError):
    """Bad input: a file, value or option tactilecal cannot use (the message says which).

    Examples
    --------
    >>> import tactilecal as tc
    >>> tc.calibrate([], method="spline")
    Traceback (most recent call last):
    ...
    tactilecal.TactilecalError: method='spline' is unknown; expected one of [...]
    """

    __module__ = "tactilecal"


class TactilecalTypeError(TactilecalError, TypeError):
    """Bad input of the wrong type, such as a text where a file's key holds a number."""

    __module__ = "tactilecal"
