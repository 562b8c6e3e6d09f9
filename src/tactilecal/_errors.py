"""The toolkit's exception for bad input: one type that every door raises and the CLI knows.

A file, value or option that tactilecal cannot use raises :class:`TactilecalError` (a
:class:`ValueError`), or :class:`TactilecalTypeError` (also a :class:`TypeError`) when an
input holds a value of the wrong type, with a one-line message that names the file, line,
key or parameter, says what was found and what was expected. The command line prints such
an error, and any :class:`OSError`, as one line and exits 1; any other exception is a bug in
tactilecal and is shown with its traceback.

A message is at most :data:`MAX_MESSAGE` characters: a longer one (a value of megabytes
quoted in it) keeps its beginning, which names the file and line, and its end, which says
what was expected, joined by an ellipsis.
"""

__all__ = ["TactilecalError", "TactilecalTypeError", "MAX_MESSAGE", "cap_message"]

MAX_MESSAGE = 300
"""Most characters of an error message (its middle is cut with an ellipsis beyond that)."""


def cap_message(text, limit=MAX_MESSAGE):
    """Return ``text`` on one line, at most ``limit`` characters, its middle cut with "...".

    Examples
    --------
    >>> text = cap_message("line 3 of f.csv: ROWS is '" + "9" * 1000 + "'; expected an integer")
    >>> text[:30], text[-25:]
    ("line 3 of f.csv: ROWS is '9999", "999'; expected an integer")
    >>> len(cap_message("x" * 1000))
    300
    """
    text = str(text)
    if len(text) <= limit:
        return text
    head = (limit - 5) * 2 // 3
    tail = limit - 5 - head
    return f"{text[:head]} ... {text[len(text) - tail:]}"


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

    def __init__(self, *args):
        if len(args) == 1 and isinstance(args[0], str):
            args = (cap_message(args[0]),)
        super().__init__(*args)


class TactilecalTypeError(TactilecalError, TypeError):
    """Bad input of the wrong type, such as a text where a file's key holds a number."""

    __module__ = "tactilecal"
