"""Earth-pressure profile against the at-rest band (Gillis 2013, Figure 5.10)."""

import numpy as np

from tactilecal._errors import TactilecalError
from tactilecal.geotech._soil import k0_jaky, vertical_stress_kPa

__all__ = ["plot_earth_pressure_profile"]


def plot_earth_pressure_profile(profile_kPa, depth_m, *, g_level, phi_deg=(33.0, 38.0),
                                scale="prototype", label="sensor rows", ax=None,
                                **unit_weight):
    """Plot a row profile against the band of at-rest pressures for a range of phi.

    Parameters
    ----------
    profile_kPa : array_like
        Mean pressure of each sensel row [kPa], 1-D (e.g. one frame of
        ``recording.tactile.profile("row")``, or its mean over frames).
    depth_m : array_like
        Model depth of each row below the soil surface [m], same length.
    g_level : float
        Centrifugal acceleration N at which the profile was recorded.
    phi_deg : tuple of 2 float, default (33, 38)
        Range of friction angles; the band runs from ``K0(phi_max) sigma_v`` to
        ``K0(phi_min) sigma_v`` with ``K0 = 1 - sin(phi)`` (Jaky).
    scale : {"prototype", "model"}, default "prototype"
        Depth axis in prototype metres (``N z``, as in Gillis' Figure 5.10) or model metres.
        Pressures are the same at both scales.
    label : str
        Legend label of the measured profile.
    ax : matplotlib.axes.Axes, optional
        Axes to draw on; a new figure otherwise.
    **unit_weight
        Keywords of :func:`tactilecal.geotech.vertical_stress_kPa` (``unit_weight_kN_m3``,
        or ``relative_density_pct``, ``e_min``, ``e_max``, ``specific_gravity``).

    Returns
    -------
    matplotlib.figure.Figure

    Raises
    ------
    ValueError
        If the profile and depths differ in shape, ``phi_deg`` is not two angles or
        ``scale`` is unknown.

    Notes
    -----
    Gillis (2013) section 5.7: rows averaged without non-working sensels, compared with
    ``sigma_h = K0 sigma_v`` for phi = 33..38 degrees (K0 0.38..0.46).

    Examples
    --------
    >>> import numpy as np
    >>> fig = plot_earth_pressure_profile(np.array([20.0, 40.0, 60.0]),
    ...                                   np.array([1.0, 2.0, 3.0]), g_level=50,
    ...                                   unit_weight_kN_m3=16.0)
    >>> fig.axes[0].get_xlabel()
    'lateral pressure [kPa]'
    """
    from matplotlib.figure import Figure

    p = np.asarray(profile_kPa, dtype=float)
    z = np.asarray(depth_m, dtype=float)
    if p.ndim != 1 or p.shape != z.shape:
        raise TactilecalError(f"profile_kPa has shape {p.shape} and depth_m {z.shape}; expected "
                              "two 1-D arrays of the same length (one value per row)")
    phi = np.asarray(phi_deg, dtype=float)
    if phi.shape != (2,):
        raise TactilecalError(f"phi_deg is {phi_deg!r}; expected two friction angles (min, max)")
    if scale not in ("prototype", "model"):
        raise TactilecalError(f"scale is {scale!r}; expected 'prototype' or 'model'")
    factor = g_level if scale == "prototype" else 1.0
    z_line = np.linspace(0.0, np.nanmax(z) * 1.05, 100)
    sigma_v = vertical_stress_kPa(z_line, g_level, **unit_weight)
    k0 = k0_jaky(np.sort(phi))
    if ax is None:
        fig = Figure(figsize=(5, 6), layout="constrained")
        ax = fig.subplots()
    else:
        fig = ax.figure
    ax.fill_betweenx(z_line * factor, k0[1] * sigma_v, k0[0] * sigma_v, color="0.8",
                     label=(f"at rest, K0 = 1 - sin(phi), phi {phi.min():g}-{phi.max():g} deg "
                            f"(K0 {k0[1]:.2f}-{k0[0]:.2f})"))
    ax.plot(p, z * factor, "o-", label=label)
    ax.set_ylim(z_line[-1] * factor, 0.0)
    ax.set_xlim(left=0.0)
    ax.set_xlabel("lateral pressure [kPa]")
    ax.set_ylabel(f"depth, {scale} scale [m]" + (f" (N = {g_level:g})" if factor != 1 else ""))
    ax.legend(loc="upper right", fontsize="small")
    ax.grid(True, alpha=0.3)
    return fig
