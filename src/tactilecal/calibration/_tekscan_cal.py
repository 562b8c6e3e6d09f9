"""Tekscan calibration files (``.cal``, I-Scan/F-Scan) as calibration points.

A ``.cal`` file is text: header lines like an ASCII export's (``SENSOR_TYPE``, ``ROWS``,
``COLS``, ``SENSEL_AREA``, ``UNITS``, ``NOISE_THRESHOLD``...), then for each calibration
point ``n``: ``CAL_FPI_n`` (the applied load or pressure, in ``UNITS``), ``CAL_FPC_n``,
``CAL_RSI_n`` (the raw sum), ``CAL_RSC_n``, ``CAL_SM_n`` (the loaded sensels) and
``CAL_HST_n`` (256 counts: how many sensels read each raw value 0..255), and flags:
``CAL_EXP_ENABLED`` (the power-law mode), ``EQUFLAG``, ``CAL_TEMPERATURE_*``. The histogram
is the frame a point needs (:class:`CalibrationPoint`): its raw sum and loaded sensels must be
the file's ``CAL_RSI_n`` and ``CAL_SM_n`` exactly, or the file is refused.

A pressure in ``UNITS`` is applied over the point's loaded sensels (I-Scan's contact area):
``load_N = p x CAL_SM_n x sensel area``. ``CAL_FPC_n`` and ``CAL_RSC_n`` are kept in the
point's note; no documented meaning of theirs is used.
"""

import re
from pathlib import Path

import numpy as np

from tactilecal._errors import TactilecalError
from tactilecal._provenance import sensor_of
from tactilecal._units import (
    KPA_MM2_TO_N,
    area_to_mm2,
    force_to_N,
    mass_to_N,
    normalise_unit,
    pressure_to_kPa,
    unit_kind,
)
from tactilecal._validate import parse_number, read_text
from tactilecal.calibration._points import N_LEVELS, CalibrationPoint

__all__ = ["is_tekscan_cal", "read_tekscan_cal", "cal_points", "refuse_recording",
           "CAL_SUFFIX"]

CAL_SUFFIX = ".cal"
_POINT_KEY = re.compile(r"^CAL_(FPI|FPC|RSI|RSC|SM|HST)_(\d+)$")


def is_tekscan_cal(path):
    """Return True for a path ending in ``.cal`` (any case)."""
    return Path(str(path)).suffix.lower() == CAL_SUFFIX


def _lines(path):
    """Yield ``(line number, KEY, value text)`` of every non-blank line."""
    for number, line in enumerate(read_text(path, expected="a Tekscan .cal file")
                                  .splitlines(), 1):
        if line.strip():
            key, _, value = line.strip().partition(" ")
            yield number, key.strip().upper(), value.strip()


def _header(path):
    """Return the header keys and each calibration point's keys, with their lines."""
    header, points = {}, {}
    for number, key, value in _lines(path):
        match = _POINT_KEY.match(key)
        where = f"line {number} of {Path(path).name}"
        if match:
            points.setdefault(int(match.group(2)), {})[match.group(1)] = (value, where)
        else:
            header[key] = (value, where)
    return header, points


def _area_mm2(header, name):
    if "SENSEL_AREA" not in header:
        raise TactilecalError(f"{name} has no SENSEL_AREA line; expected the sensel area "
                              "(e.g. 'SENSEL_AREA 0.016129 cm2') to turn loads into "
                              "calibration points")
    text, where = header["SENSEL_AREA"]
    parts = text.split()
    value = parse_number(parts[0] if parts else "", f"SENSEL_AREA on {where}", minimum=0,
                         min_inclusive=False)
    unit = normalise_unit(" ".join(parts[1:]) or "mm2", where=f"SENSEL_AREA on {where}")
    if unit_kind(unit) != "area":
        raise TactilecalError(f"SENSEL_AREA on {where} is in {unit!r}, a {unit_kind(unit)} "
                              "unit; expected an area (e.g. 'SENSEL_AREA 0.016129 cm2')")
    try:
        return float(area_to_mm2(value, unit))
    except TactilecalError as exc:
        raise TactilecalError(f"SENSEL_AREA on {where}: {exc}") from None


def _load_unit(header, name):
    if "UNITS" not in header:
        raise TactilecalError(f"{name} has no UNITS line; expected the unit of CAL_FPI (a "
                              "pressure such as PSI or kPa, or a force or mass)")
    text, where = header["UNITS"]
    unit = normalise_unit(text, where=f"UNITS on {where}")
    if unit_kind(unit) not in ("pressure", "force", "mass"):
        raise TactilecalError(f"UNITS on {where} is {text!r}, a {unit_kind(unit)}; expected a "
                              "pressure, force or mass unit for CAL_FPI")
    return unit


def _histogram(keys, n, name):
    if "HST" not in keys:
        raise TactilecalError(f"{name}: calibration point {n} has no CAL_HST_{n} line; "
                              "expected 256 counts, one per raw value 0..255")
    text, where = keys["HST"]
    cells = [c for c in re.split(r"[,;\s]+", text) if c]
    if len(cells) != N_LEVELS:
        raise TactilecalError(f"CAL_HST_{n} on {where} has {len(cells)} counts; expected "
                              f"{N_LEVELS}, one per raw value 0..255")
    return np.array([parse_number(c, f"CAL_HST_{n} on {where}, raw value {v}", minimum=0,
                                  integer=True) for v, c in enumerate(cells)], dtype=np.int64)


def _point(n, keys, unit, area, name, sensor, path):
    missing = [k for k in ("FPI", "RSI", "SM") if k not in keys]
    if missing:
        raise TactilecalError(f"{name}: calibration point {n} lacks "
                              f"{', '.join(f'CAL_{k}_{n}' for k in missing)}; expected "
                              "CAL_FPI (load), CAL_RSI (raw sum) and CAL_SM (loaded sensels)")
    hist = _histogram(keys, n, name)
    value = parse_number(keys["FPI"][0], f"CAL_FPI_{n} on {keys['FPI'][1]}", minimum=0,
                         min_inclusive=False)
    raw_sum = parse_number(keys["RSI"][0], f"CAL_RSI_{n} on {keys['RSI'][1]}", minimum=0,
                           integer=True)
    loaded = parse_number(keys["SM"][0], f"CAL_SM_{n} on {keys['SM'][1]}", minimum=0,
                          integer=True)
    counted = (int(hist[1:].sum()), int(hist @ np.arange(N_LEVELS)))
    if counted != (loaded, raw_sum):
        raise TactilecalError(f"{name}: CAL_HST_{n} counts {counted[0]} loaded sensels with a "
                              f"raw sum of {counted[1]}; expected CAL_SM_{n} = {loaded} and "
                              f"CAL_RSI_{n} = {raw_sum}")
    if unit_kind(unit) == "pressure":
        load_N = pressure_to_kPa(value, unit) * loaded * area * KPA_MM2_TO_N
        how = f"{value:g} {unit} over its {loaded} loaded sensels"
    else:
        load_N = force_to_N(value, unit) if unit_kind(unit) == "force" else \
            mass_to_N(value, unit)
        how = f"{value:g} {unit}"
    extra = ", ".join(f"CAL_{k}_{n} {keys[k][0]}" for k in ("FPC", "RSC") if k in keys)
    return CalibrationPoint(
        histogram=hist, load_N=float(load_N), raw_sum=float(raw_sum), loaded_cells=loaded,
        saturated_cells=int(hist[-1]), source=name, frame=n, label=f"CAL point {n}",
        # the sensor's working sensels are not in the file: the histogram's are all there is
        sensel_area_mm2=area, working_cells=int(hist.sum()), total_cells=int(hist.sum()),
        note=f"from {name}: load {how}" + (f"; {extra}" if extra else ""),
        sensor=sensor, manifest=str(path))


def read_tekscan_cal(path):
    """Read a Tekscan ``.cal`` file: its calibration points and its header.

    Parameters
    ----------
    path : str or os.PathLike
        The ``.cal`` file.

    Returns
    -------
    points : list of CalibrationPoint
        One per ``CAL_*_n`` group, in the order of ``n``; ``frame`` is ``n``.
    header : dict
        Every other key (upper case) and its text, e.g. ``CAL_EXP_ENABLED``, ``EQUFLAG``.

    Raises
    ------
    TactilecalError
        A missing ``SENSEL_AREA``/``UNITS``, a point without load, raw sum, loaded sensels or
        histogram, a histogram of other than 256 counts or whose loaded sensels and raw sum
        differ from ``CAL_SM_n``/``CAL_RSI_n``; messages name the file and line.
    FileNotFoundError
        No such file.
    """
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"{path}: no such file; expected a Tekscan .cal file")
    header, groups = _header(path)
    if not groups:
        raise TactilecalError(f"{path.name} has no CAL_FPI_n, CAL_RSI_n, CAL_SM_n, CAL_HST_n "
                              "lines; expected a Tekscan calibration file with at least one "
                              "calibration point")
    unit, area = _load_unit(header, path.name), _area_mm2(header, path.name)
    sensor = sensor_of({"sensor_type": header.get("SENSOR_TYPE", (None,))[0]})
    points = [_point(n, groups[n], unit, area, path.name, sensor, path) for n in sorted(groups)]
    return points, {key: value for key, (value, _) in header.items()}


def cal_points(path, *, mask=None, equilibration=None):
    """:func:`read_tekscan_cal`'s points, for ``load_points``: a .cal holds no frames.

    Raises
    ------
    TactilecalError
        With a ``mask`` or an ``equilibration``: they act on frames, which a .cal file does
        not keep (only each point's histogram).
    """
    if mask is not None or equilibration is not None:
        what = "non-working sensels (mask)" if mask is not None else "an equilibration"
        raise TactilecalError(f"{Path(path).name} is a Tekscan .cal file: it keeps each "
                              f"point's histogram, not its frame, so {what} cannot be applied; "
                              "expected no mask and no equilibration (the .cal was made with "
                              "the equilibration Tekscan's software applied, see its EQUFLAG)")
    return read_tekscan_cal(path)[0]


def refuse_recording(path):
    """Raise when a manifest's path is a recording (a Tekscan export, NetCDF, Zarr)."""
    from tactilecal.io import recording_format

    found = recording_format(path) if Path(path).exists() else None
    if found is not None:
        what = {"tekscan": "a Tekscan export", "netcdf": "NetCDF", "zarr": "a Zarr store"}
        raise TactilecalError(f"{path} is a recording ({what.get(found, found)}); calibrate "
                              "expects a manifest "
                              "CSV (columns file, frame, load_N or mass_kg) or a Tekscan .cal "
                              "file, or a movie with --movie REC --loads LOADCELL.csv")
