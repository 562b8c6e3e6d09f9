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

#: The subpackages that define the saved kinds (importing them registers the kinds).
_SAVED_KINDS_IN = ("tactilecal.calibration", "tactilecal.dynamic", "tactilecal.analysis")


def load(path):
    """Open a saved result of any kind by the format tag in its JSON.

    The tag is ``"format": "tactilecal-<kind>/<version>"`` (:mod:`tactilecal._result`);
    files of earlier versions without it (a calibration, ``"kind": "equilibration"``, the
    output of ``validate --json``) are recognised by their keys.

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
    for module in _SAVED_KINDS_IN:
        import_module(module)
    from tactilecal._result import load_result

    return load_result(path)


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
