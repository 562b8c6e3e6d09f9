"""Assemble the self-contained HTML report and write it atomically."""

import html
import os
import platform
import sys
from collections.abc import Iterable
from datetime import UTC, datetime
from importlib import metadata
from pathlib import Path

from tactilecal._atomic import check_target, write_text_atomic
from tactilecal._errors import TactilecalError
from tactilecal._jsonutil import dumps
from tactilecal._progress import resolve
from tactilecal._text import number, share
from tactilecal._version import __version__
from tactilecal.report._figures import details_html, note_html, table_html
from tactilecal.report._inputs import load_input
from tactilecal.report._player import PLAYER_SCRIPT
from tactilecal.report._recording import aligned_blocks, recording_blocks
from tactilecal.report._sections import (
    calibration_blocks,
    comparison_blocks,
    evaluation_blocks,
    filter_blocks,
    input_set_sha256,
)

__all__ = ["build_report", "write_report"]

_CSS = """
body{font-family:system-ui,sans-serif;max-width:1200px;margin:2em auto;padding:0 1em;color:#222}
h1{border-bottom:2px solid #444}h2{margin-top:2em;border-bottom:1px solid #aaa}
h2,h3{break-after:avoid;page-break-after:avoid}
div.table{max-width:100%;margin:0.8em 0}
table{border-collapse:collapse;max-width:100%}td,th{border:1px solid #ccc;padding:2px 8px;
text-align:left;font-size:0.9em;vertical-align:top}th{background:#eee}
div.wide td{overflow-wrap:anywhere}div.wide td:first-child{overflow-wrap:break-word}
div.wide table{table-layout:auto;width:100%}
figure{display:inline-block;vertical-align:top;max-width:100%;margin:0.5em 1em 1em 0;
break-inside:avoid;page-break-inside:avoid}
img{max-width:100%;height:auto}figcaption,p.caption{font-size:0.9em;color:#444;max-width:48em}
pre{background:#f6f6f6;padding:0.6em;white-space:pre-wrap;overflow-wrap:anywhere}
.note{background:#fff4d6;padding:0.4em}
details{margin:0.6em 0}summary{cursor:pointer;color:#225}
div.player{break-inside:avoid;page-break-inside:avoid;margin:0.5em 0}
div.player-row{display:flex;flex-wrap:wrap;align-items:flex-start;gap:0.8em}
div.player canvas{border:1px solid #ccc;max-width:100%}
div.player svg.trace{width:640px;max-width:100%;height:150px;border:1px solid #eee}
div.player input.slider{width:min(640px,100%);display:block;margin:0.4em 0}
div.legend{position:relative;width:5.5em;height:12em}
div.legend .bar{position:absolute;left:0;top:0;width:1em;height:12em;border:1px solid #999}
div.legend .top{position:absolute;left:1.4em;top:-0.3em;font-size:0.8em}
div.legend .bottom{position:absolute;left:1.4em;bottom:-0.3em;font-size:0.8em}
.player-note{color:#666;font-size:0.85em}
div.tables{display:flex;flex-wrap:wrap;gap:0 1.5em;align-items:flex-start}
div.tables>div{flex:1 1 24em;min-width:0}
@media print{
body{max-width:none;margin:0;padding:0;font-size:10pt}
h2{margin-top:1em}
figure{display:block;margin:0.4em 0 0.6em 0}
div.player input.slider,.player-note{display:none}
div.player canvas{max-height:2.8in;width:auto}
div.player svg.trace{width:4.4in;height:1.4in}
details{display:none}
a{color:inherit;text-decoration:none}
}
@page{margin:12mm}
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


def _one_or_many(inputs):
    """Return ``inputs`` as a list: one input (a path, a recording, a result) as a list of one.

    A recording is iterable (over its frames) and a path is a string, so both are one input.
    """
    import xarray as xr

    if isinstance(inputs, str | os.PathLike | xr.DataArray) or not isinstance(inputs, Iterable):
        return [inputs]
    return list(inputs)


def _load_all(inputs, calibration, filter, progress):
    items = [*(x for x in (calibration, filter) if x is not None), *_one_or_many(inputs)]
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
    if kind == "validation":  # shares as percentages, like the calibration's metrics
        return [table_html([(k, share(v) if k.startswith("within_") else number(v))
                            for k, v in sorted(obj.metrics.items())],
                           header=("held-out check", "value"))]
    if kind == "filter":
        return filter_blocks(obj, label)
    if kind == "evaluation":
        return evaluation_blocks(obj, label)
    return _recording_section(obj, label, context)


def _recording_section(obj, label, context):
    calibration = context["calibration"]
    if obj.attrs.get("units") == "raw" and calibration is None \
            and context["n_calibrations"] > 1:
        yield note_html(f"{context['n_calibrations']} calibrations among the inputs: give one "
                        "with calibration=/--cal to analyse raw recordings")
    if obj.attrs.get("units", "raw") != "raw" and calibration is not None:
        if context["given"]:
            raise TactilecalError(f"calibration= (--cal) applies to raw recordings, but {label} "
                                  f"is already calibrated (units {obj.attrs['units']!r}); "
                                  "expected raw recordings, or no calibration=")
        yield note_html(f"{label} is already calibrated (units {obj.attrs['units']}): the "
                        "calibration among the inputs is not applied to it")
        calibration = None
    context["players"] += 1
    yield from recording_blocks(obj, label, calibration=calibration,
                                threshold_kPa=context["threshold_kPa"],
                                nonworking=context["nonworking"],
                                cof_min_force_N=context["cof_min_force_N"],
                                units=context["units"], regions=context["regions"],
                                gap_mm=context["gap_mm"], player=context["player"],
                                key=f"player-{context['players']}")


def _provenance(loaded, command):
    """Return the provenance folded: counts, one hash per input set; the rest on opening."""
    created = datetime.now(UTC).isoformat(timespec="seconds")
    files = [(kind, label, prov) for kind, _, prov, label in loaded]
    rows = [("report created (UTC)", created), ("tactilecal version", __version__)]
    if command:
        rows.append(("command", command))
    by_kind = {}
    for kind, label, prov in files:
        by_kind.setdefault(kind, []).append((label, prov))
    for kind, items in by_kind.items():
        hashed = [prov for _, prov in items if prov.get("sha256")]
        names = ", ".join(label for label, _ in items[:3]) + (" ..." if len(items) > 3 else "")
        what = f"{len(items)} {kind}{'s' if len(items) > 1 else ''} ({names})"
        digest = input_set_sha256(hashed) if hashed else "in memory (no file)"
        rows.append((what, ("SHA-256 " if len(hashed) == 1 else "SHA-256 of the set ")
                     + digest if hashed else digest))
    full = [(kind, label, prov.get("path", prov.get("input")), prov.get("size_bytes", ""),
             prov.get("sha256", ""), prov.get("modified_utc", ""))
            for kind, label, prov in files]
    record = {"created_utc": created, "command": command, "inputs": [
        {"kind": kind, "label": label, **prov} for kind, label, prov in files],
        "versions": dict(_versions())}
    return ["<h2>Provenance</h2>",
            table_html(rows, header=("record", "value"), wide=True),
            details_html(f"every input ({len(files)}) with its path, size, SHA-256 and time",
                         table_html(full, header=("kind", "input", "path", "bytes", "sha256",
                                                  "modified (UTC)"), wide=True)),
            details_html("versions of tactilecal, Python and the libraries",
                         table_html(_versions(), header=("item", "value"), wide=True)),
            details_html("the provenance as JSON",
                         f'<pre class="provenance-json">{html.escape(dumps(record))}</pre>')]


def build_report(inputs, *, calibration=None, filter=None, title=None, threshold_kPa=0.0,
                 nonworking=None, cof_min_force_N=None, command=None, progress=None,
                 units=None, regions=None, gap_mm=None, align="time", player=True):
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
    from tactilecal.analysis import align_recordings

    progress = resolve(progress)
    align_recordings([], how=align)  # checks the alignment before any input is read
    loaded = _load_all(inputs, calibration, filter, progress)
    calibrations = _of("calibration", loaded)
    context = {"calibration": _pick_calibration(_given_calibration(calibration, loaded), loaded),
               "given": calibration is not None,
               "n_calibrations": len(calibrations), "threshold_kPa": threshold_kPa,
               "nonworking": nonworking, "cof_min_force_N": cof_min_force_N, "units": units,
               "regions": regions, "gap_mm": gap_mm, "player": player, "players": 0}
    body = []
    if len(calibrations) > 1:
        body += ["<h2>Method comparison</h2>",
                 *comparison_blocks(calibrations, _of("validation", loaded))]
    for kind, obj, _, label in loaded:
        body.append(f"<h2>{_HEADINGS[kind]}: {html.escape(label)}</h2>")
        body += progress(_section(kind, obj, label, context), desc=f"report: {label}")
    together = _calibrated_recordings(loaded, context["calibration"])
    if len(together) > 1:
        body += progress(aligned_blocks(together, how=align), desc="report: one time axis")
    body += _provenance(loaded, command)
    title = title or "tactilecal report"
    script = PLAYER_SCRIPT if context["players"] else ""
    return (f'<!DOCTYPE html>\n<html lang="en"><head><meta charset="utf-8">'
            f'<meta name="viewport" content="width=device-width, initial-scale=1">'
            f"<title>{html.escape(title)}</title><style>{_CSS}</style></head><body>"
            f"<h1>{html.escape(title)}</h1>" + "\n".join(body) + script
            + "</body></html>\n")


def _calibrated_recordings(loaded, calibration):
    """``(label, recording in kPa)`` of every recording that has forces (for one time axis).

    Empty when fewer than two have forces: one recording is not drawn again on its own axis,
    so a raw one is not calibrated a second time for nothing.
    """
    found = [(label, obj) for kind, obj, _, label in loaded if kind == "recording"
             and (obj.attrs.get("units") != "raw" or calibration is not None)]
    if len(found) < 2:
        return []
    return [(label, calibration.apply(obj, units="kPa") if obj.attrs.get("units") == "raw"
             else obj) for label, obj in found]


def write_report(inputs, path, *, calibration=None, filter=None, title=None, threshold_kPa=0.0,
                 nonworking=None, cof_min_force_N=None, command=None, progress=None,
                 units=None, regions=None, gap_mm=None, align="time", player=True,
                 overwrite=False):
    """Write one self-contained HTML report (figures embedded as 2x PNG).

    Parameters
    ----------
    inputs : input or iterable of inputs
        One input or several: calibration JSON files or
        :class:`~tactilecal.calibration.CalibrationResult` objects (curve, points, error
        histogram, Zvyagin figures for ``method="zvyagin"``; with two or more, a method
        comparison first: parameters, intervals, training and held-out errors, all curves on
        one plot), validation JSON files (``tactilecal validate --json``: the held-out
        errors of the comparison), FILTER.json files or filters (parameters and transfer
        function), blind-test JSON files (``tactilecal dynamic evaluate``: RMS, amplitude
        and phase error before and after), recordings (Tekscan ASCII, NetCDF ``.nc`` or
        DataArrays: the export's own header calibration, a frame player, force and contact
        area against time, the peak-pressure map, the peak-force frame and the
        centre-of-force path over the map, profiles, the steps of a recording with two or
        more; a raw recording without a calibration in raw readings). Two or more recordings
        with forces are also drawn on one time axis.
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
        ``progress(iterable, total=, desc=)`` wrapping the inputs and each section's
        figures, e.g. a progress bar (the protocol of :mod:`tactilecal._progress`); None:
        no bar.
    units : str, optional
        Pressure unit of the recordings' maps and numbers (kPa, MPa, psi...); default each
        recording's own pressure unit, else kPa.
    regions : Regions, dict or "contacts", optional
        Regions of every recording to report (force, area, peak, centre of force and
        pressure-time integral of each, their centres of force drawn); ``"contacts"``
        finds the separated contact areas (``rec.tactile.split_contacts``).
    gap_mm : float, optional
        For ``regions="contacts"``.
    align : {"time", "start", "onset"}, default "time"
        How recordings are put on one time axis (:func:`tactilecal.analysis.align_recordings`).
    player : bool, default True
        A frame player (slider, map, force trace with a cursor) for each recording; long
        recordings are decimated so that each player holds at most 1.5 MB of frames.
    overwrite : bool, keyword-only
        Replace an existing ``path`` (only an HTML page; default False: an error).

    Returns
    -------
    pathlib.Path
        The written file.

    Raises
    ------
    ValueError
        For an input of no known kind, or no inputs; ``path`` exists (without
        ``overwrite``, or is not an HTML page).
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
    check_target(path, overwrite=overwrite, kind="html")
    text = build_report(inputs, calibration=calibration, filter=filter, title=title,
                        threshold_kPa=threshold_kPa, nonworking=nonworking,
                        cof_min_force_N=cof_min_force_N, command=command, progress=progress,
                        units=units, regions=regions, gap_mm=gap_mm, align=align,
                        player=player)
    write_text_atomic(path, text)
    return path
