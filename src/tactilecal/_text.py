"""How numbers are written for people: one formatter for summaries, the CLI and reports.

A result's ``summary()``, the command line and the HTML report write values through these
functions, so a number reads the same wherever it is shown: to four significant digits
(what the calibrations and measurements here support), shares as percentages.
"""

import math
import numbers

__all__ = ["number", "share"]

SIGNIFICANT_DIGITS = 4


def number(value, digits=SIGNIFICANT_DIGITS, unit=None):
    """Write ``value`` for people: whole numbers as they are, floats to ``digits`` digits.

    A float holding a whole number (a raw sum, a count read from a file) is written whole;
    other floats to ``digits`` significant digits, without an exponent below 1e15
    (``13127.5`` is ``13130``, not ``1.313e+04``). ``unit`` is appended after a space.

    Examples
    --------
    >>> number(0.0035123456), number(1514.7321), number(12), number(float("nan")), number(None)
    ('0.003512', '1515', '12', 'n/a', 'n/a')
    >>> number(13127.0), number(13127.5), number(2.5e-7), number(760.0, unit="kPa")
    ('13127', '13130', '2.5e-07', '760 kPa')
    >>> number(True), number("power")
    ('True', 'power')
    """
    text = _number(value, digits)
    return text if unit is None or text == "n/a" else f"{text} {unit}"


def _number(value, digits):
    if value is None or isinstance(value, bool | str):
        return "n/a" if value is None else str(value)
    if isinstance(value, numbers.Integral):
        return str(int(value))
    if isinstance(value, numbers.Real):
        value = float(value)
        if not math.isfinite(value):
            return "n/a" if math.isnan(value) else str(value)
        if value.is_integer() and abs(value) < 1e15:
            return str(int(value))
        text = f"{value:.{digits}g}"
        if "e+" in text and abs(value) < 1e15:
            return f"{round(value, digits - 1 - math.floor(math.log10(abs(value)))):.0f}"
        return text
    return str(value)


def share(value, decimals=1):
    """Write a share in 0..1 as a percentage, e.g. ``0.96`` -> ``'96.0 %'``.

    Examples
    --------
    >>> share(0.96), share(1), share(float("nan"))
    ('96.0 %', '100.0 %', 'n/a')
    """
    if value is None or not math.isfinite(float(value)):
        return "n/a"
    return f"{100 * float(value):.{decimals}f} %"
