"""How every static calibration treats patches with saturated (255) sensels: one default.

A sensel at 255 says only "force >= f(255)". Fitting such a patch as if 255 were the true
reading biases the law (Zvyagin's b0 came out ~1.30 instead of 1.20 on an independent
simulator's sessions), so by default a patch with any sensel at 255 is left out of
the fit and reported. The CLI (``--saturated``) and the API (``saturated=``) read the default
from here, so the two give the same calibration from the same manifest.
"""

from tactilecal._errors import TactilecalError

__all__ = ["SATURATED_CHOICES", "SATURATED_DEFAULT", "resolve_saturated"]

SATURATED_CHOICES = ("drop", "keep", "censored")
"""``"drop"``: leave patches with a sensel at 255 out of the fit (reported per point);
``"keep"``: fit them as if 255 were their true reading (Zvyagin's paper as written);
``"censored"``: fit them as lower bounds of their load (every method,
:func:`tactilecal.calibration._methods.fit_censored`; Zvyagin keeps them out of its pairs)."""

SATURATED_DEFAULT = "drop"
"""The default: on an independent simulator (8 sessions, Sensor2 parameters),
dropping raised Zvyagin's worst-session share of held-out patches within 5 % from 61 % to
78-83 %. On the simulated family (benchmarks/bench_static.py) ``censored`` reached the
same worst cases as ``drop`` for every method benchmarked, so the simpler one stays."""


def resolve_saturated(saturated=None, keep_saturated=None):
    """Return the saturation treatment (of ``SATURATED_CHOICES``) from the option or its alias.

    ``keep_saturated`` (True/False, the static methods' earlier option) is an alias; given
    both, they must agree.

    Examples
    --------
    >>> resolve_saturated(), resolve_saturated(keep_saturated=True)
    ('drop', 'keep')
    """
    if keep_saturated is not None:
        alias = "keep" if keep_saturated else "drop"
        if saturated is not None and saturated != alias:
            raise TactilecalError(f"saturated={saturated!r} and keep_saturated={keep_saturated!r} "
                                  "disagree; expected one of them")
        saturated = alias
    saturated = SATURATED_DEFAULT if saturated is None else saturated
    if saturated not in SATURATED_CHOICES:
        raise TactilecalError(f"saturated={saturated!r}; expected one of {SATURATED_CHOICES}")
    return saturated
