"""Names that left the public API: still importable for one release, with a warning.

A subpackage lists them as ``{public_name: (private_module, attribute, advice)}`` and sets
``__getattr__ = moved_names(__name__, MOVED)``; Python calls that ``__getattr__`` only for
names the module does not define (PEP 562), so the deprecated names stay out of ``dir()``
and ``__all__`` while ``from tactilecal.calibration import force_table`` keeps working.
"""

import warnings
from importlib import import_module

#: The release in which the deprecated names will be removed.
REMOVED_IN = "0.3"


def moved_names(package, moved):
    """Return a module ``__getattr__`` serving ``moved`` names with a DeprecationWarning.

    Parameters
    ----------
    package : str
        The subpackage's ``__name__`` (e.g. ``"tactilecal.calibration"``).
    moved : dict
        ``{name: (module, attribute, advice)}``; ``module`` is relative to ``package``
        (e.g. ``"_models"``) or, for the core, absolute (``"tactilecal._units"``);
        ``advice`` says what to use instead.
    """
    def __getattr__(name):
        if name not in moved:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        module, attribute, advice = moved[name]
        warnings.warn(f"{package}.{name} is no longer part of the public API and will be "
                      f"removed in tactilecal {REMOVED_IN}; {advice}", DeprecationWarning,
                      stacklevel=2)
        absolute = module.startswith("tactilecal.")
        return getattr(import_module(module if absolute else f"{package}.{module}"), attribute)

    __getattr__.moved = moved
    return __getattr__
