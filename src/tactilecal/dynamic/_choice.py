"""Candidate models of a measured correction, each with its delay, and the choice between them.

Every candidate carries a delay ``tau`` fitted jointly with it (METHOD-NOTES G: at 100 Hz a
2.5 ms error is a 90 degree phase error), so the filter's clock offset is the alignment's
lag minus ``tau``:

``log10`` (or the thesis model asked for)
    eq. 4.1 fitted to the gain, its delay to the phase (:func:`fit_delay`).
``rational``
    sections of real corners and complex pairs, the structure chosen on held-out bins,
    the delay fitted with them (:func:`choose_rational`).
``wiener``
    the measured complex correction shrunk by its random error
    (:mod:`~tactilecal.dynamic._wiener`). A correction with a parameter per bin cannot tell a
    pure delay from the sensor's own phase (METHOD-NOTES D), so its delay is the one the
    rational model found on the same bins (a causal, minimum-phase description), or the
    thesis model's when no rational model could be fitted; the correction is taken with
    that delay removed.

:func:`choose_model` scores the candidates on held-out blocks of bins (the log model, one
parameter, on the same bins) and orders them: for ``auto``, the simplest (log10, rational,
wiener) whose error is within 10 % of the best or under ``MATERIAL_ERROR`` (1 %) first, then
the others by score, in case the first is refused.
"""

from dataclasses import dataclass, field

import numpy as np

from tactilecal.dynamic._fitparts import ModelChoice
from tactilecal.dynamic._ratfit import (
    MATERIAL_ERROR,
    MIN_IMPROVEMENT,
    choose_rational,
    delayed,
    held_out_bins,
    held_out_score,
)
from tactilecal.dynamic._wiener import wiener_correction, wiener_held_out

__all__ = ["Candidate", "choose_model", "CHOSEN_MODELS", "BY_COMPLEXITY"]

#: Models :func:`fit_filter` fits beside the thesis' log model, and ``auto``, that chooses.
CHOSEN_MODELS = ("auto", "rational", "wiener")
#: Candidates of ``auto`` from the fewest parameters to the most: a later one must be 10 %
#: better.
BY_COMPLEXITY = ("log10", "rational", "wiener")


@dataclass
class Candidate:
    """A model of the measured correction, ready to become a filter.

    Attributes
    ----------
    name : str
        The filter's ``model``.
    label : str
        Name with the rational structure (``"rational (1 zero, 1 pole)"``).
    score, r2_complex, delay_s : float
        Held-out error, share of the complex correction explained (wiener: of held-out
        bins), delay fitted with it (s).
    design : dict
        Keyword arguments of :meth:`CorrectionFilter.design` (``model``, ``params`` and
        ``rational`` or the measured response).
    """

    name: str
    label: str
    score: float
    r2_complex: float
    delay_s: float
    design: dict = field(default_factory=dict)


def _log_candidate(fit, f_hz, measured, error, held):
    predicted = delayed(fit.fitted, fit.delay_s, f_hz)
    return Candidate(fit.model, fit.model, held_out_score(measured[held], predicted[held],
                                                           error[held]),
                     fit.r2_complex, fit.delay_s, {"model": fit.model, "params": fit.params})


def _rational_candidate(f_hz, measured, error, fs_hz, start_delay_s):
    rfit = choose_rational(f_hz, measured, error, fs_hz=fs_hz, delay_s=start_delay_s)
    return Candidate("rational", f"rational ({rfit.structure.label})", rfit.held_out_error,
                     rfit.r2_complex, rfit.delay_s,
                     {"model": "rational", "params": rfit.structure.as_params(),
                      "rational": rfit.model}), rfit


def _wiener_candidate(f_hz, measured, error, held, delay_s):
    undelayed = delayed(measured, -delay_s, f_hz)  # the correction at the fitted clock
    score, r2 = wiener_held_out(f_hz, undelayed, error, held)
    return Candidate("wiener", "wiener", score, r2, delay_s,
                     {"model": "wiener", "params": {"bins": int(f_hz.size)},
                      "response_f_hz": f_hz, "response_gain": wiener_correction(undelayed,
                                                                                 error)})


def choose_model(tf, log_fit, model):
    """Fit the candidates ``model`` asks for, score them, order them.

    Parameters
    ----------
    tf : TransferFunction
        The measured (pooled) transfer function; its used bins are fitted.
    log_fit : TransferFit
        The thesis model fitted to them (with its delay).
    model : str
        ``"auto"``, ``"rational"``, ``"wiener"`` or a thesis model.

    Returns
    -------
    choice : ModelChoice
        Scores, the first in order as ``chosen``, structures tried, notes.
    candidates : dict
        ``{name: Candidate}``.
    order : list of str
        The names to try, the chosen first (empty when the model asked for could not be
        fitted: ``choice.notes`` say why).
    """
    used = tf.used
    f_hz, measured, error = tf.f_hz[used], tf.response[used], tf.gain_error[used]
    held = held_out_bins(f_hz.size)
    log = _log_candidate(log_fit, f_hz, measured, error, held)
    candidates, notes, rfit = {log.name: log}, [], None
    wanted = BY_COMPLEXITY[1:] if model == "auto" else (model,)
    if "rational" in wanted:
        try:
            candidates["rational"], rfit = _rational_candidate(f_hz, measured, error, tf.fs_hz,
                                                               log_fit.delay_s)
        except ValueError as exc:  # e.g. too few coherent bins
            notes.append(f"no rational fit: {exc}")
    if "wiener" in wanted:
        if held.sum() >= 2 and (~held).sum() >= 2:
            delay_s = rfit.delay_s if rfit is not None else log_fit.delay_s
            candidates["wiener"] = _wiener_candidate(f_hz, measured, error, held, delay_s)
        else:
            notes.append(f"no wiener fit: {f_hz.size} coherent bins; expected at least 4")
    scores = {name: c.score for name, c in candidates.items()}
    enough = max(MATERIAL_ERROR, min(scores.values()) * (1 + MIN_IMPROVEMENT))
    if model == "auto":
        good = [m for m in BY_COMPLEXITY if scores.get(m, np.inf) <= enough]
        order = good + sorted((m for m in scores if m not in good), key=scores.get)
    else:
        order = [model] if model in candidates else []
    choice = ModelChoice(
        chosen=order[0] if order else "", notes=tuple(notes),
        scores={candidates[m].label: scores[m] for m in scores},
        structures={} if rfit is None else dict(rfit.candidates),
        rational="" if rfit is None else rfit.summary())
    return choice, candidates, order
