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

    assert G_STANDARD is _units.G_STANDARD
    assert LBF_N is _units.LBF_N
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


UNIT_SCALE = {1000, 1e-3, 1e6, 1e-6}
"""Decimal prefixes: a unit factor when they multiply or divide a quantity with a unit."""
UNIT_NAMES = ("kpa", "mpa", "psi", "mm2", "_n", "newton", "pressure", "force", "load", "area",
              "mass", "pad", "rho", "density", "_g")


def _literal_factors(path):
    """Yield ``(line, value, expression)`` of unit-factor literals anywhere in ``path``.

    Every numeric constant of the code (not of docstrings) equal to a constant of
    ``DEFINED_ONCE``, and every decimal prefix (1000, 1e-3...) that multiplies or divides an
    expression naming a quantity with a unit (``pressure_kPa * 1e3``, ``pad_g / 1000.0``).
    """
    source = path.read_text(encoding="utf-8")
    lines = source.splitlines()
    tree = ast.parse(source)
    for node in ast.walk(tree):
        if hasattr(node, "lineno") and "not a unit factor" in lines[node.lineno - 1]:
            continue
        if isinstance(node, ast.Constant) and isinstance(node.value, float) \
                and node.value in DEFINED_ONCE:
            yield node.lineno, node.value, DEFINED_ONCE[node.value]
        if isinstance(node, ast.BinOp) and isinstance(node.op, ast.Mult | ast.Div):
            for this, other in ((node.left, node.right), (node.right, node.left)):
                if isinstance(this, ast.Constant) and isinstance(this.value, int | float) \
                        and not isinstance(this.value, bool) and this.value in UNIT_SCALE:
                    text = ast.get_source_segment(source, other).lower()
                    if any(name in text for name in UNIT_NAMES):
                        yield node.lineno, this.value, ast.get_source_segment(source, node)


def test_no_unit_factor_is_written_as_a_literal():
    offenders = [f"{path.relative_to(SRC.parent)}:{line}: {value!r} in {text}"
                 for path in sorted(SRC.rglob("*.py"))
                 if not (path.name == "_units.py" and path.parent == SRC)
                 and path.name != "_catalogue.py"
                 for line, value, text in _literal_factors(path)]
    assert not offenders, "unit factors belong to tactilecal._units:\n" + "\n".join(offenders)


def test_the_literal_guard_finds_what_it_looks_for(tmp_path):
    bad = tmp_path / "bad.py"
    bad.write_text("def f(pressure_kPa, pad_g, x):\n"
                   "    a = pressure_kPa * 1e3\n    b = pad_g / 1000.0\n    c = 9.80665 * x\n"
                   "    d = x * 1000\n    return a, b, c, d\n")
    found = [(line, value) for line, value, _ in _literal_factors(bad)]
    assert found == [(2, 1e3), (3, 1000.0), (4, 9.80665)]  # x * 1000 has no unit: not flagged
