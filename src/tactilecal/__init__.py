"""tactilecal: calibrate and analyse matrix piezoresistive tactile pressure sensors.

The data model is one :class:`xarray.DataArray` per recording with dims
``("frame", "row", "col")``, a ``time`` coordinate in seconds along ``frame`` and the
sensor's description in ``attrs`` (see ``docs/data-model.md``).

Subpackages, one per idea:

``tactilecal.io``
    Tekscan ASCII exports, load-cell CSVs and NetCDF.
``tactilecal.sensors``
    Catalogue of sensor models (5051, 5101, 9500, ...).
``tactilecal.simulate``
    Synthetic recordings with their known truth.
``tactilecal.calibration``
    Static calibration: I-Scan methods, literature alternatives, Zvyagin (2022),
    validation.
``tactilecal.dynamic``
    Dynamic calibration (Gillis 2013): transfer function and inverse filter.
``tactilecal.analysis``
    Pressure-map analysis: force, area, centre of force, profiles, time effects.
``tactilecal.geotech``
    Earth pressure, centrifuge and hydrostatic helpers.
``tactilecal.report``
    Self-contained HTML reports.

The names below are imported lazily so that ``import tactilecal`` stays fast.
:func:`load` opens any saved result (calibration, equilibration, non-working sensels,
dynamic filter, validation) by the format tag in its JSON.

The xarray accessor ``recording.tactile`` (``.force()``, ``.area()``, ``.centre()``,
``.calibrate(cal)``...) is registered by ``import tactilecal``, before or after ``import
xarray``, without importing xarray or the analysis (:mod:`tactilecal._accessor`): the
analysis is imported on the first use of ``.tactile``.
"""

from importlib import import_module

from tactilecal._accessor import register_accessor
from tactilecal._errors import TactilecalError, TactilecalTypeError
from tactilecal._version import __version__

_LAZY = {
    "read_tekscan": "tactilecal.io",
    "write_tekscan": "tactilecal.io",
    "read_timeseries": "tactilecal.io",
    "write_timeseries": "tactilecal.io",
    "write_netcdf": "tactilecal.io",
    "read_netcdf": "tactilecal.io",
    "load_points": "tactilecal.calibration",
    "calibrate": "tactilecal.calibration",
    "validate": "tactilecal.calibration",
    "sensors": "tactilecal.sensors",
    "simulate": "tactilecal.simulate",
    "analysis": "tactilecal.analysis",
    "geotech": "tactilecal.geotech",
    "dynamic": "tactilecal.dynamic",
    "report": "tactilecal.report",
    "io": "tactilecal.io",
    "calibration": "tactilecal.calibration",
}

__all__ = ["__version__", "load", "TactilecalError", "TactilecalTypeError", *_LAZY]

#: The subpackage that defines each saved kind (importing it registers the kind).
_KIND_MODULES = {
    "calibration": "tactilecal.calibration",
    "equilibration": "tactilecal.calibration",
    "non-working-sensels": "tactilecal.calibration",
    "validation": "tactilecal.calibration",
    "dynamic-filter": "tactilecal.dynamic",
    "dynamic-evaluation": "tactilecal.dynamic",
    "creep": "tactilecal.analysis",
    "hysteresis": "tactilecal.analysis",
}


def load(path):
    """Open a saved result of any kind by the format tag in its JSON.

    The tag is ``"format": "tactilecal-<kind>/<version>"`` (:mod:`tactilecal._result`).
    Only the subpackage that defines the file's kind is imported (an equilibration does
    not import ``tactilecal.dynamic`` and numba); a file without a known tag imports them
    all, so that the message lists every kind.

    Parameters
    ----------
    path : str or os.PathLike
        A JSON file written by a result's ``to_json`` (or ``tactilecal`` commands' ``--out``).

    Returns
    -------
    tactilecal.calibration.CalibrationResult, Equilibration, NonWorkingSensels,
    ValidationResult, tactilecal.dynamic.CorrectionFilter or Evaluation,
    tactilecal.analysis.CreepResult or HysteresisResult

    Raises
    ------
    TactilecalError
        Not JSON, no tag or an unknown one, or a missing or bad key: one line naming the
        file and the key (:class:`TactilecalTypeError` for a key of the wrong type).

    Examples
    --------
    >>> import tempfile, pathlib, numpy as np
    >>> from tactilecal.calibration import equilibrate
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "eq.json"
    >>> equilibrate([np.full((1, 2, 2), 50.0)]).to_json(path)
    >>> load(path).gain.tolist()
    [[1.0, 1.0], [1.0, 1.0]]
    """
    from tactilecal._result import load_result

    return load_result(path, register=_import_kind)


def _import_kind(data):
    """Import the subpackage that defines the kind tagged in ``data``; every one if unknown."""
    tag = data.get("format")
    kind = tag[len("tactilecal-"):].partition("/")[0] if isinstance(tag, str) else None
    for module in ([_KIND_MODULES[kind]] if kind in _KIND_MODULES
                   else sorted(set(_KIND_MODULES.values()))):
        import_module(module)


def __getattr__(name):
    if name not in _LAZY:
        raise AttributeError(f"module 'tactilecal' has no attribute {name!r}")
    module = import_module(_LAZY[name])
    value = module if module.__name__ == f"tactilecal.{name}" else getattr(module, name)
    globals()[name] = value
    return value


def __dir__():
    return sorted(__all__)


def _tactile(recording):
    """Return ``recording.tactile``: the analysis is imported on its first use."""
    return import_module("tactilecal.analysis").TactileAccessor(recording)


register_accessor(_tactile)
