"""``auto``: choose the method by its error on held-out patches (grouped cross-validation).

Every candidate is fitted on the patches of ``folds - 1`` folds and predicts the loads of the
fold left out, ``repeats`` times over differently drawn folds; each patch's squared relative
error ``(predicted / load - 1)**2`` is averaged over the repeats, and a candidate's score is
the root mean square over the patches (patches whose load is only a lower bound are not
scored). The candidates are in order of preference, simplest first; the first whose mean
squared error exceeds the best's by no more than ``margin_se`` standard errors of the
patch-by-patch difference is chosen and refitted on every patch: the "one standard error
rule" (Hastie, Tibshirani & Friedman 2009, sec. 7.10), on paired differences, which cancel
what the patches share. Folds are groups of points: the points of one recording stay
together and the frames of a movie are cut into contiguous blocks, so a held-out point
never has its twin in the training set.

Zvyagin's method is not a candidate: its default (robust) law is the power law with the
objective chosen by cross-validation, which the ``power`` candidates already cover.
"""

import warnings
from dataclasses import asdict, dataclass, field

import numpy as np

from tactilecal._errors import TactilecalError
from tactilecal._validate import check_number, check_type, require_keys
from tactilecal.calibration._fit import MethodOptions, check_positive_number, option
from tactilecal.calibration._models import check_law, force_table
from tactilecal.calibration.methods import linear_offset, lut, piecewise, polynomial, power

__all__ = ["NAME", "Options", "Selection", "CANDIDATES", "MIN_PATCHES", "candidate", "fold_of",
           "groups_of", "select"]

NAME = "auto"

CANDIDATES = ("power:l1", "power:relative", "power:l2", "lut", "piecewise", "polynomial")
"""Candidates as ``method`` or ``method:objective``, in order of preference: the power law
(2 parameters) with each objective, then the flexible laws. ``lut`` (a table smoothed toward
the power law) comes before ``piecewise`` and ``polynomial``: on the family of simulated
sensors it was never worse than them where the response is curved, and the polynomial,
unconstrained between its points, was the most often misled by the folds."""

_MODULES = {m.NAME: m for m in (power, polynomial, piecewise, lut, linear_offset)}

MARGIN_SE = 1.0
"""Default ``margin_se``: one standard error of the paired difference.

Chosen by the worst case over the family of simulated sensors
(``benchmarks/bench_static_auto.py``): fixed margins of 2-10 % of the best error let the
folds pick a power law's objective or a polynomial that held-out patches then found up to
1.29x worse, where one paired standard error kept every session within 1.10x of the best
method (margins of 0.5 or 2 standard errors: up to 1.29x and 1.67x)."""

REPEATS = 3
"""Default ``repeats`` of the cross-validation: with one, the fold draw alone moved the
choice between objectives of the power law on the heavy-tailed 9500 member."""

MIN_PATCHES = 6
"""Fewer scorable patches (or a single load) than this: no cross-validation, ``power``."""

MAX_CV_POINTS = 2000
"""More points than this (a movie's frames) are thinned evenly for the cross-validation;
the chosen method is fitted on every point."""


@dataclass(frozen=True)
class Options(MethodOptions):
    """Options of ``auto``."""

    candidates: tuple = option(CANDIDATES, "methods to choose from, method or "
                                           "method:objective, in order of preference",
                               metavar="M1,M2,...")
    folds: int = option(5, "folds of the cross-validation over groups of patches")
    repeats: int = option(REPEATS, "cross-validations over differently drawn folds")
    margin_se: float = option(MARGIN_SE, "take the first candidate whose held-out error "
                                         "exceeds the best's by no more than this many "
                                         "standard errors")

    def _check(self):
        for text in self.candidates:
            name, _, objective = str(text).partition(":")
            if name not in _MODULES:
                raise TactilecalError(f"candidates: {text!r} is not a method auto can choose; "
                                      f"expected some of {sorted(_MODULES)} (with "
                                      "':objective' where the method has one)")
            if objective:
                _MODULES[name].Options(objective=objective)  # an unknown objective says so
        for name, least in (("folds", 2), ("repeats", 1)):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, int) or value < least:
                raise TactilecalError(f"{name}={value!r}; expected a whole number >= {least}")
        check_positive_number(self.margin_se, "margin_se", NAME, zero=True)


@dataclass(frozen=True)
class Selection:
    """How ``method="auto"`` chose a calibration's method.

    Attributes
    ----------
    chosen : str
        The candidate chosen, ``method`` or ``method:objective``.
    reason : str
        Why, in one sentence (or why no cross-validation was possible).
    folds, repeats : int
    margin_se : float
        How many standard errors of the paired difference a preferred candidate may be
        worse than the best.
    scores : list of dict
        One per candidate: ``candidate``, ``rms_rel`` (held-out RMS relative error, None
        when it could not be fitted on every fold), ``excess_se`` (its mean squared error
        above the best's, in standard errors of the paired difference), ``n_scored``,
        ``note``.
    """

    chosen: str
    reason: str
    folds: int
    repeats: int
    margin_se: float
    scores: list = field(default_factory=list)

    def best(self):
        """Return the score row with the smallest held-out error (None without scores)."""
        scored = [s for s in self.scores if s["rms_rel"] is not None]
        return min(scored, key=lambda s: s["rms_rel"]) if scored else None

    def best_power(self):
        """Return the power-law candidate with the smallest held-out error (or None)."""
        scored = [s for s in self.scores
                  if s["rms_rel"] is not None and s["candidate"].startswith("power")]
        return min(scored, key=lambda s: s["rms_rel"])["candidate"] if scored else None

    def lines(self):
        """Return the selection as lines of text (for summaries and reports)."""
        out = [f"method chosen by auto: {self.reason}"]
        for s in self.scores:
            score = "not fitted: " + s["note"] if s["rms_rel"] is None \
                else f"{100 * s['rms_rel']:.2f} % held-out RMS error"
            mark = " <- chosen" if s["candidate"] == self.chosen else ""
            out.append(f"  {s['candidate']:<16} {score}{mark}")
        return out

    def to_dict(self):
        """Return the JSON-ready dictionary."""
        return asdict(self)

    @classmethod
    def from_dict(cls, data, where):
        """Rebuild from :meth:`to_dict` output, checking every key (``where`` names it)."""
        require_keys(data, ("chosen", "reason", "folds", "repeats", "margin_se", "scores"),
                     where, expected="a method selection")
        scores = check_type(data["scores"], list, f"{where}, scores", expected="a list")
        for k, row in enumerate(scores):
            require_keys(check_type(row, dict, f"{where}, scores entry {k}",
                                    expected="an object"),
                         ("candidate", "rms_rel", "excess_se", "n_scored", "note"),
                         f"{where}, scores entry {k}", expected="a candidate's score")
            check_number(row["rms_rel"], f"{where}, scores entry {k}, rms_rel", minimum=0,
                         allow_none=True)
        return cls(chosen=check_type(data["chosen"], str, f"{where}, chosen",
                                     expected="a text"),
                   reason=check_type(data["reason"], str, f"{where}, reason",
                                     expected="a text"),
                   folds=int(check_number(data["folds"], f"{where}, folds", minimum=0,
                                          integer=True)),
                   repeats=int(check_number(data["repeats"], f"{where}, repeats", minimum=0,
                                            integer=True)),
                   margin_se=check_number(data["margin_se"], f"{where}, margin_se", minimum=0),
                   scores=[dict(r) for r in scores])


def candidate(text):
    """Return ``(module, options)`` of a candidate written ``method`` or ``method:objective``.

    Examples
    --------
    >>> module, options = candidate("power:relative")
    >>> module.NAME, options.objective
    ('power', 'relative')
    """
    name, _, objective = text.partition(":")
    module = _MODULES[name]
    return module, module.Options(objective=objective) if objective else module.Options()


def fold_of(groups, folds, seed=0):
    """Assign each point to a fold so that the points of one group share their fold.

    Parameters
    ----------
    groups : array_like
        A group label per point (its recording, or a block of a movie's frames).
    folds : int

    Returns
    -------
    numpy.ndarray of int
        The fold of each point, 0..folds-1, groups spread at random (fixed ``seed``) and
        evenly over the folds.

    Examples
    --------
    >>> fold_of(["a", "a", "b", "c", "d", "e"], 2).tolist()
    [1, 1, 0, 0, 0, 1]
    """
    names, index = np.unique(np.asarray(groups).astype(str), return_inverse=True)
    order = np.random.default_rng(seed).permutation(len(names))
    fold_of_group = np.empty(len(names), dtype=int)
    fold_of_group[order] = np.arange(len(names)) % folds
    return fold_of_group[index]


def groups_of(files, folds):
    """Group points for the folds: by recording, or in contiguous blocks of a few recordings.

    Points of one recording stay together. With fewer than ``2 * folds`` recordings (a
    movie, or points made in memory) the points are cut into ``10 * folds`` contiguous
    blocks in their order, so neighbouring frames fall in one fold.

    Examples
    --------
    >>> groups_of(["a.csv", "b.csv", "c.csv", "d.csv"], 2).tolist()
    ['a.csv', 'b.csv', 'c.csv', 'd.csv']
    >>> groups_of(["movie.csv"] * 4, 2).tolist()
    ['movie.csv#0', 'movie.csv#5', 'movie.csv#10', 'movie.csv#15']
    """
    files = np.asarray(files).astype(str)
    if len(np.unique(files)) >= 2 * folds:
        return files
    block = (np.arange(len(files)) * 10 * folds // max(len(files), 1)).astype(str)
    return np.char.add(np.char.add(files, "#"), block)


def select(data, options, groups):
    """Choose a method for ``data`` by grouped cross-validation (see the module docstring).

    Parameters
    ----------
    data : tactilecal.calibration._fit.FitData
        The points ``calibrate`` uses.
    options : Options
    groups : array_like
        A group label per point of ``data`` (:func:`groups_of`).

    Returns
    -------
    module, method options, Selection
        The chosen method, its options, and how it was chosen.

    Warns
    -----
    UserWarning
        Too few patches or loads for cross-validation: ``power`` is used, and says so.
    """
    if len(data.load_N) > MAX_CV_POINTS:  # neighbouring frames of a movie: a sample will do
        keep = np.linspace(0, len(data.load_N) - 1, MAX_CV_POINTS).astype(int)
        data, groups = data.rows(keep), np.asarray(groups)[keep]
    exact = np.ones(len(data.load_N), bool) if data.censored is None else ~data.censored
    n_loads = len(np.unique(np.round(data.load_N[exact], 6)))
    record = {"folds": options.folds, "repeats": options.repeats,
              "margin_se": options.margin_se}
    folds = [fold_of(groups, options.folds, seed=r) for r in range(options.repeats)]
    if exact.sum() < MIN_PATCHES or n_loads < 2 or len(np.unique(folds[0])) < 2:
        reason = (f"{int(exact.sum())} patches with an exact load, {n_loads} load(s): too few "
                  f"to cross-validate (at least {MIN_PATCHES} patches and 2 loads); "
                  "method 'power' used")
        warnings.warn(f"method='auto': {reason}", UserWarning, stacklevel=4)
        return power, power.Options(), Selection(chosen="power", reason=reason, **record)
    squared = _squared_errors(options.candidates, data, folds, exact)
    good = {t: sq for t, sq in squared.items() if not isinstance(sq, str)}
    if not good:
        raise TactilecalError("method='auto': no candidate could be fitted on every fold ("
                              + "; ".join(f"{t}: {n}" for t, n in squared.items())
                              + "); expected more patches, or an explicit method")
    best = min(good, key=lambda t: good[t].mean())
    excess = {t: _excess_se(sq, good[best]) for t, sq in good.items()}
    chosen = next(t for t in options.candidates if t in good
                  and excess[t] <= options.margin_se)
    scores = [{"candidate": t, "rms_rel": float(np.sqrt(good[t].mean())) if t in good else None,
               "excess_se": excess.get(t), "n_scored": int(exact.sum()) if t in good else 0,
               "note": "" if t in good else squared[t]} for t in options.candidates]
    rms = {row["candidate"]: row["rms_rel"] for row in scores}
    reason = (f"{chosen}: held-out RMS error {100 * rms[chosen]:.2f} %, the first candidate "
              f"within {options.margin_se:g} standard error(s) of the best ({best}, "
              f"{100 * rms[best]:.2f} %) in {options.repeats} x {options.folds}-fold "
              "cross-validation")
    module, chosen_options = candidate(chosen)
    return module, chosen_options, Selection(chosen=chosen, reason=reason, scores=scores,
                                             **record)


def _excess_se(squared, best):
    """Return the mean of ``squared - best`` in standard errors of that paired difference."""
    diff = squared - best
    if diff.mean() <= 1e-6 * best.mean() + 1e-12:  # equal to round-off (noise-free loads)
        return 0.0
    se = diff.std(ddof=1) / np.sqrt(len(diff))
    return float(diff.mean() / se) if se > 0 else float("inf")


def _squared_errors(candidates, data, folds, exact):
    """Each exact patch's held-out squared relative error, averaged over the repeats.

    Returns a dict: per candidate the array, or the reason it could not be fitted on every
    fold. The candidates are fitted on one fold's training rows after another, so they
    share what those rows give them all (:attr:`FitData.memo`: the power law that
    ``power:l1`` is and ``lut`` and ``piecewise`` start from).
    """
    methods = {text: candidate(text) for text in candidates}
    total = {text: np.zeros(int(exact.sum())) for text in candidates}
    failed = {}
    for fold in folds:
        error = {text: np.full(len(data.load_N), np.nan) for text in candidates}
        for k in np.unique(fold):
            train, held = data.rows(fold != k), fold == k
            for text in candidates:
                if text not in failed:
                    _fold_error(text, *methods[text], train, data, held, k, error, failed)
        for text in candidates:
            if text not in failed:  # a failed candidate's errors are not all written
                total[text] += error[text][exact] ** 2
    return {text: failed.get(text, total[text] / len(folds)) for text in candidates}


def _fold_error(text, module, options, train, data, held, k, error, failed):
    """Fit one candidate on one fold's ``train`` rows and score it on its ``held`` rows.

    Writes the relative errors of the held rows of ``data`` into ``error[text]``, or why
    the candidate could not be fitted into ``failed[text]``.
    """
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # a fold's warnings are not the user's
            fit = module.fit(train, options)
        check_law(fit.model, fit.params, f"fold {k + 1}")
    except (TactilecalError, np.linalg.LinAlgError) as exc:
        failed[text] = str(exc)
        return
    error[text][held] = data.hist[held] @ force_table(fit.model, fit.params) \
        / data.load_N[held] - 1.0
