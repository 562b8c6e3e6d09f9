"""The ``.tactile`` accessor of :class:`xarray.DataArray`, registered by ``import tactilecal``.

``import tactilecal`` does not import xarray (it would make that import many times slower:
``benchmarks/bench_import.py``), yet ``import tactilecal; import xarray`` must give
``DataArray.tactile`` whatever the order of the imports (isort puts ``tactilecal`` first).
So the registration waits for xarray: if xarray is loaded, it happens at once; else a finder
on :data:`sys.meta_path` (the import system's post-import hook, PEP 302/451) sees the first
``import xarray`` and registers right after xarray's module has run. What it registers is
the factory ``tactilecal/__init__.py`` gives, which imports :mod:`tactilecal.analysis` (and
its dependencies) only on the first use of ``.tactile``: registering costs nothing.
"""

import sys

__all__ = ["register_accessor", "ACCESSOR_NAME"]

ACCESSOR_NAME = "tactile"


def register_accessor(factory):
    """Register ``factory`` as ``DataArray.tactile`` now if xarray is loaded, else at its import.

    ``factory(recording)`` returns the accessor (xarray calls it once per DataArray and
    caches the result).
    """
    if "xarray" in sys.modules:
        _register(sys.modules["xarray"], factory)
    elif not any(isinstance(f, _XarrayImport) for f in sys.meta_path):
        sys.meta_path.insert(0, _XarrayImport(factory))


def _register(xarray, factory):
    """Register ``factory`` on ``xarray.DataArray`` (once)."""
    if getattr(xarray.DataArray, ACCESSOR_NAME, None) is not factory:
        xarray.register_dataarray_accessor(ACCESSOR_NAME)(factory)


class _XarrayImport:
    """A meta-path finder that only watches for ``import xarray`` and then steps aside."""

    def __init__(self, factory):
        self._factory = factory

    def find_spec(self, fullname, path=None, target=None):
        if fullname != "xarray":
            return None
        sys.meta_path.remove(self)
        from importlib.util import find_spec

        spec = find_spec(fullname)
        if spec is not None and spec.loader is not None:
            spec.loader = _RegisteringLoader(spec.loader, self._factory)
        return spec


class _RegisteringLoader:
    """xarray's own loader, which registers the accessor once the module has run."""

    def __init__(self, loader, factory):
        self._loader, self._factory = loader, factory

    def create_module(self, spec):
        return self._loader.create_module(spec)

    def exec_module(self, module):
        self._loader.exec_module(module)
        _register(module, self._factory)

    def __getattr__(self, name):  # resources, get_filename...: xarray's loader answers
        return getattr(self._loader, name)
