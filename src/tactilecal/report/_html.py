"""Assemble the self-contained HTML report and write it atomically."""

import html
import platform
import sys
from datetime import UTC, datetime
from importlib import metadata
from pathlib import Path

from tactilecal._atomic import write_text_atomic
from tactilecal._progress import resolve
from tactilecal._version import __version__
from tactilecal.report._inputs import load_input
from tactilecal.report._sections import (
    calibration_blocks,
    filter_blocks,
    note_html,
    recording_blocks,
    table_html,
)

__all__ = ["build_report", "write_report"]

_CSS = """
body{font-family:system-ui,sans-serif;max-width:1000px;margin:2em auto;padding:0 1em;color:#222}
h1{border-bottom:2px solid #444}h2{margin-top:2em;border-bottom:1px solid #aaa}
table{border-collapse:collapse;margin:0.8em 0}td,th{border:1px solid #ccc;padding:2px 8px;
text-align:left;font-size:0.9em}th{background:#eee}figure{margin:1em 0}
figure{display:inline-block;vertical-align:top;width:47%;margin:0.5em}img{max-width:100%}figcaption{font-size:0.9em;color:#555}
pre{background:#f6f6f6;padding:0.6em;overflow-x:auto}.note{background:#fff4d6;padding:0.4em}
"""
_PACKAGES = ("numpy", "scipy", "pandas", "xarray", "matplotlib", "dask")


def _versions():
    rows = [("tactilecal", __version__), ("python", sys.version.split()[0]),
            ("platform", platform.platform())]
    for name in _PACKAGES:
        try:
            rows.append((name, metadata.version(name)))
        except metadata.PackageNotFoundError:
            rows.append((name, "not installed"))
    return rows


def _pick_calibration(calibration, loaded):
    """Return the calibration for raw recordings: the one given, else the only input one."""
    if calibration is not None:
        return calibration
    found = [obj for kind, obj, _, _ in loaded if kind == "calibration"]
    return found[0] if len(found) == 1 else None


def _load_all(inputs, calibration, filter, progress):
    items = list(inputs)
    extra = []
    if calibration is not None:
        extra.append(calibration)
    if filter is not None:
        extra.append(filter)
    loaded = []
    todo = extra + items
    for item in progress(todo, total=len(todo), desc="report"):
        kind, obj, prov = load_input(item)
        label = Path(str(item)).name if isinstance(item, str | Path) else prov["input"]
        if any(prov.get("sha256") and prov.get("sha256") == p.get("sha256")
               and p.get("path") == prov.get("path") for _, _, p, _ in loaded):
            continue  # the same file given twice (as input and as --cal)
        loaded.append((kind, obj, prov, label))
    if not loaded:
        raise ValueError("no report inputs; expected at least one calibration JSON, "
                         "FILTER.json or recording")
    return loaded


def build_report(inputs, *, calibration=None, filter=None, title=None, threshold_kPa=0.0,
                 nonworking=None, command=None, progress=None):
    """Return the HTML text of a report on ``inputs`` (see :func:`write_report`)."""
    progress = resolve(progress)
    loaded = _load_all(inputs, calibration, filter, progress)
    cal_obj = None
    if calibration is not None:
        cal_obj = load_input(calibration)[1]
    cal_obj = _pick_calibration(cal_obj, loaded)
    n_cal = sum(kind == "calibration" for kind, *_ in loaded)
    heading = {"calibration": "Calibration", "filter": "Dynamic filter",
               "recording": "Recording"}
    body = []
    for kind, obj, _, label in progress(loaded, total=len(loaded), desc="report"):
        body.append(f"<h2>{heading[kind]}: {html.escape(label)}</h2>")
        if kind == "calibration":
            body += calibration_blocks(obj, label)
        elif kind == "filter":
            body += filter_blocks(obj, label)
        else:
            if obj.attrs.get("units") == "raw" and cal_obj is None and n_cal > 1:
                body.append(note_html(f"{n_cal} calibrations among the inputs: give one "
                                      "with calibration=/--cal to analyse raw recordings"))
            body += recording_blocks(obj, label, calibration=cal_obj,
                                     threshold_kPa=threshold_kPa, nonworking=nonworking)
    body.append("<h2>Provenance</h2>")
    body.append(table_html([(kind, label, prov.get("path", prov.get("input")),
                             prov.get("size_bytes", ""), prov.get("sha256", ""),
                             prov.get("modified_utc", ""))
                            for kind, _, prov, label in loaded],
                           header=("kind", "input", "path", "bytes", "sha256",
                                   "modified (UTC)")))
    created = datetime.now(UTC).isoformat(timespec="seconds")
    rows = [("report created (UTC)", created), *_versions()]
    if command:
        rows.insert(1, ("command", command))
    body.append(table_html(rows, header=("item", "value")))
    title = title or "tactilecal report"
    return (f'<!DOCTYPE html>\n<html lang="en"><head><meta charset="utf-8">'
            f"<title>{html.escape(title)}</title><style>{_CSS}</style></head><body>"
            f"<h1>{html.escape(title)}</h1>" + "\n".join(body) + "</body></html>\n")


def write_report(inputs, path, *, calibration=None, filter=None, title=None, threshold_kPa=0.0,
                 nonworking=None, command=None, progress=None):
    """Write one self-contained HTML report (figures embedded as base64 PNG).

    Parameters
    ----------
    inputs : iterable
        Calibration JSON files or :class:`~tactilecal.calibration.CalibrationResult`
        objects (curve, points, error histogram, Zvyagin figures for ``method="zvyagin"``),
        FILTER.json files or filters (parameters and transfer-function fit), recordings
        (Tekscan ASCII, NetCDF ``.nc`` or DataArrays: force against time, pressure map at
        the peak-force frame, centre-of-force path, profiles).
    path : str or os.PathLike
        Output ``.html`` file, written atomically.
    calibration : path or CalibrationResult, optional
        Calibration for raw recordings (also reported). Without it, the only calibration
        among ``inputs`` is used; raw recordings with none say so in their section.
    filter : path or CorrectionFilter, optional
        Dynamic filter to report alongside.
    title : str, optional
        Page title (default "tactilecal report").
    threshold_kPa : float, default 0
        Loaded-sensel threshold for contact areas.
    nonworking : array_like of bool, optional
        Non-working sensels left out of the profiles.
    command : str, optional
        Command line to record in the provenance section.
    progress : callable, optional
        ``progress(iterable, total=, desc=)`` wrapping the inputs, e.g. a progress bar (the
        protocol of :mod:`tactilecal._progress`); None: no bar.

    Returns
    -------
    pathlib.Path
        The written file.

    Raises
    ------
    ValueError
        For an input that is neither a calibration, a filter nor a recording, or no inputs.
    FileNotFoundError
        For a missing input or output folder.
    """
    path = Path(path)
    if not path.parent.is_dir():
        raise FileNotFoundError(f"cannot write {path}: folder {path.parent} does not exist")
    text = build_report(inputs, calibration=calibration, filter=filter, title=title,
                        threshold_kPa=threshold_kPa, nonworking=nonworking, command=command,
                        progress=progress)
    write_text_atomic(path, text)
    return path
