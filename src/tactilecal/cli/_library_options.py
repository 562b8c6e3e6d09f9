"""Flags built from the library's functions: one owner for every default.

A flag's default is read from the signature of the library function it is passed to
(:func:`inspect.signature`), and its help says it with ``%(default)s``, so neither the
value nor its text is written twice.
"""

import inspect

__all__ = ["default", "add_option"]


def default(function, name):
    """Return the default of keyword ``name`` of ``function`` (the library's, the only copy)."""
    return inspect.signature(function).parameters[name].default


def add_option(parser, flag, function, name, help, **kwargs):
    """Add ``flag`` for keyword ``name`` of ``function``, with its default and help.

    A boolean default makes a switch (``store_true``); ``kwargs`` go to ``add_argument``
    (``type``, ``choices``, ``nargs``, ``metavar``).
    """
    value = default(function, name)
    if value is False:
        return parser.add_argument(flag, dest=name, action="store_true", help=help)
    said = "" if value is None else " (default %(default)s)"
    return parser.add_argument(flag, dest=name, default=value, help=help + said, **kwargs)
