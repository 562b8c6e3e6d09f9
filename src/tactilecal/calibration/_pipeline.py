"""The preprocessing of a static calibration: equilibration gains and non-working sensels.

Gillis (2013), sec. 3.5: the raw frames are equilibrated (per-sensel gains) and the
non-working sensels left out *before* the calibration law is fitted, and a recording is
treated the same way before the law is applied. :func:`calibrate` does the first step for
a manifest and keeps both on the result (``equilibration`` and ``non_working``), where
:meth:`CalibrationResult.apply` finds them.
"""

import os

import numpy as np

from tactilecal.calibration._manifest import load_frames, load_points
from tactilecal.calibration._sensels import (
    Equilibration,
    NonWorkingSensels,
    find_dead_sensels,
    load_equilibration,
)

__all__ = ["MASK_DETECT", "as_equilibration", "chain", "is_path", "manifest_points",
           "reading_options"]

MASK_DETECT = "detect"
"""``mask="detect"``: find the non-working sensels over the manifest's frames."""


def is_path(value):
    """Whether ``value`` names a file (str or os.PathLike), not data."""
    return isinstance(value, str | os.PathLike)


def as_equilibration(equilibration):
    """Return ``equilibration`` as an :class:`Equilibration` (None stays None).

    Parameters
    ----------
    equilibration : Equilibration, str, os.PathLike or None
        The gains, or the path of their JSON (:func:`load_equilibration`).

    Raises
    ------
    TypeError
        For anything else.
    """
    if equilibration is None or isinstance(equilibration, Equilibration):
        return equilibration
    if is_path(equilibration):
        return load_equilibration(equilibration)
    raise TypeError(f"equilibration is a {type(equilibration).__name__}; expected an "
                    "Equilibration, the path of its JSON, or None")


def chain(first, then):
    """Return the equilibration that applies ``first``, then ``then`` (either may be None).

    Gains multiply: ``x * g1 * g2`` (Equilibration.apply clips at 255 and keeps 255).

    Examples
    --------
    >>> a = Equilibration(gain=np.full((1, 2), 2.0)); b = Equilibration(gain=np.full((1, 2), 0.5))
    >>> chain(a, b).gain.tolist(), chain(None, b) is b
    ([[1.0, 1.0]], True)
    """
    if first is None or then is None:
        return then if first is None else first
    return Equilibration(gain=first.gain * then.gain, levels=first.levels)


def reading_options(progress):
    """Keywords of :func:`load_points`/:func:`load_frames` for the ``progress`` protocol.

    ``progress`` is None (no bar) or a callable ``progress(iterable, total=, desc=)``.
    """
    if progress is not None and not callable(progress):
        raise TypeError(f"progress is a {type(progress).__name__}; expected None or a "
                        "callable progress(iterable, total=, desc=)")
    return {"progress": progress}


def _as_dead(mask, manifest, equilibration, progress):
    """Return the non-working sensels ``mask`` names (None for none)."""
    if mask is None or isinstance(mask, NonWorkingSensels):
        return mask
    if isinstance(mask, str) and mask == MASK_DETECT:
        frames = load_frames(manifest, equilibration=equilibration,
                             **reading_options(progress))
        return find_dead_sensels(frames)
    values = np.asarray(mask) if not isinstance(mask, str | bool) else None
    if values is None or values.dtype != bool or values.ndim != 2:
        raise TypeError(f"mask is {_describe(mask)}; expected {MASK_DETECT!r}, a "
                        "NonWorkingSensels, a 2-d boolean array (rows, cols) or None")
    return NonWorkingSensels(mask=values, evidence_frames=np.zeros(values.shape, int),
                             n_frames=0)


def _describe(value):
    if isinstance(value, str):
        return repr(value)
    shape = getattr(np.asarray(value, dtype=object), "shape", ())
    return f"a {type(value).__name__} of shape {shape}" if shape else \
        f"a {type(value).__name__}"


def manifest_points(manifest, *, equilibration=None, mask=None, progress=None):
    """Read a manifest's points with the calibration's preprocessing applied.

    Parameters
    ----------
    manifest : str or os.PathLike
        Calibration manifest CSV (:func:`load_points`).
    equilibration : Equilibration, str, os.PathLike or None
        Gains applied to every frame first (or the path of their JSON).
    mask : {"detect"}, NonWorkingSensels, array_like of bool or None
        Non-working sensels to leave out: ``"detect"`` finds them over the manifest's
        (equilibrated) frames with :func:`find_dead_sensels`, as ``tactilecal calibrate
        --mask-dead`` does.
    progress : callable, optional
        ``progress(iterable, total=, desc=)`` shown while reading (None: no bar).

    Returns
    -------
    points : list of CalibrationPoint
    dead : NonWorkingSensels or None
    equilibration : Equilibration or None
    """
    equilibration = as_equilibration(equilibration)
    dead = _as_dead(mask, manifest, equilibration, progress)
    points = load_points(manifest, mask=None if dead is None else dead.mask,
                         equilibration=equilibration, **reading_options(progress))
    return points, dead, equilibration
