"""What every static method shares: its input, its output and its options' base class.

The input is :class:`FitData`, the output :class:`Fit`, the options a frozen dataclass of
:class:`MethodOptions` whose fields are made by :func:`option`.

A method is one module of :mod:`tactilecal.calibration.methods` exporting ``NAME``, an
``Options`` class (a frozen :class:`MethodOptions` dataclass: the only place the method's
defaults live) and ``fit(data, options) -> Fit``. :func:`tactilecal.calibration.calibrate`
chooses the points, resolves saturation and the sensel area, checks the options once and
calls ``fit`` on the points it uses; the command line builds its flags from the same
``Options`` fields (their ``metadata`` carries the help text and the choices).
"""

import dataclasses
from dataclasses import dataclass, field

import numpy as np

from tactilecal._errors import TactilecalError, TactilecalTypeError

__all__ = ["Fit", "FitData", "MethodOptions", "option"]


@dataclass(frozen=True)
class FitData:
    """The points a method fits, already chosen by ``calibrate``.

    Attributes
    ----------
    hist : numpy.ndarray
        (n, 256) counts of raw values 0..255 per point (any numeric dtype).
    load_N : numpy.ndarray
        (n,) applied loads in newtons.
    censored : numpy.ndarray of bool or None
        Points whose load is only a lower bound of the law's prediction (a sensel at 255,
        ``saturated="censored"``); None when every load is exact.
    sensel_area_mm2 : float
        Area of one sensel (NaN when unknown).
    labels : tuple of str
        Names of the points for messages and figures.
    memo : dict
        What was computed from these points once for every fit that needs it (the power law
        that ``lut`` and ``piecewise`` start from and ``auto``'s ``power:l1`` candidate is,
        on the same fold); empty in the rows taken by :meth:`rows`.
    """

    hist: np.ndarray
    load_N: np.ndarray
    censored: np.ndarray | None = None
    sensel_area_mm2: float = float("nan")
    labels: tuple = ()
    memo: dict = field(default_factory=dict, init=False, repr=False, compare=False)

    def rows(self, keep):
        """Return the data of the rows ``keep`` (bool mask or indices)."""
        keep = np.asarray(keep)
        labels = tuple(np.asarray(self.labels, dtype=object)[keep]) if self.labels else ()
        return dataclasses.replace(
            self, hist=self.hist[keep], load_N=self.load_N[keep], labels=labels,
            censored=None if self.censored is None else self.censored[keep])


@dataclass
class Fit:
    """What a method's ``fit`` returns: the per-sensel law and what the fit found.

    Attributes
    ----------
    model : str
        The per-sensel law, a key of :data:`tactilecal.calibration._models.MODELS`.
    params : dict
        Its parameters.
    diagnostics : dict
        JSON-ready values describing the fit (cost, evaluations, segments...); read by
        people and reports, never by :meth:`CalibrationResult.apply`.
    chosen : tuple of int, optional
        For methods whose law passes through chosen points (I-Scan's 1-point and 2-point
        calibrations): their indices into the fitted rows; the other rows are reported as
        not used.
    method_result : object, optional
        The method's own result with its intermediates (Zvyagin's :class:`ZvyaginResult`).
    """

    model: str
    params: dict
    diagnostics: dict = field(default_factory=dict)
    chosen: tuple | None = None
    method_result: object = None


def option(default, help, *, choices=None, metavar=None, flag=None):
    """Declare a field of a method's ``Options``: its default, help text and allowed values.

    The command line builds ``--<name>`` from it (``metadata["help"]``,
    ``metadata["choices"]``), so neither the default nor the text is written twice;
    ``flag=("--learn-gains", "learn")`` makes it a flag without a value that sets that
    choice.
    """
    metadata = {"help": help, "choices": choices, "metavar": metavar, "flag": flag}
    if isinstance(default, list | dict):
        raise TypeError("option defaults must be immutable (use a tuple)")
    return field(default=default, metadata=metadata)


@dataclass(frozen=True)
class MethodOptions:
    """Base of every method's frozen ``Options`` dataclass.

    Subclasses declare their fields with :func:`option` and may add ``_check(self)`` for
    rules between fields; values given as lists are stored as tuples, the choices of a
    field are checked here.
    """

    def __post_init__(self):
        for f in dataclasses.fields(self):
            value = getattr(self, f.name)
            if isinstance(value, list):
                object.__setattr__(self, f.name, tuple(value))
            choices = f.metadata.get("choices")
            if choices is not None and getattr(self, f.name) not in choices:
                raise TactilecalError(f"{f.name}={value!r} is not an option of "
                                      f"{self.method_name()}; expected one of {choices}")
        self._check()

    def _check(self):
        """Rules between fields (a subclass raises TactilecalError naming the option)."""

    @classmethod
    def method_name(cls):
        """Return the ``NAME`` of the method module that defines this class."""
        import sys

        return getattr(sys.modules[cls.__module__], "NAME", cls.__module__)

    @classmethod
    def names(cls):
        """Return the option names, in declaration order."""
        return tuple(f.name for f in dataclasses.fields(cls))

    @classmethod
    def from_keywords(cls, keywords, *, accepted_too=()):
        """Return the options given as keywords, refusing any the method does not take.

        Raises
        ------
        TactilecalTypeError
            An unknown or inapplicable option, naming it and the accepted ones
            (``accepted_too``: the keywords of the caller itself, listed as accepted).
        """
        unknown = sorted(set(keywords) - set(cls.names()))
        if unknown:
            raise TactilecalTypeError(
                f"method={cls.method_name()!r} does not take the option(s) {unknown}; "
                f"expected some of {[*cls.names(), *accepted_too]}")
        return cls(**keywords)

    def to_dict(self):
        """Return the options as a JSON-ready dict (tuples as lists)."""
        return {name: list(v) if isinstance(v, tuple) else v
                for name, v in ((n, getattr(self, n)) for n in self.names())}


def check_positive_number(value, name, method, *, zero=False):
    """Raise TactilecalError unless ``value`` is a finite number > 0 (>= 0 with ``zero``)."""
    if isinstance(value, bool) or not isinstance(value, int | float | np.number) \
            or not np.isfinite(value) or value < 0 or (value == 0 and not zero):
        raise TactilecalError(f"{name}={value!r} is not an option of {method}; expected a "
                              f"finite number {'>=' if zero else '>'} 0")
