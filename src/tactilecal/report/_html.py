"""Assemble the self-contained HTML report and write it atomically."""

import html
import platform
import sys
from datetime import UTC, datetime
from importlib import metadata
from pathlib import Path

from tactilecal._atomic import write_text_atomic
from tactilecal._errors import TactilecalError
from tactilecal._progress import resolve
from tactilecal._version import __version__
from tactilecal.report._figures import note_html, table_html
from tactilecal.report._inputs import load_input
from tactilecal.report._sections import (
    calibration_blocks,
    comparison_blocks,
    evaluation_blocks,
    filter_blocks,
    recording_blocks,
)

__all__ = ["build_report", "write_report"]

_CSS = """
body{font-family:system-ui,sans-serif;max-width:1200px;margin:2em auto;padding:0 1em;color:#222}
h1{border-bottom:2px solid #444}h2{margin-top:2em;border-bottom:1px solid #aaa}
div.table{max-width:100%;overflow-x:auto;margin:0.8em 0}
table{border-collapse:collapse}td,th{border:1px solid #ccc;padding:2px 8px;text-align:left;
font-size:0.9em;vertical-align:top}th{background:#eee}
div.wide td{overflow-wrap:break-word;max-width:40em}
figure{display:inline-block;vertical-align:top;max-width:100%;margin:0.5em 1em 1em 0}
img{max-width:100%;height:auto}figcaption{font-size:0.9em;color:#444;max-width:40em}
pre{background:#f6f6f6;padding:0.6em;overflow-x:auto;white-space:pre-wrap}
.note{background:#fff4d6;padding:0.4em}
"""
_PACKAGES = ("numpy", "scipy", "pandas", "xarray", "matplotlib", "dask")
_HEADINGS = {"calibration": "Calibration", "validation": "Validation",
             "filter": "Dynamic filter", "evaluation": "Blind test of a dynamic filter",
             "recording": "Recording"}


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


def _given_calibration(calibration, loaded):
    """Return the ``calibration=`` input as loaded (it is first), checked to be a calibration."""
    if calibration is None:
        return None
    kind, obj, _, label = loaded[0]
    if kind != "calibration":
        raise TactilecalError(f"calibration= (--cal) {label} is a {kind}; expected a calibration "
                              "JSON or CalibrationResult")
    return obj


def _load_all(inputs, calibration, filter, progress):
    items = [*(x for x in (calibration, filter) if x is not None), *inputs]
    loaded = []
    for item in progress(items, total=len(items), desc="report"):
        kind, obj, prov = load_input(item)
        label = Path(str(item)).name if isinstance(item, str | Path) else prov["input"]
        if any(prov.get("sha256") and prov.get("sha256") == p.get("sha256")
               and p.get("path") == prov.get("path") for _, _, p, _ in loaded):
            continue  # the same file given twice (as input and as --cal)
        loaded.append((kind, obj, prov, label))
    if not loaded:
        raise TactilecalError("no report inputs; expected at least one calibration JSON, "
                              "validation JSON, FILTER.json, blind-test JSON or recording")
    return loaded


def _of(kind, loaded):
    return [(label, obj) for k, obj, _, label in loaded if k == kind]


def _section(kind, obj, label, context):
    if kind == "calibration":
        return calibration_blocks(obj, label)
    if kind == "validation":
        return [table_html(sorted(obj.metrics.items()), header=("held-out check", "value"))]
    if kind == "filter":
        return filter_blocks(obj, label)
    if kind == "evaluation":
        return evaluation_blocks(obj, label)
    blocks = []
    if obj.attrs.get("units") == "raw" and context["calibration"] is None \
            and context["n_calibrations"] > 1:
        blocks.append(note_html(f"{context['n_calibrations']} calibrations among the inputs: "
                                "give one with calibration=/--cal to analyse raw recordings"))
    return blocks + recording_blocks(obj, label, calibration=context["calibration"],
                                     threshold_kPa=context["threshold_kPa"],
                                     nonworking=context["nonworking"],
                                     cof_min_force_N=context["cof_min_force_N"])


def _provenance(loaded, command):
    rows = [(kind, label, prov.get("path", prov.get("input")), prov.get("size_bytes", ""),
             prov.get("sha256", ""), prov.get("modified_utc", ""))
            for kind, _, prov, label in loaded]
    versions = [("report created (UTC)", datetime.now(UTC).isoformat(timespec="seconds")),
                *_versions()]
    if command:
        versions.insert(1, ("command", command))
    return ["<h2>Provenance</h2>",
            table_html(rows, header=("kind", "input", "path", "bytes", "sha256",
                                     "modified (UTC)"), wide=True),
            table_html(versions, header=("item", "value"), wide=True)]


def build_report(inputs, *, calibration=None, filter=None, title=None, threshold_kPa=0.0,
                 nonworking=None, cof_min_force_N=None, command=None, progress=None):
    """Return the HTML text of a report on ``inputs`` (see :func:`write_report`).

    Examples
    --------
    >>> from tactilecal.calibration import header_calibration
    >>> cal = header_calibration({"sensel_area_mm2": 2.0, "calibration_point_1_load_N": 10.0,
    ...                           "calibration_point_1_raw_sum": 100.0})
    >>> html = build_report([cal], title="header calibration")
    >>> html.startswith("<!DOCTYPE html>"), "<h2>Provenance</h2>" in html
    (True, True)
    """
    progress = resolve(progress)
    loaded = _load_all(inputs, calibration, filter, progress)
    calibrations = _of("calibration", loaded)
    context = {"calibration": _pick_calibration(_given_calibration(calibration, loaded), loaded),
               "n_calibrations": len(calibrations), "threshold_kPa": threshold_kPa,
               "nonworking": nonworking, "cof_min_force_N": cof_min_force_N}
    body = []
    if len(calibrations) > 1:
        body += ["<h2>Method comparison</h2>",
                 *comparison_blocks(calibrations, _of("validation", loaded))]
    for kind, obj, _, label in progress(loaded, total=len(loaded), desc="report"):
        body.append(f"<h2>{_HEADINGS[kind]}: {html.escape(label)}</h2>")
        body += _section(kind, obj, label, context)
    body += _provenance(loaded, command)
    title = title or "tactilecal report"
    return (f'<!DOCTYPE html>\n<html lang="en"><head><meta charset="utf-8">'
            f'<meta name="viewport" content="width=device-width, initial-scale=1">'
            f"<title>{html.escape(title)}</title><style>{_CSS}</style></head><body>"
            f"<h1>{html.escape(title)}</h1>" + "\n".join(body) + "</body></html>\n")


def write_report(inputs, path, *, calibration=None, filter=None, title=None, threshold_kPa=0.0,
                 nonworking=None, cof_min_force_N=None, command=None, progress=None):
    """Write one self-contained HTML report (figures embedded as 2x PNG).

    Parameters
    ----------
    inputs : iterable
        Calibration JSON files or :class:`~tactilecal.calibration.CalibrationResult`
        objects (curve, points, error histogram, Zvyagin figures for ``method="zvyagin"``;
        with two or more, a method comparison first: parameters, intervals, training and
        held-out errors, all curves on one plot), validation JSON files (``tactilecal
        validate --json``: the held-out errors of the comparison), FILTER.json files or
        filters (parameters and transfer function), blind-test JSON files (``tactilecal
        dynamic evaluate``: RMS, amplitude and phase error before and after), recordings
        (Tekscan ASCII, NetCDF ``.nc`` or DataArrays: force and contact area against time,
        peak-pressure map, pressure map and profiles at the peak-force frame,
        centre-of-force path; a raw recording without a calibration in raw readings).
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
    cof_min_force_N : float, optional
        The centre-of-force path leaves out frames with less force (default 5 % of the
        recording's peak force).
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
        For an input of no known kind, or no inputs.
    FileNotFoundError
        For a missing input or output folder.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from tactilecal.calibration import header_calibration
    >>> cal = header_calibration({"sensel_area_mm2": 2.0, "calibration_point_1_load_N": 10.0,
    ...                           "calibration_point_1_raw_sum": 100.0})
    >>> out = write_report([cal], pathlib.Path(tempfile.mkdtemp()) / "report.html")
    >>> out.name, out.read_text().count("<img")  # the law, its points, their errors
    ('report.html', 3)
    """
    path = Path(path)
    if not path.parent.is_dir():
        raise FileNotFoundError(f"cannot write {path}: folder {path.parent} does not exist")
    text = build_report(inputs, calibration=calibration, filter=filter, title=title,
                        threshold_kPa=threshold_kPa, nonworking=nonworking,
                        cof_min_force_N=cof_min_force_N, command=command, progress=progress)
    write_text_atomic(path, text)
    return path
