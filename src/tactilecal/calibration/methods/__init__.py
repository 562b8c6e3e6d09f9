"""The static calibration methods, one module each.

A method module exports ``NAME`` (the ``method=`` string), ``Options`` (a frozen dataclass
of :class:`tactilecal.calibration._fit.MethodOptions`: the only place the method's defaults
live) and ``fit(data, options)`` returning a :class:`tactilecal.calibration._fit.Fit`.
:func:`tactilecal.calibration.calibrate` is the one door to them: it chooses the points,
resolves saturation and the sensel area once, checks the options, and calls ``fit``.

==================  ============================================  ===========================
method              per-sensel law                                source
==================  ============================================  ===========================
``linear``          ``A raw`` (1-point, or through zero)          I-Scan; Gillis 2013, 3.5
``power-2pt``       ``A x**b`` on the mean reading x              I-Scan; Gillis 2013, 3.5
``power``           ``A raw**b`` over every sensel                Zvyagin 2022 eq. 3; I-Scan
``linear-offset``   ``K max(raw - offset, 0)``                    Paikowsky & Hajduk 1997
``piecewise``       power law per raw range, continuous           after Stith
``lut``             monotone table, smoothed to a power law       Eilers & Marx 1996
``polynomial``      ``sum_j c_j raw**j``, nondecreasing           --
``zvyagin``         ``A0 raw**b0`` from the high-pressure zones   Zvyagin 2022
==================  ============================================  ===========================

To add a method, add a module here with those three names and list it in :data:`MODULES`.
"""

from tactilecal.calibration.methods import (
    linear,
    linear_offset,
    lut,
    piecewise,
    polynomial,
    power,
    power_2pt,
    zvyagin,
)

__all__ = ["MODULES"]

MODULES = {module.NAME: module for module in (linear, power_2pt, power, linear_offset,
                                              piecewise, lut, polynomial, zvyagin)}
"""Method name -> its module (``NAME``, ``Options``, ``fit``)."""
