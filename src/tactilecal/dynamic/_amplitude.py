"""Does the response depend on the load's amplitude? Two sweeps compared within their errors.

A linear sensor has one transfer function whatever the amplitude; a sensor whose dynamics
stiffen or soften with the amplitude (a foam's Payne effect, friction) does not, and one
linear filter cannot correct it (METHOD-NOTES G). Sweeps at different amplitudes reveal it:
the corrections ``C`` of the largest and the smallest sweep are compared bin by bin on the
bins both hold coherently, after removing the relative delay of their two alignments
(:func:`~tactilecal.dynamic._fit.fit_delay`), against the random error of each (Bendat &
Piersol eq. 9.90: the relative error of a complex ``C`` is ``e`` per component, so the
difference of two has a standard deviation ``sqrt(2 (e1^2 + e2^2))``).
"""

import numpy as np

from tactilecal.dynamic._fit import fit_delay
from tactilecal.dynamic._fitparts import AmplitudeCheck
from tactilecal.dynamic._ratfit import MATERIAL_ERROR, delayed

__all__ = ["compare_amplitudes", "MAX_RMS_Z"]

#: RMS of the differences in units of their standard error above which two sweeps differ
#: beyond their error bars (about 1 for a linear sensor; the error of Welch estimates with
#: overlapping segments is somewhat underestimated, so not 1).
MAX_RMS_Z = 3.0


def compare_amplitudes(tfs, amplitudes_N):
    """Compare the transfer functions of the largest and the smallest sweep.

    Parameters
    ----------
    tfs : sequence of TransferFunction
        One per sweep, on one frequency grid.
    amplitudes_N : sequence of float
        The sweeps' load amplitudes.

    Returns
    -------
    AmplitudeCheck
    """
    order = np.argsort(amplitudes_N)
    small, large = tfs[order[0]], tfs[order[-1]]
    common = small.used & large.used
    f_hz = small.f_hz[common]
    amplitudes = tuple(float(amplitudes_N[k]) for k in order[::-1])
    if f_hz.size < 2:
        return AmplitudeCheck(amplitudes, f_hz, np.empty(0), np.empty(0), float("nan"),
                              float("nan"), False)
    c_small, c_large = small.response[common], large.response[common]
    e_small, e_large = small.gain_error[common], large.gain_error[common]
    sigma = np.sqrt(2.0 * (e_small**2 + e_large**2))
    tau = fit_delay(f_hz, c_small, c_large, sigma)
    difference = np.abs(c_small - delayed(c_large, tau, f_hz)) / np.abs(c_large)
    z = difference / sigma
    rms_difference = float(np.sqrt(np.mean(difference**2)))
    rms_z = float(np.sqrt(np.mean(z**2)))
    return AmplitudeCheck(amplitudes, f_hz, difference, z, rms_difference, rms_z,
                          bool(rms_z > MAX_RMS_Z and rms_difference > MATERIAL_ERROR))
