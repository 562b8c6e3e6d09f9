"""Unit helpers: spellings from real files, exact conversion factors, errors."""

import numpy as np
import pytest

from tactilecal._units import (
    G_STANDARD,
    area_to_mm2,
    force_to_N,
    length_to_mm,
    mass_to_N,
    normalise_unit,
    pressure_to_kPa,
    time_to_s,
    unit_kind,
)


@pytest.mark.parametrize("text, unit", [
    ("raw", "raw"), ("KPa", "kPa"), ("KPa ", "kPa"), ("MPa", "MPa"), ("PSI", "psi"),
    ("Pa", "Pa"), ("N", "N"), ("kN", "kN"), ("kgf", "kgf"), ("lbf", "lbf"), ("(Kgs)", "kg"),
    ("Lbs", "lb"), ("centimeters", "cm"), ("mm", "mm"), ("inches", "in"), ("cm2", "cm2"),
    ("mm^2", "mm2"), ("in²", "in2"), ("[ms]", "ms"), ("sec", "s"),
])
def test_spellings(text, unit):
    assert normalise_unit(text) == unit


def test_exact_factors():
    assert G_STANDARD == 9.80665
    assert length_to_mm(1.0, "in") == 25.4 and area_to_mm2(1.0, "in2") == 645.16
    assert force_to_N(1.0, "lbf") == pytest.approx(4.4482216152605, rel=1e-14)
    assert mass_to_N(np.array([1.0, 2.0]), "kg") == pytest.approx([9.80665, 19.6133])
    assert mass_to_N(1.0, "lb") == pytest.approx(force_to_N(1.0, "lbf"), rel=1e-15)
    assert pressure_to_kPa(1.0, "psi") == pytest.approx(6.894757293168, rel=1e-12)
    assert pressure_to_kPa(2.0, "MPa") == 2000.0 and pressure_to_kPa(500.0, "Pa") == 0.5
    assert force_to_N(1.0, "kgf") == G_STANDARD and time_to_s(250.0, "ms") == 0.25
    assert unit_kind("kPa") == "pressure"


def test_unknown_unit_names_where():
    with pytest.raises(ValueError, match=r"unknown unit 'furlong' in UNITS on line 3 of a.csv; "
                                         r"expected one of raw, kPa"):
        normalise_unit("furlong", where="UNITS on line 3 of a.csv")


def test_wrong_kind():
    with pytest.raises(ValueError, match=r"cannot convert 'kPa' \(pressure\) to N"):
        force_to_N(1.0, "kPa")
    with pytest.raises(ValueError, match=r"unit 'KPa' is not a canonical unit; pass it"):
        unit_kind("KPa")
