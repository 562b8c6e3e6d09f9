"""The public API: one ``__all__`` per subpackage, documented in docs/api.md, no clashes.

Nothing is released, so nothing is deprecated: a name that leaves the API is gone, and no
module serves names through a module ``__getattr__``.
"""

import inspect
import re
from importlib import import_module
from pathlib import Path

import pytest

SUBPACKAGES = ("io", "sensors", "simulate", "calibration", "dynamic", "analysis", "geotech",
               "report", "demo")
API_PAGE = Path(__file__).resolve().parents[1] / "docs" / "api.md"


def _modules():
    return {sub: import_module(f"tactilecal.{sub}") for sub in SUBPACKAGES}


def test_every_public_name_exists_and_every_callable_is_documented():
    for sub, module in _modules().items():
        assert len(module.__all__) == len(set(module.__all__)), f"{sub}: __all__ repeats"
        for name in module.__all__:
            obj = getattr(module, name)
            if callable(obj):
                assert inspect.getdoc(obj), f"tactilecal.{sub}.{name} has no docstring"


def test_no_name_is_public_in_two_subpackages():
    owners = {}
    for sub, module in _modules().items():
        for name in module.__all__:
            owners.setdefault(name, []).append(sub)
    clashes = {name: subs for name, subs in owners.items() if len(subs) > 1}
    assert not clashes, f"public in more than one subpackage: {clashes}"


def test_the_api_page_lists_exactly_the_public_names():
    page = API_PAGE.read_text(encoding="utf-8")
    listed, sub = {}, None
    for line in page.splitlines():
        if line.startswith("## "):
            heading = re.match(r"## `(?:tactilecal\.(\w+)|(recording\.tactile))`", line)
            sub = heading and (heading.group(1) or heading.group(2))
        entry = re.match(r"- `(\w+)`", line)
        if entry and sub:
            listed.setdefault(sub, []).append(entry.group(1))
    public = {sub: sorted(module.__all__) for sub, module in _modules().items()}
    accessor = vars(import_module("tactilecal.analysis").TactileAccessor)
    public["recording.tactile"] = sorted(name for name, value in accessor.items()
                                         if not name.startswith("_") and callable(value))
    assert {sub: sorted(names) for sub, names in listed.items()} == public


def test_the_public_surface_stays_small():
    # issue 14: 182 public names before, "roughly halved" asked; 0.2 has 90 (figures are
    # methods of what they draw, the analysis of a recording is methods of rec.tactile).
    # Do not raise.
    assert sum(len(m.__all__) for m in _modules().values()) <= 90


def test_no_module_serves_names_it_does_not_define():
    """No module ``__getattr__`` (PEP 562) anywhere but the lazy top level."""
    root = Path(import_module("tactilecal").__file__).parent
    serving = [str(path.relative_to(root)) for path in root.rglob("*.py")
               if re.search(r"^def __getattr__\(|^__getattr__ = ", path.read_text(), re.M)]
    assert serving == ["__init__.py"]


def test_nothing_is_deprecated():
    root = Path(import_module("tactilecal").__file__).parent
    hits = [f"{path.relative_to(root)}:{k}" for path in root.rglob("*.py")
            for k, line in enumerate(path.read_text().splitlines(), 1)
            if re.search(r"DeprecationWarning|[Dd]eprecat", line)]
    assert hits == []


def test_an_unknown_name_is_still_an_attribute_error():
    from tactilecal import calibration

    with pytest.raises(AttributeError, match="'tactilecal.calibration' has no attribute 'nope'"):
        calibration.nope  # noqa: B018
    with pytest.raises(ImportError, match="cannot import name 'nope'"):
        exec("from tactilecal.calibration import nope", {})
