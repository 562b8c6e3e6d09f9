"""Argument types of the CLI's numeric flags: a finite number in range, or one line naming it."""

import argparse
import math

__all__ = ["positive_int", "non_negative_int", "positive_float", "non_negative_float", "share"]


def _number(kind, minimum, inclusive, maximum=None):
    """Return an argparse ``type`` for a finite number in range (the error names the flag)."""
    bound = f"{'>=' if inclusive else '>'} {minimum:g}"
    bound += f" and <= {maximum:g}" if maximum is not None else ""
    what = "whole number" if kind is int else "finite number"

    def convert(text):
        try:
            value = kind(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{text!r}; expected a {what} {bound}") from None
        if not math.isfinite(value) or value < minimum or (value == minimum and not inclusive) \
                or (maximum is not None and value > maximum):
            raise argparse.ArgumentTypeError(f"{text!r}; expected a finite number {bound}")
        return value
    convert.__name__ = kind.__name__  # argparse says "invalid int value" on a bare failure
    convert.checks_value = True  # a refused value is bad input (exit 1), not bad usage
    return convert


positive_int = _number(int, 0, False)
non_negative_int = _number(int, 0, True)
positive_float = _number(float, 0.0, False)
non_negative_float = _number(float, 0.0, True)
share = _number(float, 0.0, True, 1.0)
