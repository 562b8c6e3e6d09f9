"""The public API: one ``__all__`` per subpackage, each in the reference pages, no clashes.

Nothing is released, so nothing is deprecated: a name that leaves the API is gone, and no
module serves names through a module ``__getattr__``.
"""

import importlib.util
import inspect
import re
from importlib import import_module
from pathlib import Path

import pytest

SUBPACKAGES = ("io", "sensors", "simulate", "calibration", "dynamic", "analysis", "geotech",
               "report", "demo")
DOCS = Path(__file__).resolve().parents[1] / "docs"


def _modules():
    return {sub: import_module(f"tactilecal.{sub}") for sub in SUBPACKAGES}


def test_every_public_name_exists_and_every_callable_is_documented():
    for sub, module in _modules().items():
        assert len(module.__all__) == len(set(module.__all__)), f"{sub}: __all__ repeats"
        for name in module.__all__:
            obj = getattr(module, name)
            if callable(obj):
                assert inspect.getdoc(obj), f"tactilecal.{sub}.{name} has no docstring"


def test_every_public_callable_and_tactile_method_has_examples():
    """A numpydoc Examples section (run by --doctest-modules) in every public docstring."""
    heading = "\nExamples\n--------\n"
    documented = {f"tactilecal.{sub}.{name}": getattr(module, name)
                  for sub, module in _modules().items() for name in module.__all__
                  if callable(getattr(module, name))}
    accessor = vars(import_module("tactilecal.analysis").TactileAccessor)
    documented |= {f"recording.tactile.{name}": value for name, value in accessor.items()
                   if not name.startswith("_") and callable(value)}
    missing = sorted(name for name, obj in documented.items()
                     if heading not in (inspect.getdoc(obj) or ""))
    assert not missing, f"{len(missing)} public callables have no Examples section: {missing}"


def test_no_name_is_public_in_two_subpackages():
    owners = {}
    for sub, module in _modules().items():
        for name in module.__all__:
            owners.setdefault(name, []).append(sub)
    clashes = {name: subs for name, subs in owners.items() if len(subs) > 1}
    assert not clashes, f"public in more than one subpackage: {clashes}"


def _api_pages():
    """``docs/_api.py``, which writes the reference pages from ``__all__`` (loaded by path)."""
    spec = importlib.util.spec_from_file_location("tactilecal_docs_api", DOCS / "_api.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_the_reference_pages_list_exactly_the_public_names(tmp_path):
    api = _api_pages()
    assert api.SUBPACKAGES == SUBPACKAGES
    listed = api.write_pages(tmp_path)
    public = {f"tactilecal.{sub}": sorted(module.__all__) for sub, module in _modules().items()}
    accessor = vars(import_module("tactilecal.analysis").TactileAccessor)
    public["recording.tactile"] = sorted(name for name, value in accessor.items()
                                         if not name.startswith("_") and callable(value))
    assert {page: sorted(names) for page, names in listed.items()} == public
    for page, names in listed.items():  # each name is in its page's autosummary
        text = (tmp_path / f"{page}.rst").read_text()
        entries = re.findall(r"^   (?:TactileAccessor\.)?(\w+)$", text, re.M)
        assert sorted(entries) == sorted(names), page
    toctree = re.findall(r"^api/(\S+)$", (DOCS / "api.md").read_text(), re.M)
    assert sorted(toctree) == sorted(listed)


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
