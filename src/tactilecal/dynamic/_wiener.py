"""A regularised non-parametric inverse: the measured complex correction, shrunk by its error.

For a sensor no parametric model describes, the correction can be the measured one: the
complex ``C = reference / sensor`` of each coherent bin (:class:`TransferFunction`
``.response``). Its random error is known from the coherence and the number of Welch
averages: the gain's normalised error ``e`` and the phase's standard deviation (radians) are
the same number (Bendat & Piersol, *Random Data*, eqs. 9.90-9.91), so ``|dC|^2 ~ 2 e^2
|C|^2``. The deviation from the identity, ``D = C - 1`` (what the filter must do), is shrunk
the way a Wiener filter weighs a signal against its noise, ``S / (S + N)``:

    D_w = D |D|^2 / (|D|^2 + 2 e^2 |C|^2)

Bins whose deviation stands well above its error keep it; bins where it is lost in the error
are left as recorded (``D_w -> 0``), rather than amplified. Between bins the correction is
interpolated linearly (real and imaginary parts), from 1 at 0 Hz
(:meth:`CorrectionFilter.target`). Its held-out error (blocks of bins predicted from the
others, as for the rational orders) lets ``model="auto"`` weigh it against the parametric
models: with a parameter per bin it must do better than they do to be chosen.
"""

import numpy as np

from tactilecal.dynamic._fit import complex_r2
from tactilecal.dynamic._ratfit import held_out_score

__all__ = ["wiener_correction", "wiener_held_out"]


def wiener_correction(correction, gain_error):
    """Return ``1 + D_w`` for the measured ``correction`` and its ``gain_error`` (see the notes).

    Examples
    --------
    >>> c = wiener_correction([1.5 + 0.5j, 1.02], [0.01, 0.05])
    >>> [round(float(abs(v - 1)), 3) for v in c]  # a clear deviation kept, a noisy one shrunk
    [0.706, 0.001]
    """
    correction = np.asarray(correction, dtype=complex)
    deviation = correction - 1.0
    noise = 2.0 * np.asarray(gain_error, dtype=float) ** 2 * np.abs(correction) ** 2
    power = np.abs(deviation) ** 2
    with np.errstate(invalid="ignore", divide="ignore"):
        shrink = np.where(power > 0, power / (power + noise), 0.0)
    return 1.0 + deviation * shrink


def _interpolate(f_hz, values, at_hz):
    """Complex linear interpolation through ``(0, 1)`` and ``(f_hz, values)``."""
    f, v = np.r_[0.0, f_hz], np.r_[1.0 + 0j, values]
    return np.interp(at_hz, f, v.real) + 1j * np.interp(at_hz, f, v.imag)


def wiener_held_out(f_hz, correction, gain_error, held):
    """Held-out score (:func:`held_out_score`) and complex R2 of the ``held`` bins.

    The correction is built without them and interpolated across them.
    """
    f_hz = np.asarray(f_hz, dtype=float)
    correction = np.asarray(correction, dtype=complex)
    gain_error = np.asarray(gain_error, dtype=float)
    shrunk = wiener_correction(correction[~held], gain_error[~held])
    predicted = _interpolate(f_hz[~held], shrunk, f_hz[held])
    return (held_out_score(correction[held], predicted, gain_error[held]),
            complex_r2(correction[held], predicted))
