"""Unit factors and sensor constants come from one place (tactilecal._units, the catalogue)."""

import ast
from pathlib import Path

import pytest

import tactilecal
from tactilecal import _units

SRC = Path(tactilecal.__file__).parent

# each value with the module-level names it once had in several modules
DEFINED_ONCE = {9.80665: "G_STANDARD", 0.45359237: "LB_KG", 4.4482216152605: "LBF_N",
                6.894757293168361: "PSI_TO_KPA", 1.6129: "the 5051 sensel area"}


def test_factors_against_their_definitions():
    # NIST SP 811 appendix B: 1 lbf = 4.4482216152605 N, 1 psi = 6.894757293168361 kPa
    assert _units.G_STANDARD == 9.80665
    assert _units.LBF_N == pytest.approx(4.4482216152605, rel=1e-15)
    assert _units.PSI_TO_KPA == pytest.approx(6.894757293168361, rel=1e-15)
    # 1 kPa x 1 mm2 = 1e3 Pa x 1e-6 m2 = 1e-3 N; 1 N/mm2 = 1 MPa = 1e3 kPa
    assert _units.KPA_MM2_TO_N == pytest.approx(1e3 * 1e-6, rel=1e-15)
    assert _units.KPA_MM2_TO_N * _units.N_PER_MM2_TO_KPA == pytest.approx(1.0, rel=1e-15)


def test_public_names_are_the_core_values():
    from tactilecal._units import G_STANDARD
    from tactilecal.sensors import get_sensor
    from tactilecal.simulate._dynamic import LBF_N
    from tactilecal.zvyagin._calibrate import SENSEL_AREA_5051_MM2

    assert G_STANDARD is _units.G_STANDARD
    assert LBF_N is _units.LBF_N
    assert SENSEL_AREA_5051_MM2 == get_sensor("5051").sensel_area_mm2
    assert get_sensor("5051-350").capacity_kPa == pytest.approx(350 * _units.PSI_TO_KPA)


def _module_constants(path):
    """(line, value) of module-level assignments of numbers (a tuple, a product of two)."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    for node in tree.body:
        if isinstance(node, ast.Assign | ast.AnnAssign) and node.value is not None:
            try:
                value = ast.literal_eval(node.value)
            except ValueError:
                if not (isinstance(node.value, ast.BinOp) and isinstance(node.value.op, ast.Mult)):
                    continue
                try:
                    value = (ast.literal_eval(node.value.left)
                             * ast.literal_eval(node.value.right))
                except ValueError:
                    continue
            for item in value if isinstance(value, tuple) else [value]:
                if isinstance(item, float):
                    yield node.lineno, item


def test_no_module_redefines_a_core_constant():
    offenders = [f"{path.relative_to(SRC.parent)}:{line}: {DEFINED_ONCE[value]} = {value!r}"
                 for path in sorted(SRC.rglob("*.py")) if path.name != "_units.py"
                 or path.parent != SRC
                 for line, value in _module_constants(path) if value in DEFINED_ONCE]
    assert not offenders, "defined again (import it from tactilecal._units or the " \
        "sensor catalogue):\n" + "\n".join(offenders)
