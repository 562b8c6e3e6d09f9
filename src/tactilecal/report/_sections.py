"""The sections of a report: calibration, dynamic filter, recording, provenance.

Each builder returns a list of HTML blocks. Figures come from the plot functions of the
subpackage that owns them; a figure that cannot be drawn (a module absent from this
version, missing intermediate results) is replaced by a note saying why, never by a
silent gap.
"""

import base64
import html
import io
import json

import numpy as np

from tactilecal._jsonutil import to_jsonable

__all__ = ["calibration_blocks", "filter_blocks", "recording_blocks", "figure_html",
           "table_html", "note_html"]


def _esc(value):
    return html.escape(str(value))


def note_html(text):
    """Return a highlighted note (where a figure or number is not available)."""
    return f'<p class="note">{_esc(text)}</p>'


def table_html(rows, header=None):
    """Return an HTML table built from an iterable of row tuples."""
    head = "" if header is None else "<tr>" + "".join(f"<th>{_esc(h)}</th>" for h in header) \
        + "</tr>"
    body = "".join("<tr>" + "".join(f"<td>{_esc(_fmt(v))}</td>" for v in row) + "</tr>"
                   for row in rows)
    return f"<table>{head}{body}</table>"


def _fmt(value):
    if isinstance(value, float | np.floating):
        return "n/a" if not np.isfinite(value) else f"{value:.6g}"
    return value


def figure_html(fig, caption):
    """Embed a matplotlib Figure as a base64 PNG ``<figure>`` with a caption."""
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=96)
    data = base64.b64encode(buf.getvalue()).decode("ascii")
    return (f'<figure><img alt="{_esc(caption)}" src="data:image/png;base64,{data}">'
            f"<figcaption>{_esc(caption)}</figcaption></figure>")


def _new_axes(figsize=(6, 4)):
    from matplotlib.figure import Figure

    return Figure(figsize=figsize, layout="constrained").subplots()


def _try_figure(caption, draw):
    """Draw a figure with ``draw()`` (returning a Figure or Axes); a note if it fails."""
    try:
        out = draw()
    except Exception as exc:  # any failure becomes a visible note, never a crash
        return note_html(f"{caption}: not drawn ({type(exc).__name__}: {exc})")
    fig = out if hasattr(out, "savefig") else np.ravel(out)[0].figure
    return figure_html(fig, caption)


def _zvyagin_figures(result, what):
    """Return the Zvyagin (2022) figures of a calibration result, one per plot function."""
    from tactilecal.zvyagin import (
        plot_ab_scatter,
        plot_calibration_curves,
        plot_d_map,
        plot_energy,
        plot_error_histogram,
        plot_pair_chart,
    )

    plots = (plot_d_map, plot_pair_chart, plot_ab_scatter, plot_calibration_curves,
             plot_error_histogram, plot_energy)
    return [_try_figure(f"{what}: {_first_line(fn)}", lambda fn=fn: fn(result)) for fn in plots]


def _first_line(fn):
    """Return the first line of a function's docstring (its name if it has none)."""
    doc = (fn.__doc__ or fn.__name__).strip()
    return doc.splitlines()[0].rstrip(".")


def calibration_blocks(result, label):
    """Summary, parameters, points table and figures of a calibration result."""
    from tactilecal.calibration import (
        plot_calibration_curve,
        plot_error_histogram,
        plot_points,
    )

    intervals = result.details.get("params_interval") or {}
    params = [(k, v, result.params_stderr.get(k),
               " .. ".join(f"{x:.6g}" for x in intervals[k]) if k in intervals
               else intervals.get("unbounded", "none (no n_bootstrap)"))
              for k, v in result.params.items() if np.ndim(v) == 0]
    blocks = [
        f"<pre>{_esc(result.summary())}</pre>",
        table_html(params, header=("parameter", "value", "bootstrap standard error",
                                   "95 % interval")),
        table_html(sorted(result.metrics.items()), header=("metric", "value")),
        table_html([("created", getattr(result, "created", "")),
                    ("tactilecal version", getattr(result, "version", "")),
                    ("options", json.dumps(to_jsonable(getattr(result, "options", {}))))],
                   header=("calibration record", "value")),
        _try_figure(f"{label}: calibration curve",
                    lambda: plot_calibration_curve(result, ax=_new_axes())),
        _try_figure(f"{label}: calibrated against applied load",
                    lambda: plot_points(result, ax=_new_axes())),
        _try_figure(f"{label}: error histogram",
                    lambda: plot_error_histogram(result, ax=_new_axes())),
    ]
    if result.method == "zvyagin" or result.details:
        if result.method == "zvyagin":
            blocks += _zvyagin_figures(result, f"{label}: Zvyagin (2022)")
        else:
            blocks.append(f"<p>Method {_esc(repr(result.method))} keeps intermediate results "
                          f"under 'details': {_esc(', '.join(sorted(result.details)))}.</p>")
    return blocks


def _draw_fit(fit):
    ax = _new_axes()
    f = np.asarray(fit["f_hz"], dtype=float)
    ax.plot(f, np.asarray(fit["measured"], dtype=float), ".", ms=4, label="measured")
    ax.plot(f, np.asarray(fit["fitted"], dtype=float), "-", label=f"fit ({fit['model']})")
    ax.set_xlabel("frequency [Hz]")
    ax.set_ylabel("|load cell| / |sensor|")
    ax.legend(frameon=False)
    return ax


def filter_blocks(data, label):
    """Parameters and fit figures of a dynamic filter (FILTER.json content)."""
    keys = ("model", "A", "log_base", "lag_s", "fs_hz", "band_hz", "outside", "n_taps")
    blocks = [table_html([(k, data.get(k)) for k in keys if k in data],
                         header=("key", "value"))]
    if data.get("forced"):
        blocks.append(note_html(f"{label} was written with --force although its model was "
                                f"refused: {data.get('forced_reason')}"))
    fit = data.get("fit")
    if not fit:
        return blocks + [note_html(f"{label}: no fitted transfer function stored (fit is "
                                   "empty), so no fit figure")]
    excluded = fit.get("excluded") or {}
    rows = [(k, fit.get(k)) for k in ("r2", "rmse", "method", "r2_complex")]
    rows += [(k, excluded[k]) for k in ("model_choice", "model_r2_complex", "rational",
                                        "sensor_delay_s") if k in excluded]
    blocks.append(table_html(rows, header=("fit", "value")))
    try:
        from tactilecal.dynamic import plot_transfer
    except ImportError:
        blocks.append(note_html("tactilecal.dynamic.plot_transfer is not part of this "
                                "version; the fit is drawn from the filter file's points"))
        return blocks + [_try_figure(f"{label}: transfer function and fit",
                                     lambda: _draw_fit(fit))]
    from tactilecal.dynamic import CorrectionFilter

    blocks.append(_try_figure(
        f"{label}: transfer function, fitted model and filter gain (Gillis 2013 Fig. 4.9)",
        lambda: plot_transfer(CorrectionFilter.from_dict(data, where=label))))
    return blocks + [note_html("time-history, spectra and error figures need the evaluation "
                               "records, which a FILTER.json does not hold")]


def recording_blocks(recording, label, *, calibration=None, threshold_kPa=0.0,
                     nonworking=None):
    """Key numbers and figures of one recording (force, peak map, centre path, profiles)."""
    from tactilecal import analysis

    attrs = recording.attrs
    info = [(k, attrs[k]) for k in ("source", "sensor_type", "units", "sensel_area_mm2",
                                    "row_spacing_mm", "col_spacing_mm", "seconds_per_frame",
                                    "sensitivity", "calibration_method",
                                    "saturation_pressure_kPa") if k in attrs]
    info.insert(0, ("frames x rows x cols", " x ".join(str(n) for n in recording.shape)))
    blocks = [table_html(info, header=("property", "value"))]
    if attrs.get("units") == "raw" and calibration is None:
        return blocks + [note_html(f"{label} holds raw readings and no calibration was "
                                   "given, so force and pressure cannot be shown; pass a "
                                   "calibration JSON (--cal)")]
    if attrs.get("units") == "raw":
        recording = calibration.apply(recording, units="kPa")
        blocks.append(note_html(f"raw readings calibrated with method "
                                f"{calibration.method!r} ({calibration.model})"))
    s = analysis.summary(recording, threshold_kPa=threshold_kPa).compute()
    i = analysis.peak_frame(s)
    t = s["time"].values if "time" in s.coords else np.arange(s.sizes["frame"])
    numbers = [
        ("duration [s]", float(t[-1] - t[0]) if len(t) else float("nan")),
        ("peak total force [N]", float(s.force_N[i])),
        ("time of peak force [s]", float(t[i])),
        ("frame of peak force", recording["frame"].values[i]),
        ("largest contact area [mm2]", float(s.contact_area_mm2.max())),
        ("largest sensel pressure [kPa]", float(s.peak_kPa.max())),
        ("loaded-sensel threshold [kPa]", float(threshold_kPa)),
    ]
    saturated = (int((s["saturated_sensels"] > 0).sum()) if "saturated_sensels" in s
                 else "unknown")
    numbers.append(("frames with saturated sensels", saturated))
    blocks.append(table_html(numbers, header=("quantity", "value")))
    if saturated not in (0, "unknown"):
        blocks.append(note_html(f"{saturated} of {s.sizes['frame']} frames hold sensels at "
                                f"saturation ({s.attrs['saturation_rule']}): their force "
                                "and pressures are lower bounds, not measurements"))
    blocks += [
        _try_figure(f"{label}: total force and contact area against time",
                    lambda: analysis.plot_force_time(s)),
        _try_figure(f"{label}: pressure map at the peak-force frame",
                    lambda: analysis.plot_pressure_map(recording, i)),
        _try_figure(f"{label}: centre-of-force path", lambda: analysis.plot_cof_path(s)),
        _try_figure(f"{label}: row and column profiles at the peak-force frame",
                    lambda: analysis.plot_profiles(recording, i, nonworking=nonworking)),
    ]
    return blocks
