"""The sections of a report: methods compared, calibration, filter, blind test.

The recordings' sections are in :mod:`tactilecal.report._recording`.

Each builder returns a list of HTML blocks. Every figure says under it what it shows and
how to read it. What a section cannot show is decided from its input before anything is
drawn (a raw recording without a calibration, a filter file without its fit) and said in a
note; a figure that fails to draw for any other reason is a bug and raises.
"""

import hashlib
import html
import json

import numpy as np

from tactilecal._jsonutil import to_jsonable
from tactilecal._text import number, share
from tactilecal._units import N_PER_MM2_TO_KPA
from tactilecal.report._figures import (
    details_html,
    figure_html,
    new_axes,
    note_html,
    table_html,
)

__all__ = ["comparison_blocks", "calibration_blocks", "filter_blocks", "evaluation_blocks",
           "input_set_sha256"]


def _scalar_params(result):
    return [(k, v) for k, v in result.params.items() if np.ndim(v) == 0]


# ---------------------------------------------------------------- method comparison
def comparison_blocks(calibrations, validations):
    """Every calibration side by side: parameters, training and held-out errors.

    Parameters
    ----------
    calibrations : list of (label, CalibrationResult)
    validations : list of (label, ValidationResult)
        Outputs of :func:`tactilecal.calibration.validate` (``tactilecal validate --json``);
        each is matched to the calibration whose fingerprint it records
        (``calibration_sha256``).
    """
    by_print = {result.fingerprint(): position
                for position, (_, result) in enumerate(calibrations)}
    held_out = {}
    for _, check in validations:
        position = by_print.get(check.metrics.get("calibration_sha256"))
        if position is not None:
            held_out[position] = check.metrics
    rows = []
    for position, (label, result) in enumerate(calibrations):
        params = ", ".join(f"{k} = {number(v)}" for k, v in _scalar_params(result)) or "table"
        check = held_out.get(position, {})
        rows.append((label, result.method, result.model, params,
                     f"{result.metrics['n']} of {result.metrics['n_points']}",
                     number(result.metrics.get("median_abs_error_pct")),
                     share(result.metrics.get("within_5pct")),
                     number(check["median_abs_error_pct"]) if check else "no validation input",
                     share(check["within_5pct"]) if check else ""))
    blocks = [table_html(rows, header=(
        "calibration", "method", "model", "parameters", "points used",
        "training median |error| %", "training share within 5 %",
        "held-out median |error| %", "held-out share within 5 %"), wide=True)]
    if not held_out:
        blocks.append(note_html("no validation among the inputs: the errors above are on the "
                                "calibration's own points, which flatter it; add the JSON of "
                                "'tactilecal validate CAL.json MANIFEST --json' for held-out "
                                "errors"))
    return blocks + [figure_html(
        _draw_curves(calibrations), "Calibration curves of all methods",
        "Each line is one calibration's pressure on a sensel against its raw reading; where "
        "the lines part, the methods disagree, most often above the highest calibration "
        "load, where only the chosen law extrapolates.")]


def _draw_curves(calibrations):
    ax = new_axes((7.5, 4.5))
    raw = np.arange(256)
    for label, result in calibrations:
        pressure_kPa = result.force_table() / result.sensel_area_mm2 * N_PER_MM2_TO_KPA
        ax.plot(raw[1:], pressure_kPa[1:], lw=1.2, label=f"{label} ({result.method})")
    ax.set(xlabel="raw reading (0..255)", ylabel="pressure on a sensel [kPa]")
    ax.legend(fontsize="small", frameon=False)
    return ax


# ---------------------------------------------------------------- one calibration
def calibration_blocks(result, label):
    """Yield the summary, parameters, record and figures of one calibration result."""
    loads = np.asarray(result.points["load_N"], float) if len(result.points) else np.ones(1)
    scale = float(np.nanmax(np.abs(loads))) if np.isfinite(loads).any() else 1.0
    metrics = [(k, share(v) if k.startswith("within_") else _metric(k, v, scale))
               for k, v in result.metrics.items()]
    yield f"<pre>{html.escape(result.summary())}</pre>"
    yield from _choice_blocks(result, label)
    yield table_html(metrics, header=("metric", "value"))
    yield from _record_blocks(result)
    yield figure_html(result.plot_curve(ax=new_axes()),
                      f"{label}: calibration curve",
                      "The line is the fitted law; each point is one calibration patch's "
                      "applied load per loaded sensel at its mean raw reading; open points "
                      "were not used (saturated or rejected).")
    yield figure_html(result.plot_points(ax=new_axes()),
                      f"{label}: calibrated against applied load",
                      "Each point is a calibration patch; on the diagonal the calibrated load "
                      "equals the applied one, and the vertical distance is its error.")
    yield figure_html(result.plot_error_histogram(ax=new_axes()),
                      f"{label}: error histogram",
                      "How many patches the calibration misses by how much, in percent of the "
                      "applied load; a narrow peak at 0 is a good calibration.")
    if result.method_result is not None:
        yield from _zvyagin_blocks(result.method_result, label)


def _choice_blocks(result, label):
    """How ``auto`` chose the method, whether the law fits, the gains learned with it."""
    blocks = []
    if result.lack_of_fit is not None and result.lack_of_fit.flagged:
        blocks += [note_html(f"{label}: {message}") for message in result.lack_of_fit.messages]
    if result.selection is not None:
        rows = [(s["candidate"], "not fitted: " + s["note"] if s["rms_rel"] is None
                 else share(s["rms_rel"], 2), "" if s["excess_se"] is None
                 else number(s["excess_se"], 2),
                 "chosen" if s["candidate"] == result.selection.chosen else "")
                for s in result.selection.scores]
        blocks += [f"<p>{html.escape(result.selection.reason)}</p>",
                   table_html(rows, header=("candidate", "held-out RMS error",
                                            "above the best (standard errors)", ""))]
    gains = result.diagnostics.get("gains")
    if gains and gains["chosen"] != "none" and result.equilibration is not None:
        blocks.append(figure_html(
            result.equilibration.plot_gains(ax=new_axes((5.0, 4.2))),
            f"{label}: gains learned with the law ({gains['chosen']})",
            "Each sensel's reading is multiplied by its gain before the law: red sensels "
            "read low and are raised, blue ones read high; a smooth pattern is a field over "
            f"the sensor, isolated spots single sensels. {gains['reason']}."))
    return blocks


#: A force below this share of the largest calibration load is 0 at the loads' precision.
FORCE_RESOLUTION_SHARE = 1e-9


def _metric(key, value, scale):
    """Return a metric for people; an error in N far below the loads' precision is 0."""
    if key.endswith("_N") and isinstance(value, float) and np.isfinite(value) \
            and abs(value) < FORCE_RESOLUTION_SHARE * scale:
        return "0 (below 1e-9 of the largest load)"
    return number(value)


def input_set_sha256(inputs):
    """One SHA-256 for a set of input files: that of its sorted ``sha256  name`` lines.

    A single file's own SHA-256 is returned unchanged (``sha256sum`` gives the same).

    Examples
    --------
    >>> input_set_sha256([{"sha256": "ab", "path": "/x/a.csv"}])
    'ab'
    >>> len(input_set_sha256([{"sha256": "ab", "path": "a"}, {"sha256": "cd", "path": "b"}]))
    64
    """
    inputs = [i for i in inputs if i.get("sha256")]
    if len(inputs) == 1:
        return inputs[0]["sha256"]
    lines = sorted(f"{i['sha256']}  {i.get('path', '')}" for i in inputs)
    return hashlib.sha256("\n".join(lines).encode("utf-8")).hexdigest()


def _record_blocks(result):
    """Yield the record (created, version, options, sensor) and the inputs, folded."""
    prov = result.provenance
    rows = [("created", result.created), ("tactilecal version", result.version),
            ("options", json.dumps(to_jsonable(result.options)))]
    inputs = prov.get("inputs", []) if prov else []
    if prov:
        rows.append(("sensor type, serial (export header)",
                     f"{prov.get('sensor_type') or 'unknown'}, "
                     f"{prov.get('sensor_serial') or 'unknown'}"))
    if inputs:
        rows.append((f"inputs ({len(inputs)} files)",
                     f"SHA-256 of the set {input_set_sha256(inputs)}"))
    yield table_html(rows, header=("calibration record", "value"), wide=True)
    if inputs:
        listed = [(k + 1, entry["path"], entry.get("size_bytes", ""), entry["sha256"])
                  for k, entry in enumerate(inputs)]
        yield details_html(f"all {len(inputs)} input files with their SHA-256",
                           table_html(listed, header=("", "path", "bytes", "sha256"),
                                      wide=True))


_ZVYAGIN_FIGURES = (
    ("plot_d_map", "d map (Fig. 7)",
     "Each cell is the discrepancy d of one choice of the class separation; the darkest cell "
     "is the separation the method keeps."),
    ("plot_pair_chart", "chart of pairs (Fig. 8)",
     "Patches sorted by load on both axes; a mark is a pair whose two equations gave an "
     "(A, b) solution, shaded patches (grey) take part in none."),
    ("plot_ab_scatter", "(A, b) of the pairs (Fig. 9)",
     "Each point is one pair's power law; they lie along a ridge because A and b trade off, "
     "and the cross is the law chosen by the energy minimum; points far off the ridge are "
     "pairs the 10 % rule should have left out."),
    ("plot_calibration_curves", "calibration curves (Fig. 10)",
     "The chosen law against the laws of the terminal points T1 and T2; their spread is how "
     "far the pair solutions disagree."),
    ("plot_patch_errors", "error per patch (Fig. 11)",
     "The misfit of every patch in percent of its applied load, by weight; a weight whose "
     "bars all lean one way shows a law that bends away from the data at that load."),
    ("plot_energy", "energy along the power-law curve (eq. 15)", None),
)

_ENERGY_FAITHFUL = ("E against the exponent b0 along the fitted A(b) curve; the orange line at "
                    "its minimum is the chosen b0, and a flat valley means b0 is poorly "
                    "determined.")
_ENERGY_ROBUST = ("E against the exponent b0 along the fitted A(b) curve, its minimum marked "
                  "in orange; robust mode returned another law, a free power-law fit of all "
                  "patches (dashed blue, b = {b}), which need not lie on this curve nor at its "
                  "minimum.")


def energy_caption(zvyagin):
    """How to read the energy figure: what it marks depends on what the mode returned."""
    if zvyagin.final.get("free"):
        return _ENERGY_ROBUST.format(b=number(zvyagin.b0))
    return _ENERGY_FAITHFUL


def _zvyagin_blocks(zvyagin, label):
    """Yield the paper's figures of a Zvyagin calibration (its ``method_result``)."""
    for name, title, how in _ZVYAGIN_FIGURES:
        yield figure_html(getattr(zvyagin, name)(), f"{label}: Zvyagin (2022) {title}",
                          how or energy_caption(zvyagin))


# ---------------------------------------------------------------- dynamic filter
def filter_blocks(filt, label):
    """Show the parameters, fit and transfer function of a dynamic filter."""
    keys = ("model", "A", "log_base", "lag_s", "fs_hz", "band_hz", "outside", "n_taps")
    data = filt.to_dict()
    blocks = [table_html([(k, data.get(k)) for k in keys], header=("key", "value"))]
    if filt.forced:
        blocks.append(note_html(f"{label} was written with --force although its model was "
                                f"refused: {filt.forced}"))
    fit = filt.fit
    if fit is not None:
        rows = [("r2", fit.r2), ("rmse", fit.rmse), ("method", fit.method),
                ("r2_complex", fit.r2_complex), ("band", fit.band_note)]
        if fit.model_choice is not None:
            rows += [("model_choice", fit.model_choice.summary()),
                     ("model_r2_complex", fit.model_choice.r2_complex),
                     ("model_delay_s", fit.model_choice.delay_s)]
        if filt.rational is not None:
            rows.append(("rational", filt.rational.describe()))
        if fit.amplitude is not None:
            rows.append(("amplitude", fit.amplitude.summary()))
        blocks.append(table_html(rows, header=("fit", "value"), wide=True))
    else:
        blocks.append(note_html(f"{label} stores no fitted transfer function (made from a "
                                "model, not a sweep): the figure shows the filter's gain only"))
    blocks.append(figure_html(
        filt.plot_transfer(),
        f"{label}: transfer function, fitted model and filter gain (Gillis 2013, Fig. 4.9)",
        "Grey points are the measured ratio load cell / sensor per frequency, the black line "
        "the fitted model, red the filter's gain: the filter multiplies each frequency by it, "
        "so it should follow the points inside the band (grey verticals) and fall back to 1 "
        "above it."))
    return blocks


def evaluation_blocks(ev, label):
    """Show the evaluation of a dynamic filter (``tactilecal dynamic evaluate``)."""
    rows = [("RMS error of the dynamic part before the filter [N]", ev.rms_before_N),
            ("RMS error after the filter [N]", ev.rms_after_N),
            ("improvement (before / after)", ev.improvement),
            ("clock", f"{ev.clock} (lag {ev.lag_s:.6g} s)"),
            ("timing error [ms]", 1e3 * ev.timing_error_s),
            ("share of the dynamic power above the band", ev.above_band_share),
            ("static factor", ev.static_factor), ("sampling rate [Hz]", ev.fs_hz)]
    if ev.rms_after_realigned_N == ev.rms_after_realigned_N:  # not NaN: asked for
        rows.append(("RMS error after, re-aligned (not what the filter delivers) [N]",
                     ev.rms_after_realigned_N))
    blocks = [table_html(rows, header=("evaluation", "value"))]
    if ev.window:
        blocks.append(figure_html(
            ev.plot_time(), f"{label}: records in a zoomed window (Gillis 2013, Figs 4.10, "
            "4.13a)", "Black is the reference, orange the sensor with its static calibration "
            "only, blue after the dynamic filter, at the evaluated clock: a good filter lays "
            "the blue line on the black one, in amplitude and in time."))
    if ev.spectra:
        blocks.append(figure_html(
            ev.plot_spectra(), f"{label}: Fourier amplitude spectra (Gillis 2013, Figs 4.11, "
            "4.13b)", "The blue spectrum should follow the black one inside the band (to the "
            "grey line); above it the sensor is left as recorded."))
    if not ev.f_hz.size:
        return blocks + [note_html(f"{label} holds no per-frequency errors, so the gain and "
                                   "phase figure is not drawn")]
    return blocks + [figure_html(
        ev.plot_error(),
        f"{label}: amplitude and phase error before and after the filter (Gillis 2013, "
        "Fig. 4.12)",
        "Each point is one coherent frequency of the blind test: orange is the sensor with "
        "its static calibration only, blue after the dynamic filter; a good filter brings "
        "the blue points to 0 % and 0 degrees across the band.")]
