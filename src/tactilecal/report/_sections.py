"""The sections of a report: methods compared, calibration, filter, blind test, recording.

Each builder returns a list of HTML blocks. Every figure says under it what it shows and
how to read it. What a section cannot show is decided from its input before anything is
drawn (a raw recording without a calibration, a filter file without its fit) and said in a
note; a figure that fails to draw for any other reason is a bug and raises.
"""

import html
import json
from types import SimpleNamespace

import numpy as np

from tactilecal._jsonutil import to_jsonable
from tactilecal._text import number, share
from tactilecal._units import N_PER_MM2_TO_KPA
from tactilecal.report._figures import (
    figure_html,
    new_axes,
    note_html,
    table_html,
)

__all__ = ["comparison_blocks", "calibration_blocks", "filter_blocks", "evaluation_blocks",
           "recording_blocks"]

#: Share of the peak force (or raw sum) below which the centre-of-force path is not drawn.
COF_MIN_FORCE_SHARE = 0.05


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
        each is matched to the calibration of its ``calibration_method`` when exactly one
        calibration has that method.
    """
    by_method = {}
    for position, (_, result) in enumerate(calibrations):
        by_method.setdefault(result.method, []).append(position)
    held_out = {}
    for _, check in validations:
        positions = by_method.get(check.metrics.get("calibration_method"), ())
        if len(positions) == 1:
            held_out[positions[0]] = check.metrics
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
    """Summary, parameters, points table and figures of one calibration result."""
    metrics = [(k, share(v) if k.startswith("within_") else number(v))
               for k, v in result.metrics.items()]
    blocks = [
        f"<pre>{html.escape(result.summary())}</pre>",
        table_html(metrics, header=("metric", "value")),
        table_html(_record_rows(result), header=("calibration record", "value"), wide=True),
        figure_html(result.plot_curve(ax=new_axes()),
                    f"{label}: calibration curve",
                    "The line is the fitted law; each point is one calibration patch's "
                    "applied load per loaded sensel at its mean raw reading; open points "
                    "were not used (saturated or rejected)."),
        figure_html(result.plot_points(ax=new_axes()),
                    f"{label}: calibrated against applied load",
                    "Each point is a calibration patch; on the diagonal the calibrated load "
                    "equals the applied one, and the vertical distance is its error."),
        figure_html(result.plot_error_histogram(ax=new_axes()),
                    f"{label}: error histogram",
                    "How many patches the calibration misses by how much, in percent of the "
                    "applied load; a narrow peak at 0 is a good calibration."),
    ]
    blocks[1:1] = _choice_blocks(result, label)
    if result.method_result is not None:
        blocks += _zvyagin_blocks(result.method_result, label)
    return blocks


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


def _record_rows(result):
    """Return the record rows: created, version, options, sensor, inputs with their hashes."""
    prov = result.provenance
    rows = [("created", result.created), ("tactilecal version", result.version),
            ("options", json.dumps(to_jsonable(result.options)))]
    if prov:
        rows.append(("sensor type, serial (export header)",
                     f"{prov.get('sensor_type') or 'unknown'}, "
                     f"{prov.get('sensor_serial') or 'unknown'}"))
        rows += [(f"input {k + 1}", f"{entry['path']} (SHA-256 {entry['sha256']})")
                 for k, entry in enumerate(prov.get("inputs", []))]
    return rows


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
    ("plot_energy", "energy along the power-law curve (eq. 15)",
     "E against the exponent b0 along the fitted A(b) curve; the minimum is the chosen b0, "
     "and a flat valley means b0 is poorly determined."),
)


def _zvyagin_blocks(zvyagin, label):
    """Return the paper's figures of a Zvyagin calibration (its ``method_result``)."""
    return [figure_html(getattr(zvyagin, name)(), f"{label}: Zvyagin (2022) {title}", how)
            for name, title, how in _ZVYAGIN_FIGURES]


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
        "Each point is one coherent frequency of the test: orange is the sensor with its "
        "static calibration only, blue after the dynamic filter; a good filter brings the "
        "blue points to 0 % and 0 degrees across the band.")]


# ---------------------------------------------------------------- recording
def _record_table(recording):
    attrs = recording.attrs
    info = [(k, attrs[k]) for k in ("source", "sensor_type", "units", "sensel_area_mm2",
                                    "row_spacing_mm", "col_spacing_mm", "seconds_per_frame",
                                    "sensitivity", "calibration_method",
                                    "saturation_pressure_kPa") if k in attrs]
    info.insert(0, ("frames x rows x cols", " x ".join(str(n) for n in recording.shape)))
    return table_html(info, header=("property", "value"), wide=True)


def recording_blocks(recording, label, *, calibration=None, threshold_kPa=0.0,
                     nonworking=None, cof_min_force_N=None):
    """Key numbers and figures of one recording.

    A calibrated recording (or a raw one with ``calibration``) shows force and contact
    area against time, the peak-pressure map, the pressure map and the profiles at the
    peak-force frame and the centre-of-force path where the force is at least
    ``cof_min_force_N`` (default 5 % of the peak force). A raw recording without a
    calibration shows the same in raw readings.
    """
    blocks = [_record_table(recording)]
    if recording.attrs.get("units") == "raw" and calibration is None:
        return blocks + _raw_blocks(recording, label, cof_min_share=COF_MIN_FORCE_SHARE)
    if recording.attrs.get("units") == "raw":
        recording = calibration.apply(recording, units="kPa")
        blocks.append(note_html(f"raw readings calibrated with method "
                                f"{calibration.method!r} ({calibration.model})"))
    return blocks + _calibrated_blocks(recording, label, threshold_kPa, nonworking,
                                       cof_min_force_N)


def _calibrated_blocks(recording, label, threshold_kPa, nonworking, cof_min_force_N):
    from tactilecal import analysis

    s = recording.tactile.frame_summary(threshold_kPa=threshold_kPa).compute()
    head = analysis.overview(s)
    i = analysis.peak_frame(s)
    if cof_min_force_N is None:
        peak_N = head["peak_force_N"]
        cof_min_force_N = COF_MIN_FORCE_SHARE * peak_N if np.isfinite(peak_N) else 0.0
    saturated = "unknown" if head["saturated_frames"] is None else head["saturated_frames"]
    numbers = [
        ("duration [s]", head["duration_s"]),
        ("peak total force [N]", head["peak_force_N"]),
        ("time of peak force [s]", head["peak_force_time_s"]),
        ("frame of peak force", head["peak_force_frame"]),
        ("largest contact area [mm2]", head["max_contact_area_mm2"]),
        ("largest sensel pressure [kPa]", head["max_pressure_kPa"]),
        ("loaded-sensel threshold [kPa]", float(threshold_kPa)),
        ("centre of force drawn where force >= [N]", float(cof_min_force_N)),
        ("frames with saturated sensels", saturated),
    ]
    blocks = [table_html(numbers, header=("quantity", "value"))]
    if saturated not in (0, "unknown"):
        blocks.append(note_html(f"{saturated} of {s.sizes['frame']} frames hold sensels at "
                                f"saturation ({s.attrs['saturation_rule']}): their force "
                                "and pressures are lower bounds, not measurements"))
    return blocks + [
        figure_html(recording.tactile.plot_force_time(summary=s),
                    f"{label}: total force and contact area against time",
                    "Blue is the total force (left axis), orange the area of sensels above "
                    "the threshold (right axis); the dotted line marks the peak-force frame."),
        figure_html(recording.tactile.plot_pressure_map(), f"{label}: peak-pressure map",
                    "Each sensel's largest pressure over the whole recording: where the "
                    "contact carried load at any time, and how much at most."),
        figure_html(recording.tactile.plot_pressure_map(frame=i),
                    f"{label}: pressure map at the peak-force frame",
                    "The pressure on every sensel at the moment of largest total force; "
                    "blank cells are sensels without a reading."),
        figure_html(recording.tactile.plot_cof_path(summary=s,
                                                    min_force_N=cof_min_force_N),
                    f"{label}: centre-of-force path",
                    "The force-weighted centre of the contact, coloured by time; frames "
                    "with less force than the threshold in the title are left out, because "
                    "with almost no load the centre is the mean of noise."),
        figure_html(recording.tactile.plot_profiles(frame=i, nonworking=nonworking),
                    f"{label}: row and column profiles at the peak-force frame",
                    "The mean pressure of each sensel row (left, row position downwards) "
                    "and column (right) at the peak-force frame, blank and non-working "
                    "sensels left out."),
    ]


def _raw_summary(recording):
    """Per-frame raw sum, loaded area (raw > 0) and raw-weighted centre of a raw recording."""
    raw = recording.fillna(0.0).astype(float)
    total = raw.sum(("row", "col"))
    weight = total.where(total > 0)
    rows = np.arange(raw.sizes["row"]) * float(recording.attrs.get("row_spacing_mm", 1.0))
    cols = np.arange(raw.sizes["col"]) * float(recording.attrs.get("col_spacing_mm", 1.0))
    return SimpleNamespace(
        time_s=np.asarray(recording["time"].values if "time" in recording.coords
                          else np.arange(recording.sizes["frame"]), float),
        raw_sum=np.asarray(total.values, float),
        area_mm2=np.asarray(recording.tactile.area().values, float),
        row_mm=np.asarray((raw.dot(_coord(rows, "row")).sum("col") / weight).values, float),
        col_mm=np.asarray((raw.dot(_coord(cols, "col")).sum("row") / weight).values, float))


def _coord(values, dim):
    import xarray as xr

    return xr.DataArray(np.asarray(values, float), dims=dim)


def _raw_blocks(recording, label, *, cof_min_share):

    s = _raw_summary(recording)
    i = int(np.nanargmax(s.raw_sum)) if np.isfinite(s.raw_sum).any() else 0
    min_sum = cof_min_share * float(np.nanmax(s.raw_sum)) if s.raw_sum.size else 0.0
    saturated = int((recording >= 255).any(("row", "col")).sum())
    numbers = [("duration [s]", float(s.time_s[-1] - s.time_s[0])),
               ("largest sum of raw readings", float(s.raw_sum[i])),
               ("frame of the largest sum", recording["frame"].values[i]),
               ("largest loaded area (raw > 0) [mm2]", float(np.nanmax(s.area_mm2))),
               ("frames with saturated sensels (255)", saturated)]
    return [
        note_html(f"{label} holds raw readings and no calibration was given, so forces and "
                  "pressures are not shown: the figures are in raw readings, which rise with "
                  "pressure but not in proportion. Pass a calibration JSON (--cal) for kPa "
                  "and N."),
        table_html(numbers, header=("quantity", "value")),
        figure_html(_draw_raw_time(s), f"{label}: sum of raw readings and loaded area "
                    "against time",
                    "Blue is the sum of all raw readings of a frame (a stand-in for load that "
                    "is not proportional to it), orange the area of sensels reading above 0."),
        figure_html(recording.tactile.plot_pressure_map(), f"{label}: peak raw map",
                    "Each sensel's largest raw reading over the recording (255 is "
                    "saturation): where the contact carried load at any time."),
        figure_html(_draw_raw_centre(s, min_sum), f"{label}: centre of the raw readings",
                    "The raw-weighted centre of each frame, coloured by time, drawn where the "
                    "raw sum is at least 5 % of its peak; with a nonlinear sensor law it is "
                    "near, but not equal to, the centre of force."),
    ]


def _draw_raw_time(s):
    ax = new_axes()
    ax.plot(s.time_s, s.raw_sum, color="C0")
    ax.set(xlabel="time [s]")
    ax.set_ylabel("sum of raw readings", color="C0")
    twin = ax.twinx()
    twin.plot(s.time_s, s.area_mm2, color="C1", lw=1, alpha=0.8)
    twin.set_ylabel("loaded area [mm2]", color="C1")
    return ax


def _draw_raw_centre(s, min_sum):
    ax = new_axes((5, 5))
    keep = s.raw_sum >= min_sum
    x, y = np.where(keep, s.col_mm, np.nan), np.where(keep, s.row_mm, np.nan)
    ax.plot(x, y, color="0.7", lw=0.8)
    points = ax.scatter(x, y, c=s.time_s, s=10, cmap="plasma")
    ax.figure.colorbar(points, ax=ax, label="time [s]")
    ax.set(xlabel="column [mm]", ylabel="row [mm]",
           title=f"{int(np.sum(keep & np.isfinite(x)))} of {keep.size} frames")
    ax.invert_yaxis()
    ax.set_aspect("equal", adjustable="datalim")
    return ax
