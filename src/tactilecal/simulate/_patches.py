"""Dead-weight patches reduced to histograms: a fast, geometry-free session for fitting tests.

Where :func:`~tactilecal.simulate.deadweight_session` simulates a whole sensor under rigid
pads (gains, read noise, dead sensels, written files), :func:`patch_histograms` gives only
what a histogram method sees, with a known power law and nothing else: each patch is a
square pad with an uneven contact field (a few Gaussian bumps, peak 5-10x the periphery,
like Zvyagin 2022, Figure 4); each sensel's share of the load becomes a raw reading through
``f = A_N * X**b``, an optional per-sensel gain spread, rounding, the noise threshold
(readings below it read 0) and saturation at 255.
"""

import numpy as np

from tactilecal._units import mass_to_N
from tactilecal.simulate._loads import PAD_MASS_G

__all__ = ["patch_histograms"]


def _contact_field(side, rng):
    """Uneven positive weights on a side x side pad, peak 5-10x the periphery, summing to 1."""
    yy, xx = np.mgrid[0:side, 0:side] / max(side - 1, 1)
    field = np.full((side, side), 1.0)
    for _ in range(rng.integers(1, 4)):
        cy, cx = rng.uniform(0.2, 0.8, 2)
        width = rng.uniform(0.12, 0.35)
        field += rng.uniform(2.0, 5.0) * np.exp(-((yy - cy) ** 2 + (xx - cx) ** 2)
                                                / (2 * width ** 2))
    field *= rng.uniform(0.7, 1.3, field.shape)
    return field.ravel() / field.sum()


def patch_histograms(n_patches=60, *, A_N=0.0035, b=1.16, masses_kg=(2, 5, 10),
                     pad_sides_cm=(2, 3, 4), sensel_pitch_mm=None, gain_spread=0.0,
                     threshold=3, seed=0):
    """Simulate dead-weight patches as 256-bin histograms with a known per-sensel law.

    Each patch's load is ``(mass_kg + pad_mass_g / 1000) * g`` (pad masses of Zvyagin 2022,
    Table 1; g = 9.80665 m/s2), spread over the pad's sensels by an uneven contact field;
    sensel ``i`` reads ``round((F_i / A_N) ** (1 / b))`` (the inverse of ``f = A_N X**b``),
    clipped to 0..255, with readings below ``threshold`` set to 0.

    Parameters
    ----------
    n_patches : int
        Number of patches; masses and pads are drawn at random.
    A_N, b : float
        True per-sensel law ``f = A_N * X**b`` (newtons per sensel).
    masses_kg, pad_sides_cm : sequence
        Dead weights and square pad sides (Table 1 pad masses are added to the load).
    sensel_pitch_mm : float, optional
        Sensel pitch; default the 5051's from :mod:`tactilecal.sensors` (1.27 mm).
    gain_spread : float
        Standard deviation of a lognormal per-sensel gain on the force (0: none).
    threshold : int
        Readings below it are reported as 0.
    seed : int
        Seed of :func:`numpy.random.default_rng`.

    Returns
    -------
    histograms : numpy.ndarray of int64, shape (n_patches, 256)
    load_N : numpy.ndarray, shape (n_patches,)
    mass_kg : numpy.ndarray, shape (n_patches,)

    References
    ----------
    Zvyagin, A. (2022). Calibration of tactile pressure sensors for high-pressure zones
    (Table 1: pad masses; Figure 4: uneven contact under a pad).

    Examples
    --------
    >>> h, f, m = patch_histograms(3, seed=1)
    >>> h.shape, f.shape, bool((h.sum(axis=1) > 0).all())
    ((3, 256), (3,), True)
    """
    if sensel_pitch_mm is None:
        from tactilecal.sensors import get_sensor

        sensel_pitch_mm = get_sensor("5051").row_spacing_mm
    rng = np.random.default_rng(seed)
    hist = np.zeros((n_patches, 256), dtype=np.int64)
    mass = rng.choice(np.asarray(masses_kg, dtype=float), n_patches)
    side_cm = rng.choice(np.asarray(pad_sides_cm), n_patches)
    load = mass_to_N(mass, "kg") + mass_to_N(
        np.array([PAD_MASS_G.get(int(s), 0.0) for s in side_cm]), "g")
    for t in range(n_patches):
        side = max(int(round(side_cm[t] * 10 / sensel_pitch_mm)), 2)
        force = load[t] * _contact_field(side, rng)
        if gain_spread:
            force = force * rng.lognormal(0.0, gain_spread, force.shape)
        raw = np.clip(np.round((force / A_N) ** (1.0 / b)), 0, 255).astype(np.int64)
        raw[raw < threshold] = 0
        hist[t] = np.bincount(raw, minlength=256)
    return hist, load, mass
