"""Contact loads on the sensor: rigid pads on an uneven base (Winkler-like contact)."""

import numpy as np
from scipy.ndimage import gaussian_filter
from scipy.optimize import brentq

from tactilecal._units import G_STANDARD, KPA_MM2_TO_N

__all__ = ["G_STANDARD", "PAD_MASS_G", "smooth_field", "winkler_contact", "block_sum"]

PAD_MASS_G = {1: 0.6, 2: 2.6, 3: 5.9, 4: 10.6, 5: 16.1}
"""Plexiglass pad mass in g by pad side in cm (Zvyagin 2022, Table 1)."""


def smooth_field(rng, shape, sigma_cells, std):
    """Gaussian random field of standard deviation ``std`` smoothed over ``sigma_cells``.

    White noise filtered with :func:`scipy.ndimage.gaussian_filter` over the last two axes
    (leading axes are independent fields), then rescaled to ``std`` per field.
    ``sigma_cells`` is one smoothing length or ``(rows, cols)`` lengths, in cells.
    """
    noise = rng.standard_normal(shape)
    sigma = (0,) * (len(shape) - 2) + tuple(np.broadcast_to(sigma_cells, 2))
    field = gaussian_filter(noise, sigma=sigma, mode="wrap", truncate=3.0)
    field -= field.mean(axis=(-2, -1), keepdims=True)
    scale = field.std(axis=(-2, -1), keepdims=True)
    return field * (std / np.where(scale > 0, scale, 1.0))


def winkler_contact(gap_um, load_N, *, stiffness_kPa_per_um, cell_area_mm2):
    """Pressure under a rigid pad pressed into a Winkler foundation with load ``load_N``.

    The pad sinks by ``delta`` (um); each cell of the contact carries
    ``p = k * max(0, delta - gap)`` (kPa), and ``delta`` is solved with
    :func:`scipy.optimize.brentq` so that ``sum(p) * cell_area`` equals the load.

    Parameters
    ----------
    gap_um : numpy.ndarray
        ``(n, ny, nx)`` initial gap between pad and base in um, one field per patch.
    load_N : array_like
        ``(n,)`` load of each patch in N.
    stiffness_kPa_per_um : float
        Foundation modulus ``k``.
    cell_area_mm2 : float
        Area of one cell of ``gap_um``.

    Returns
    -------
    numpy.ndarray
        ``(n, ny, nx)`` contact pressure in kPa; ``sum * cell_area_mm2 * 1e-3`` equals the
        load to brentq's tolerance (callers rescale for exact totals).

    Examples
    --------
    >>> p = winkler_contact(np.zeros((1, 2, 2)), [4.0], stiffness_kPa_per_um=1.0,
    ...                     cell_area_mm2=1000.0)
    >>> np.round(p, 6).tolist()
    [[[1.0, 1.0], [1.0, 1.0]]]
    """
    load = np.asarray(load_N, dtype=np.float64)
    flat = gap_um.reshape(len(gap_um), -1)
    per_um_N = stiffness_kPa_per_um * cell_area_mm2 * KPA_MM2_TO_N  # N per um of overlap per cell
    delta = np.empty(len(flat))
    for i, (gap, force) in enumerate(zip(flat, load, strict=True)):
        lo = gap.min()
        hi = lo + force / per_um_N
        delta[i] = brentq(lambda d, g=gap, f=force: per_um_N * np.maximum(d - g, 0).sum() - f,
                          lo, hi, xtol=1e-9 * (hi - lo), rtol=1e-12)
    pressure = stiffness_kPa_per_um * np.maximum(delta[:, None] - flat, 0.0)
    return pressure.reshape(gap_um.shape)


def block_sum(fine, factor):
    """Sum ``(..., R*f, C*f)`` fine cells into ``(..., R, C)`` blocks of ``f x f``."""
    *lead, ny, nx = fine.shape
    return fine.reshape(*lead, ny // factor, factor, nx // factor, factor).sum(axis=(-3, -1))
