"""Fit rational (pole-zero) sensor responses to a complex transfer function, choose the order.

A linear viscoelastic sensor (creep, compliant foam or mounting) relaxes with real time
constants, so its response ``H = sensor / reference`` is a ratio of first-order factors,
``H(f) = prod(1 + j f / fz_i) / prod(1 + j f / fp_i)`` with real positive corner
frequencies and unit gain at 0 Hz (the sweep was scaled statically): minimum-phase and
stable by construction, so ``1 / H`` is a stable causal
correction (METHOD-NOTES D: the standard linear solid is the first-order case). The corners
are fitted in log-frequency by :func:`scipy.optimize.least_squares` on the real and
imaginary parts of ``C - 1 / H`` over the coherent bins (``C`` = reference / sensor, the
measured correction), weighted by ``sqrt(coherence / (1 - coherence))`` (the inverse of the
bins' random error, Bendat & Piersol). Orders 1-4 are tried; the order is chosen by the
error on held-out blocks of bins (cross-validation, :func:`held_out_score`), and a higher
order must lower it by at least 10 % to be kept.
"""

from dataclasses import dataclass

import numpy as np
from scipy import optimize

from tactilecal._errors import TactilecalError
from tactilecal.dynamic._fit import complex_r2
from tactilecal.dynamic._rational import RationalModel

__all__ = ["RationalFit", "fit_rational", "choose_rational"]

ORDERS = (1, 2, 3, 4)
HELD_OUT_EVERY = 4
#: Consecutive bins held out together: Welch's Hann window spreads a tone over about four
#: bins, so neighbouring bins are correlated and a single held-out bin would be "predicted"
#: by its own leakage into the bins beside it (which flatters an interpolating model).
HELD_OUT_BLOCK = 4


def held_out_score(measured, predicted, gain_error):
    """Relative error of a model on held-out bins: RMS of ``|C - model| / |C|``, weighted.

    Each bin is weighted by ``1 / e^2``, ``e`` its gain's normalised random error (Bendat &
    Piersol eq. 9.90; the phase's error in radians is the same number), so noisy bins at
    the band's edges do not outweigh clean ones. 0.01 is a 1 % error of the correction.
    """
    measured = np.asarray(measured, dtype=complex)
    weight = 1.0 / np.maximum(np.asarray(gain_error, dtype=float), 1e-9) ** 2
    relative = np.abs(measured - predicted) ** 2 / np.abs(measured) ** 2
    return float(np.sqrt(np.sum(weight * relative) / np.sum(weight)))


def held_out_bins(n_bins):
    """Mask of the held-out bins: every ``HELD_OUT_EVERY``-th block of ``HELD_OUT_BLOCK``."""
    block = np.arange(n_bins) // HELD_OUT_BLOCK
    return block % HELD_OUT_EVERY == HELD_OUT_EVERY // 2
MIN_IMPROVEMENT = 0.10
#: Highest corner frequency, as a share of the Nyquist frequency (see :func:`fit_rational`).
MAX_CORNER_NYQUIST = 0.8
#: A held-out error below this (1 % of the correction, about the resolution of an 8-bit
#: sensel at mid-range) is immaterial: a model this good is not replaced by one with more
#: parameters, however much better that one fits a long, clean sweep (which resolves 0.1 %).
MATERIAL_ERROR = 0.01


@dataclass
class RationalFit:
    """A rational model fitted to a measured complex correction.

    Attributes
    ----------
    model : RationalModel
        The sensor response ``H`` (its :meth:`~RationalModel.correction` is the fitted ``C``).
    order : int
        Number of zeros (= number of poles).
    r2_complex : float
        Share of the complex correction explained on all used bins (:func:`complex_r2`).
    held_out_error : float
        :func:`held_out_score` of the held-out bins (the model was fitted without them).
    candidates : dict
        ``{order: held_out_error}`` of every order tried (``inf`` when its fit failed).
    delay_s : float
        The sensor's own delay that the clock alignment had absorbed (fitted jointly).
    """

    model: RationalModel
    order: int
    r2_complex: float
    held_out_error: float
    candidates: dict
    delay_s: float = 0.0

    def summary(self):
        """Return a one-line description with the corner frequencies."""
        zeros = ", ".join(f"{-z.real / (2 * np.pi):.4g}" for z in self.model.zeros_rad_s)
        poles = ", ".join(f"{-p.real / (2 * np.pi):.4g}" for p in self.model.poles_rad_s)
        return (f"rational order {self.order}: zeros at {zeros} Hz, poles at {poles} Hz, "
                f"gain {self.model.gain:.4g}, delay {1e3 * self.delay_s:.3g} ms; complex R2 "
                f"{self.r2_complex:.4f}, held-out error {self.held_out_error:.3g}")


def _model(x, order):
    """RationalModel from parameters ``[delay_ms, log fz_1..n, log fp_1..n]`` (Hz).

    Unit gain at 0 Hz: the sweep was scaled statically (mean reference / mean sensor), so
    ``H(0) = 1``, and a correction must leave a static calibration untouched.
    """
    fz, fp = np.exp(x[1:order + 1]), np.exp(x[order + 1:])
    return RationalModel.from_corners_hz(zeros_hz=fz, poles_hz=fp)


def _delayed_correction(model, delay_s, f_hz):
    """``1/H`` times the residual clock delay ``exp(-j 2 pi f delay)``: the fitted ``C``."""
    return model.correction(f_hz) * np.exp(-2j * np.pi * f_hz * delay_s)


def _correction(x, order, f_hz):
    """:func:`_delayed_correction` of the parameters ``x`` (``x[0]``: the delay in ms)."""
    return _delayed_correction(_model(x, order), x[0] * 1e-3, f_hz)


def _residuals(x, order, f_hz, measured, weight):
    diff = weight * (measured - _correction(x, order, f_hz))
    return np.concatenate([diff.real, diff.imag])


def fit_rational(f_hz, correction, coherence, order, *, fit_mask=None, max_delay_ms=5.0,
                 fs_hz=None):
    """Fit a rational response of ``order`` zeros and poles to a measured correction.

    Parameters
    ----------
    f_hz, correction, coherence : array_like
        Used bins: frequency, measured complex ``C`` = reference / sensor, coherence.
    order : int
        Zeros = poles = ``order`` (1-4).
    fit_mask : array_like of bool, optional
        Bins to fit (the rest are held out); default all.
    max_delay_ms : float
        Bound of the residual delay fitted jointly with the model: the clocks were aligned
        by cross-correlation, which takes the sensor's own group delay for clock offset.
    fs_hz : float, optional
        Sampling rate: corners are kept below ``MAX_CORNER_NYQUIST`` of its Nyquist
        frequency, where a causal (bilinear) inverse can still place them; a corner beyond
        would only mimic a gain that keeps rising, and its inverse would amplify the noise
        far above the band.

    Returns
    -------
    (RationalModel, float)
        The sensor response and the residual delay in s (the sensor's group delay that the
        alignment absorbed: the clock offset is the alignment's lag minus it).
    """
    f_hz = np.asarray(f_hz, dtype=float)
    measured = np.asarray(correction, dtype=complex)
    coherence = np.clip(np.asarray(coherence, dtype=float), 0.0, 0.999)
    weight = np.sqrt(coherence / (1 - coherence))
    mask = np.ones(f_hz.size, bool) if fit_mask is None else np.asarray(fit_mask, bool)
    lo, hi = np.log(max(f_hz.min(), 1e-3) / 4), np.log(f_hz.max() * 4)
    top = hi + 2 if fs_hz is None else min(hi + 2, np.log(MAX_CORNER_NYQUIST * fs_hz / 2))
    hi = min(hi, top)
    best = None
    for shift in (0.0, 0.5):  # two spreads of starting corners; keep the better fit
        corners = np.linspace(lo, hi, 2 * order + 2)[1:-1]
        corners = corners + shift * (corners[1] - corners[0]) if order > 0 else corners
        zeros, poles = corners[1::2], corners[0::2]  # poles below zeros: a falling gain
        start = np.concatenate([[0.0], zeros, poles])
        sol = optimize.least_squares(
            _residuals, start, args=(order, f_hz[mask], measured[mask], weight[mask]),
            bounds=(np.r_[-max_delay_ms, [lo - 2] * 2 * order],
                    np.r_[max_delay_ms, [top] * 2 * order]))
        if best is None or sol.cost < best.cost:
            best = sol
    return _model(best.x, order), float(best.x[0]) * 1e-3


def choose_rational(f_hz, correction, coherence, gain_error, *, orders=ORDERS, fs_hz=None):
    """Fit every order, choose by held-out bins; return the :class:`RationalFit`.

    Every ``HELD_OUT_EVERY``-th block of bins is held out (:func:`held_out_bins`); each
    order is fitted on the others and scored on the held-out ones by
    :func:`held_out_score` (``gain_error``: each bin's). The lowest order within
    ``MIN_IMPROVEMENT`` of the best score wins (a higher order must earn its parameters);
    it is then refitted on all bins.

    ``fs_hz`` bounds the corners (see :func:`fit_rational`).

    Raises
    ------
    ValueError
        Fewer than ``4 * (max order + 1)`` bins.
    """
    f_hz = np.asarray(f_hz, dtype=float)
    correction = np.asarray(correction, dtype=complex)
    gain_error = np.asarray(gain_error, dtype=float)
    need = max(4 * (max(orders) + 1), HELD_OUT_EVERY * HELD_OUT_BLOCK)
    if f_hz.size < need:
        raise TactilecalError(f"{f_hz.size} coherent bins; a rational fit of order up to "
                              f"{max(orders)} needs at least {need}")
    held = held_out_bins(f_hz.size)
    scores = {}
    for order in orders:
        try:
            model, delay_s = fit_rational(f_hz, correction, coherence, order, fit_mask=~held,
                                           fs_hz=fs_hz)
        except (ValueError, np.linalg.LinAlgError):
            scores[order] = float("inf")
            continue
        predicted = _delayed_correction(model, delay_s, f_hz[held])
        scores[order] = held_out_score(correction[held], predicted, gain_error[held])
    best = min(scores.values())
    order = min(o for o, s in scores.items() if s <= best * (1 + MIN_IMPROVEMENT))
    model, delay_s = fit_rational(f_hz, correction, coherence, order, fs_hz=fs_hz)
    r2 = complex_r2(correction, _delayed_correction(model, delay_s, f_hz))
    return RationalFit(model, order, r2, scores[order], scores, delay_s)
