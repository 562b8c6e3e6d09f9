"""Soil and water stresses in a centrifuge model: Jaky's K0, vertical and hydrostatic stress.

Model scale throughout: depths in metres of the model, ``g_level`` the centrifugal
acceleration in multiples of g (N). A unit weight measured at 1 g (kN/m3) becomes
``N * gamma`` in flight, so the vertical stress at model depth ``z`` is ``N gamma z``, the
same as at prototype depth ``N z`` under 1 g (Gillis 2013, section 5.4).
"""

import numpy as np

from tactilecal._errors import TactilecalError
from tactilecal._units import G_STANDARD, pressure_to_kPa

__all__ = ["k0_jaky", "void_ratio", "dry_unit_weight_kN_m3", "unit_weight_from_relative_density",
           "vertical_stress_kPa", "hydrostatic_pressure_kPa", "at_rest_pressure_kPa"]

WATER_UNIT_WEIGHT_KN_M3 = 1000.0 * G_STANDARD / 1000.0
"""Unit weight of water at 1 g: 1000 kg/m3 x 9.80665 m/s2 = 9.80665 kN/m3."""


def _finite(name, value, *, low=None, high=None, open_low=False):
    arr = np.asarray(value, dtype=float)
    bad = ~np.isfinite(arr)
    if low is not None:
        bad |= (arr <= low) if open_low else (arr < low)
    if high is not None:
        bad |= arr > high
    if bad.any():
        rng = (f"{'>' if open_low else '>='} {low}" if low is not None else "") + (
            f" and <= {high}" if high is not None else "")
        raise TactilecalError(f"{name} is {value!r}; expected finite values {rng}".rstrip())
    return arr


def k0_jaky(phi_deg):
    """At-rest earth-pressure coefficient of Jaky, ``K0 = 1 - sin(phi)``.

    Parameters
    ----------
    phi_deg : float or array_like
        Friction angle in degrees, 0 < phi < 90.

    Returns
    -------
    float or numpy.ndarray
        K0 (dimensionless).

    Raises
    ------
    ValueError
        If a friction angle is outside (0, 90) degrees.

    Notes
    -----
    Jaky (1944) simplified; used by Gillis (2013) section 5.7 for Nevada sand with
    phi = 33..38 degrees (K0 0.38..0.46, Figure 5.10).

    Examples
    --------
    >>> round(float(k0_jaky(33)), 3), round(float(k0_jaky(38)), 3)
    (0.455, 0.384)
    """
    phi = _finite("phi_deg", phi_deg, low=0, high=90, open_low=True)
    if np.any(phi >= 90):
        raise TactilecalError(f"phi_deg is {phi_deg!r}; expected friction angles in (0, 90) "
                              f"degrees")
    return 1.0 - np.sin(np.radians(phi))


def void_ratio(relative_density_pct, *, e_min, e_max):
    """Void ratio at a relative density, ``e = e_max - Dr (e_max - e_min)``.

    Parameters
    ----------
    relative_density_pct : float or array_like
        Relative density Dr in percent (0 = loosest, e_max; 100 = densest, e_min).
    e_min, e_max : float
        Minimum and maximum void ratios of the soil, ``0 < e_min < e_max``.

    Returns
    -------
    float or numpy.ndarray

    Raises
    ------
    ValueError
        If ``e_min >= e_max`` (e.g. the swapped columns of Gillis 2013, Table 5.2) or Dr is
        outside 0..100.

    Notes
    -----
    Definition of relative density, ``Dr = (e_max - e) / (e_max - e_min)``. Gillis (2013)
    Table 5.2 prints ``e_min = 0.59`` against Dr = 0 % and ``e_max = 0.85`` against
    Dr = 100 %: swapped, since the loosest state (Dr = 0) has the largest void ratio.
    With e_min = 0.59, e_max = 0.85 the formula gives the table's e = 0.69 at Dr = 60 %.

    Examples
    --------
    >>> round(float(void_ratio(60, e_min=0.59, e_max=0.85)), 3)
    0.694
    """
    dr = _finite("relative_density_pct", relative_density_pct, low=0, high=100)
    e_min = float(_finite("e_min", e_min, low=0, open_low=True))
    e_max = float(_finite("e_max", e_max, low=0, open_low=True))
    if e_min >= e_max:
        raise TactilecalError(f"e_min is {e_min} and e_max is {e_max}; expected e_min < e_max "
                              "(the loosest state, Dr = 0 %, has the larger void ratio e_max)")
    return e_max - dr / 100.0 * (e_max - e_min)


def dry_unit_weight_kN_m3(void_ratio, specific_gravity, *,
                          water_unit_weight_kN_m3=WATER_UNIT_WEIGHT_KN_M3):
    """Dry unit weight at 1 g, ``gamma_d = Gs gamma_w / (1 + e)`` [kN/m3].

    Parameters
    ----------
    void_ratio : float or array_like
        Void ratio e > 0.
    specific_gravity : float
        Specific gravity of the solids Gs.
    water_unit_weight_kN_m3 : float, default 9.80665
        Unit weight of water (1000 kg/m3 under standard gravity).

    Returns
    -------
    float or numpy.ndarray

    Examples
    --------
    >>> round(float(dry_unit_weight_kN_m3(0.694, 2.65)), 2)
    15.34
    """
    e = _finite("void_ratio", void_ratio, low=0, open_low=True)
    gs = _finite("specific_gravity", specific_gravity, low=0, open_low=True)
    return gs * water_unit_weight_kN_m3 / (1.0 + e)


def unit_weight_from_relative_density(relative_density_pct, *, e_min, e_max, specific_gravity):
    """Dry unit weight at 1 g of a sand placed at a relative density [kN/m3].

    Combines :func:`void_ratio` and :func:`dry_unit_weight_kN_m3`.

    Examples
    --------
    >>> g = unit_weight_from_relative_density(60, e_min=0.59, e_max=0.85, specific_gravity=2.65)
    >>> round(float(g), 2)
    15.34
    """
    e = void_ratio(relative_density_pct, e_min=e_min, e_max=e_max)
    return dry_unit_weight_kN_m3(e, specific_gravity)


def vertical_stress_kPa(depth_m, g_level, *, unit_weight_kN_m3=None, relative_density_pct=None,
                        e_min=None, e_max=None, specific_gravity=None, surcharge_kPa=0.0):
    """Vertical stress under a dry soil layer in a centrifuge, ``sigma_v = N gamma z + q``.

    Parameters
    ----------
    depth_m : float or array_like
        Model depth below the soil surface [m].
    g_level : float or array_like
        Centrifugal acceleration N (multiples of g) at the layer's mid depth.
    unit_weight_kN_m3 : float, optional
        Unit weight at 1 g. Or give the next four instead.
    relative_density_pct, e_min, e_max, specific_gravity : float, optional
        To compute the dry unit weight (:func:`unit_weight_from_relative_density`).
    surcharge_kPa : float, default 0
        Stress on the soil surface.

    Returns
    -------
    float or numpy.ndarray
        Vertical stress [kPa] (kN/m2).

    Raises
    ------
    ValueError
        If neither or both ways of giving the unit weight are used, or an input is
        negative or not finite.

    Notes
    -----
    The acceleration grows linearly with radius, so with N taken at mid depth the mean
    over the layer is N and ``sigma_v = N gamma H`` holds exactly at the base. Gillis
    (2013) Table 5.3: 25 cm of Nevada sand at 15.36 kN/m3 -> 3.84 kPa per g.

    Examples
    --------
    >>> round(float(vertical_stress_kPa(0.25, 1.0, unit_weight_kN_m3=15.36)), 2)
    3.84
    >>> round(float(vertical_stress_kPa(0.25, 47.6, unit_weight_kN_m3=15.36)), 1)
    182.8
    """
    by_density = [relative_density_pct, e_min, e_max, specific_gravity]
    if (unit_weight_kN_m3 is None) == all(v is None for v in by_density):
        raise TactilecalError("give unit_weight_kN_m3, or relative_density_pct with e_min, e_max "
                              "and specific_gravity (exactly one of the two)")
    if unit_weight_kN_m3 is None:
        if any(v is None for v in by_density):
            raise TactilecalError("relative_density_pct, e_min, e_max and specific_gravity are all "
                                  f"needed; got {by_density}")
        unit_weight_kN_m3 = unit_weight_from_relative_density(
            relative_density_pct, e_min=e_min, e_max=e_max, specific_gravity=specific_gravity)
    gamma = _finite("unit_weight_kN_m3", unit_weight_kN_m3, low=0, open_low=True)
    z = _finite("depth_m", depth_m, low=0)
    n = _finite("g_level", g_level, low=0, open_low=True)
    q = _finite("surcharge_kPa", surcharge_kPa, low=0)
    return n * gamma * z + q


def hydrostatic_pressure_kPa(depth_m, g_level, *, density_kg_m3=1000.0):
    """Water pressure at a model depth in a centrifuge, ``u = rho N g z`` [kPa].

    Parameters
    ----------
    depth_m : float or array_like
        Model depth below the water surface [m].
    g_level : float or array_like
        Centrifugal acceleration N (multiples of g).
    density_kg_m3 : float, default 1000
        Fluid density.

    Returns
    -------
    float or numpy.ndarray

    Notes
    -----
    Gillis (2013) section 4.4.2 calibrates from 7.0 cm of water at the test's g-level.

    Examples
    --------
    >>> round(float(hydrostatic_pressure_kPa(0.07, 77)), 2)
    52.86
    """
    z = _finite("depth_m", depth_m, low=0)
    n = _finite("g_level", g_level, low=0, open_low=True)
    rho = _finite("density_kg_m3", density_kg_m3, low=0, open_low=True)
    return pressure_to_kPa(rho * n * G_STANDARD * z, "Pa")


def at_rest_pressure_kPa(depth_m, g_level, phi_deg, **unit_weight):
    """At-rest lateral earth pressure ``K0(phi) sigma_v`` [kPa] (Gillis 2013, section 5.7).

    ``unit_weight`` takes the keywords of :func:`vertical_stress_kPa`.

    Examples
    --------
    >>> round(float(at_rest_pressure_kPa(0.25, 1.0, 33, unit_weight_kN_m3=15.36)), 3)
    1.749
    """
    return k0_jaky(phi_deg) * vertical_stress_kPa(depth_m, g_level, **unit_weight)
