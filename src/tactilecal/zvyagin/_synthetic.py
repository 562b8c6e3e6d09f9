"""Small synthetic dead-weight patches with a known power law, for tests and benchmarks.

This is a deliberately simple stand-in (no sensor geometry, no drift): each patch is a square
pad with an uneven contact field (a few Gaussian bumps, peak 5-10x the periphery, like the
paper's Figure 4); the load on each sensel is turned into a raw reading with f = A * X**b,
an optional per-sensel gain spread, rounding, the noise threshold (readings < 3 -> 0) and
saturation at 255.
"""

import numpy as np

__all__ = ["synthetic_patches"]

G_STANDARD = 9.80665
#: Table 1 of the paper: pad side (cm) -> pad mass (g)
PAD_MASS_G = {1: 0.6, 2: 2.6, 3: 5.9, 4: 10.6, 5: 16.1}


def _contact_field(side, rng):
    """Uneven positive weights on a side x side pad, peak 5-10x the periphery."""
    yy, xx = np.mgrid[0:side, 0:side] / max(side - 1, 1)
    field = np.full((side, side), 1.0)
    for _ in range(rng.integers(1, 4)):
        cy, cx = rng.uniform(0.2, 0.8, 2)
        width = rng.uniform(0.12, 0.35)
        field += rng.uniform(2.0, 5.0) * np.exp(-((yy - cy) ** 2 + (xx - cx) ** 2)
                                                / (2 * width ** 2))
    field *= rng.uniform(0.7, 1.3, field.shape)
    return field.ravel() / field.sum()


def synthetic_patches(n_patches=60, *, A_N=0.0035, b=1.16, masses_kg=(2, 5, 10),
                      pad_sides_cm=(2, 3, 4), sensel_pitch_mm=1.27, gain_spread=0.0,
                      threshold=3, seed=0):
    """Simulate dead-weight calibration patches following f = A_N * X**b per sensel.

    Parameters
    ----------
    n_patches : int
        Number of patches; masses and pads are drawn at random.
    A_N, b : float
        True per-sensel law (newtons per sensel).
    masses_kg, pad_sides_cm : sequence
        Dead weights and square pad sides (Table 1 pad masses are added to the load).
    sensel_pitch_mm : float
        Sensel pitch (5051: 1.27 mm).
    gain_spread : float
        Standard deviation of a lognormal per-sensel gain on the force (0: none).
    threshold : int
        Readings below it are reported as 0.
    seed : int
        Random seed.

    Returns
    -------
    histograms : numpy.ndarray of int64, shape (n_patches, 256)
    load_N : numpy.ndarray, shape (n_patches,)
    mass_kg : numpy.ndarray, shape (n_patches,)

    Examples
    --------
    >>> h, f, m = synthetic_patches(3, seed=1)
    >>> h.shape, f.shape
    ((3, 256), (3,))
    """
    rng = np.random.default_rng(seed)
    hist = np.zeros((n_patches, 256), dtype=np.int64)
    mass = rng.choice(np.asarray(masses_kg, dtype=float), n_patches)
    side_cm = rng.choice(np.asarray(pad_sides_cm), n_patches)
    load = (mass + np.array([PAD_MASS_G.get(int(s), 0.0) for s in side_cm]) / 1000) * G_STANDARD
    for t in range(n_patches):
        side = max(int(round(side_cm[t] * 10 / sensel_pitch_mm)), 2)
        force = load[t] * _contact_field(side, rng)
        if gain_spread:
            force = force * rng.lognormal(0.0, gain_spread, force.shape)
        raw = np.clip(np.round((force / A_N) ** (1.0 / b)), 0, 255).astype(np.int64)
        raw[raw < threshold] = 0
        hist[t] = np.bincount(raw, minlength=256)
    return hist, load, mass
