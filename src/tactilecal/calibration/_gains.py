"""A sensor's own gains, learned from its calibration patches with the law.

No global law removes a spatial gain field (edges less sensitive than the centre) or the
spread of gains between sensels; equilibration under a uniform load measures them, but a
dead-weight session holds the same information, spread over its patches. Each sensel's
reading is multiplied by a gain ``G_k = exp(g_k)`` with

``g = B theta + delta``,

a smooth surface (``B``: the terms ``u, v, u**2, u v, v**2`` of a quadratic over the
sensor, ``u`` and ``v`` in -1..1 across rows and columns) plus a per-sensel residual
``delta`` shrunk toward 0 by a ridge penalty ``lambda |delta|**2``. With the power law
``f = A x**b`` a patch's load is ``F_T = A sum_k exp(b g_k) x_kT**b``, and ``log A``, ``b``,
``theta`` and ``delta`` are fitted together by Gauss-Newton steps on the patches' relative errors,
from the power law without gains; ``delta`` is eliminated in the dual form (one system of
the size of the number of patches, whatever the number of sensels). The strength
(no gains, the surface alone, or the surface with a residual of ridge weight
:data:`RIDGE_WEIGHTS`) is chosen by held-out patches with the rule of
:mod:`tactilecal.calibration.methods.auto`, no gains first, the patches held out by the
place they pressed (:func:`spatial_folds`).
"""

import warnings

import numpy as np

from tactilecal._errors import TactilecalError
from tactilecal.calibration._points import frame_histograms
from tactilecal.calibration._powerfit import fit_power
from tactilecal.calibration._sensels import Equilibration
from tactilecal.calibration.methods.auto import _excess_se, fold_of

__all__ = ["CHOICES", "MARGIN_SE", "RIDGE_WEIGHTS", "learn_gains", "spatial_folds"]

RIDGE_WEIGHTS = (10.0, 1.0)
"""Ridge weights of the per-sensel residual, as multiples of the mean diagonal of
``J J^T`` (the squared sensitivity of a patch's relative error to the gains)."""

CHOICES = ("none", "surface", *(f"surface+residual/{w:g}" for w in RIDGE_WEIGHTS))
"""The strengths the held-out patches choose from, simplest first."""

ITERATIONS = 8
"""Gauss-Newton steps (each halved until the cost falls)."""

MARGIN_SE = 2.0
"""Gains are learned only when they beat the simpler strengths by this many standard errors
of the held-out difference. At one standard error (``auto``'s rule) a residual learned from
45 patches of a sensor with 12 % random gains won by 1.9 standard errors and made 500 new
patches 1.75 times worse; on a sensor whose edges are 15 % less sensitive the gains won by
5.4 and 7.6 standard errors (two sessions)."""

MAX_PATCHES = 400
"""Patches used to learn the gains (a movie's frames are thinned evenly to this many)."""


def learn_gains(readings, load_N, exact, *, folds=5, repeats=2, margin_se=MARGIN_SE,
                where="the points"):
    """Learn per-sensel gains from calibration frames and their loads, strength by CV.

    Parameters
    ----------
    readings : numpy.ndarray
        ``(n, rows, cols)`` raw frames of the used points (NaN outside the sensor).
    load_N : numpy.ndarray
        ``(n,)`` applied loads.
    exact : numpy.ndarray of bool
        Points whose load is exact (not a lower bound): those the gains are learned from.
    folds, repeats, margin_se
        The cross-validation and its rule (:mod:`tactilecal.calibration.methods.auto`):
        the simplest strength within ``margin_se`` standard errors of the best.
    where : str
        What the points are, for messages.

    Returns
    -------
    Equilibration or None
        The learned gains (None when no gains predicted held-out patches better).
    dict
        The record: ``chosen``, ``reason`` and ``scores`` (held-out RMS relative error per
        strength).

    Raises
    ------
    TactilecalError
        Fewer than 6 exact patches, or frames of different shapes.
    """
    readings = np.asarray(readings, dtype=float)
    keep = np.flatnonzero(exact)
    if len(keep) < 6:
        raise TactilecalError(f"{where}: {len(keep)} patches with an exact load; learning a "
                              "gain map needs at least 6")
    if len(keep) > MAX_PATCHES:
        keep = keep[np.linspace(0, len(keep) - 1, MAX_PATCHES).astype(int)]
    x, load = readings[keep], np.asarray(load_N, dtype=float)[keep]
    basis = _surface(x.shape[1:])
    splits = [spatial_folds(x, folds, seed=r) for r in range(repeats)]
    squared = {c: _cv_squared(c, x, load, basis, splits) for c in CHOICES}
    best = min(squared, key=lambda c: squared[c].mean())
    chosen = next(c for c in CHOICES if _excess_se(squared[c], squared[best]) <= margin_se)
    scores = [{"choice": c, "rms_rel": float(np.sqrt(squared[c].mean()))} for c in CHOICES]
    record = {"chosen": chosen, "scores": scores, "patches": len(load),
              "reason": f"{chosen}: held-out RMS error "
                        f"{100 * np.sqrt(squared[chosen].mean()):.2f} % against "
                        f"{100 * np.sqrt(squared['none'].mean()):.2f} % without gains "
                        f"({repeats} x {folds}-fold cross-validation over the places the "
                        "patches pressed)"}
    if chosen == "none":
        return None, record
    g, _ = _fit(chosen, x, load, basis)
    gain = np.where(np.isfinite(readings[0]), np.exp(g).reshape(readings.shape[1:]), np.nan)
    return Equilibration(gain=gain, levels=[]), record


def spatial_folds(x, folds, seed=0):
    """Assign patches to folds by where they pressed: held-out patches lie elsewhere.

    Gains learned from patches are used wherever the sensor is loaded later; folds of
    random patches let a residual learned at one spot be scored on patches at the same
    spot, which favoured residuals that did not hold on new positions. The patches'
    centres (reading-weighted) are clustered into ``2 * folds`` places (k-means,
    :func:`scipy.cluster.vq.kmeans2`, fixed ``seed``) and whole places go to a fold.

    Examples
    --------
    >>> x = np.zeros((8, 10, 10))
    >>> for k in range(8):
    ...     x[k, (k % 4) * 2, (k // 4) * 5] = 50.0  # 8 patches at 8 places
    >>> folds = spatial_folds(x, 2)
    >>> sorted(np.bincount(folds).tolist())
    [4, 4]
    >>> np.unique(spatial_folds(np.ones((6, 3, 3)), 2)).tolist()  # one place: at random
    [0, 1]
    """
    from scipy.cluster.vq import kmeans2

    w = np.nan_to_num(np.asarray(x, dtype=float))
    rows, cols = np.indices(w.shape[1:])
    total = w.sum(axis=(1, 2))
    total = np.where(total > 0, total, 1.0)
    centres = np.column_stack([(w * rows).sum(axis=(1, 2)) / total,
                               (w * cols).sum(axis=(1, 2)) / total])
    places = min(2 * folds, len(np.unique(centres, axis=0)))
    with warnings.catch_warnings():  # an empty cluster only means fewer places
        warnings.filterwarnings("ignore", message="One of the clusters is empty")
        _, label = kmeans2(centres, places, seed=seed, minit="++")
    if len(np.unique(label)) < 2:  # one place (a movie of one contact): patches at random
        label = np.arange(len(w))
    return fold_of(label.astype(str), folds, seed=seed)


def _surface(shape):
    """Return the quadratic surface's terms over the sensor: ``(rows * cols, 5)``."""
    u, v = np.meshgrid(np.linspace(-1, 1, shape[0]), np.linspace(-1, 1, shape[1]),
                       indexing="ij")
    u, v = u.ravel(), v.ravel()
    return np.column_stack([u, v, u * u, u * v, v * v])


def _corrected(x, g):
    """Return readings times their gains, rounded and clipped like a recording."""
    out = np.clip(np.rint(x * np.exp(g).reshape(x.shape[1:])), 0, 255)
    return np.where(x >= 255, 255.0, out)


def _start(x, load):
    """Return the power law without gains (relative least squares) as ``[log A, b]``."""
    law = fit_power(frame_histograms(x).astype(float), load, objective="relative").params
    return np.array([np.log(law["A"]), law["b"]])


def _fit(choice, x, load, basis):
    """Return the gains ``g`` (log, per sensel) and the law ``(A, b)`` learned with ``choice``.

    Gauss-Newton on ``p = (log A, b, theta)`` and ``delta`` (see the module docstring),
    each step halved until the penalised cost falls.
    """
    p = np.r_[_start(x, load), np.zeros(basis.shape[1])]
    delta = np.zeros(basis.shape[0])
    flat = np.nan_to_num(x.reshape(len(x), -1))
    with np.errstate(divide="ignore"):  # a reading of 0 carries no force: exp(-inf) = 0
        flat = np.log(flat)
    if choice != "none":
        weight = None if choice == "surface" else float(choice.split("/")[1])
        cost = _cost(p, delta, flat, load, basis, weight)
        for _ in range(ITERATIONS):
            step_p, new_delta = _step(p, delta, flat, load, basis, weight)
            for scale in (1.0, 0.5, 0.25, 0.125):
                trial_p = p + scale * step_p
                trial_delta = delta + scale * (new_delta - delta)
                trial = _cost(trial_p, trial_delta, flat, load, basis, weight)
                if trial < cost:
                    p, delta, cost = trial_p, trial_delta, trial
                    break
            else:
                break
    g = basis @ p[2:] + delta
    return g, {"A": float(np.exp(p[0])), "b": float(p[1])}


def _terms(p, delta, log_x, basis):
    """Return per patch and sensel ``exp(b g_k) x_k**b`` and ``g`` (``log_x``: log readings).

    A reading of 0 (``log_x`` = -inf) gives 0.
    """
    g = np.einsum("kp,p->k", basis, p[2:]) + delta
    return np.exp(p[1] * (g + log_x)), g


def _cost(p, delta, flat, load, basis, weight):
    """Return the sum of squared relative errors plus the ridge penalty."""
    terms, _ = _terms(p, delta, flat, basis)
    r = 1.0 - np.exp(p[0]) * terms.sum(axis=1) / load
    penalty = 0.0 if weight is None else \
        weight * _scale(p, terms, load) * float(np.sum(delta * delta))
    return float(np.sum(r * r)) + penalty


def _scale(p, terms, load):
    """Return the mean diagonal of ``J J^T``: the ridge weights are multiples of it."""
    jac = np.exp(p[0]) * p[1] * terms / load[:, None]
    return float(np.mean(np.sum(jac * jac, axis=1)))


def _step(p, delta, flat, load, basis, weight):
    """Return the Gauss-Newton step of ``p`` and the new ``delta`` (dual form).

    The products over sensels are written with :func:`numpy.einsum`, not BLAS: a few dozen
    patches by a few thousand sensels are too small for threads, which on busy cores
    waited milliseconds per product (five times the whole learning's time).
    """
    terms, g = _terms(p, delta, flat, basis)
    log_x = np.where(terms > 0, flat, 0.0)
    a = np.exp(p[0])
    predicted = a * terms.sum(axis=1) / load
    r = 1.0 - predicted
    jac = a * p[1] * terms / load[:, None]  # d(predicted / load) / d g_k
    design = np.column_stack([predicted, a * (terms * (g + log_x)).sum(axis=1) / load,
                              np.einsum("ik,kp->ip", jac, basis)])
    if weight is None:
        return np.linalg.lstsq(design, r, rcond=None)[0], delta
    y = r + np.einsum("ik,k->i", jac, delta)
    gram = np.einsum("ik,jk->ij", jac, jac)
    inverse = np.linalg.inv(gram + weight * _scale(p, terms, load) * np.eye(len(load)))
    step = np.linalg.lstsq(design.T @ inverse @ design, design.T @ inverse @ y, rcond=None)[0]
    return step, np.einsum("ik,i->k", jac, inverse @ (y - design @ step))


def _cv_squared(choice, x, load, basis, splits):
    """Return each patch's held-out squared relative error with ``choice`` (split mean)."""
    total = np.zeros(len(load))
    for fold in splits:
        for k in np.unique(fold):
            train, held = fold != k, fold == k
            g, law = _fit(choice, x[train], load[train], basis)
            hist = frame_histograms(_corrected(x[held], g)).astype(float)
            predicted = hist @ (law["A"] * np.arange(256.0) ** law["b"])
            total[held] += (predicted / load[held] - 1.0) ** 2
    return total / len(splits)
