"""The report's recording sections: numbers, the header's calibration, player, figures.

Each builder is a generator of HTML blocks, so that the report's progress line moves figure
by figure. Pressures are shown in one unit (``units``: the recording's own pressure unit by
default, else kPa); forces in N.
"""

import html
from types import SimpleNamespace

import numpy as np

from tactilecal._contact import CONTACT_FORCE_SHARE
from tactilecal._errors import TactilecalError
from tactilecal._text import number, share
from tactilecal._units import N_PER_MM2_TO_KPA, display_pressure
from tactilecal.report._figures import (
    figure_html,
    new_axes,
    new_map_axes,
    note_html,
    table_html,
)
from tactilecal.report._player import player_html

__all__ = ["recording_blocks", "aligned_blocks", "display_units", "header_blocks"]


def display_units(recording, units):
    """Return ``(unit, factor)``: pressures in kPa divided by ``factor`` are in ``unit``.

    ``units`` when given, else the recording's own pressure unit, else kPa.
    """
    return display_pressure(recording.attrs.get("units"), units, where="units (--units)")


def _record_table(recording):
    attrs = recording.attrs
    info = [(k, attrs[k]) for k in ("source", "sensor_type", "units", "sensel_area_mm2",
                                    "row_spacing_mm", "col_spacing_mm", "seconds_per_frame",
                                    "sensitivity", "calibration_method",
                                    "saturation_pressure_kPa") if k in attrs]
    info.insert(0, ("frames x rows x cols", " x ".join(str(n) for n in recording.shape)))
    return table_html(info, header=("property", "value"), wide=True)


def header_blocks(recording, unit, factor):
    """Yield the calibration the export's header states (I-Scan/F-Scan), as a table."""
    from tactilecal.calibration import header_calibration

    attrs = recording.attrs
    if not any(k.startswith(("calibration_point_", "scale_factor")) for k in attrs):
        return []
    try:
        cal = header_calibration(attrs)
    except TactilecalError as exc:
        return [note_html(f"the header states a calibration that cannot be read: {exc}")]
    per_count = cal.params["A"] / cal.sensel_area_mm2 * N_PER_MM2_TO_KPA / factor  # at raw 1
    b = cal.params["b"]
    rows = []
    if cal.method == "header-linear":
        mode = attrs.get("calibration_mode_1", "1-point")
        rows.append(("method", f"{mode} calibration, linear through zero (1 point)"))
    else:
        rows.append(("method", "2-point power law (SCALE_FACTOR, EXPONENT)"))
    k = 1
    while f"calibration_point_{k}_load" in attrs:
        rows.append((f"calibration point {k}",
                     f"{number(attrs[f'calibration_point_{k}_load'])} "
                     f"{attrs.get(f'calibration_point_{k}_load_unit', '')} "
                     f"({number(attrs.get(f'calibration_point_{k}_load_N'))} N), raw sum "
                     f"{number(attrs.get(f'calibration_point_{k}_raw_sum'))}, "
                     f"{number(attrs.get(f'calibration_point_{k}_loaded_cells'))} loaded "
                     "sensels"))
        k += 1
    law = f"p = {number(per_count)} {unit} x raw" + ("" if b == 1 else f"^{number(b)}")
    rows.append(("law per sensel", law))
    if "saturation_pressure_kPa" in attrs:
        rows.append(("saturation pressure (header)",
                     number(float(attrs["saturation_pressure_kPa"]) / factor, unit=unit)))
    rows.append(("pressure at raw 255 by this law", number(per_count * 255.0 ** b, unit=unit)))
    return [table_html(rows, header=("the export's own calibration (header)", "value"),
                       wide=True)]


def recording_blocks(recording, label, *, calibration=None, threshold_kPa=0.0,
                     nonworking=None, cof_min_force_N=None, units=None, regions=None,
                     gap_mm=None, player=True, key="player"):
    """Yield the key numbers, header calibration, player and figures of one recording.

    A calibrated recording (or a raw one with ``calibration``) shows force and contact area
    against time, the maps (peak pressure, the peak-force frame, the centre-of-force path
    over the peak map), the profiles, its steps when it has two or more, and its regions
    when asked; a raw recording without a calibration shows the same in raw readings.
    """
    import tactilecal.analysis  # noqa: F401 - registers recording.tactile

    if recording.attrs.get("units") == "raw" and calibration is None:
        yield _record_table(recording)
        yield from _raw_blocks(recording, label, player=player, key=key)
        return
    unit, factor = display_units(recording, units)
    first = [_record_table(recording), *header_blocks(recording, unit, factor)]
    if recording.attrs.get("units") == "raw":
        first.append(note_html(f"raw readings calibrated with method {calibration.method!r} "
                               f"({calibration.model})"))
        recording = calibration.apply(recording, units="kPa")
    yield from _calibrated_blocks(recording, label, first, SimpleNamespace(
        threshold_kPa=threshold_kPa, nonworking=nonworking, cof_min_force_N=cof_min_force_N,
        unit=unit, factor=factor, units=units, regions=regions, gap_mm=gap_mm,
        player=player, key=key))


def _numbers(head, s, threshold_kPa, cof_min_force_N, unit, factor):
    saturated = "unknown" if head["saturated_frames"] is None else head["saturated_frames"]
    bound = " (a lower bound: saturated frames)" if head["peak_force_is_lower_bound"] else ""
    rows = [
        ("duration", number(head["duration_s"], unit="s")),
        ("peak total force", number(head["peak_force_N"], unit="N") + bound),
        ("time and frame of peak force", f"{number(head['peak_force_time_s'], unit='s')}, "
                                         f"frame {head['peak_force_frame']}"),
        ("mean total force", number(head["mean_force_N"], unit="N")),
        ("largest contact area", number(head["max_contact_area_mm2"], unit="mm2")),
        ("largest sensel pressure", number(head["max_pressure_kPa"] / factor, unit=unit)
         + bound),
        ("impulse (force-time integral)", number(s.impulse_N_s, unit="N s")),
        ("loaded-sensel threshold", number(threshold_kPa / factor, unit=unit)),
        ("centre of force drawn where force is at least", number(cof_min_force_N, unit="N")),
        ("frames with saturated sensels", saturated),
    ]
    return table_html(rows, header=("quantity", "value"))


def _calibrated_blocks(recording, label, first, o):
    from tactilecal.analysis import overview

    s = recording.tactile.frame_summary(threshold_kPa=o.threshold_kPa).compute()
    head = overview(s)  # the headline numbers of rec.tactile.analyze(), from this summary
    i = int(np.nanargmax(s["force_N"].values)) if np.isfinite(s["force_N"].values).any() else 0
    peak_N = head["peak_force_N"]
    cof_min = o.cof_min_force_N if o.cof_min_force_N is not None else \
        CONTACT_FORCE_SHARE * peak_N if np.isfinite(peak_N) else 0.0
    extra = SimpleNamespace(impulse_N_s=recording.tactile.impulse())
    numbers = _numbers(head, extra, o.threshold_kPa, cof_min, o.unit, o.factor)
    yield ('<div class="tables"><div>' + "".join(first) + f"</div><div>{numbers}</div></div>")
    if head["saturated_frames"] not in (0, None):
        yield note_html(f"{head['saturated_frames']} of {s.sizes['frame']} frames hold sensels "
                        f"at saturation ({s.attrs['saturation_rule']}): their force and "
                        "pressures are lower bounds, not measurements; they are red crosses on "
                        "every map and red ticks on the force plot")
    if o.player:
        pressure = recording.tactile.pressure_map()
        yield _player_block(pressure, label, s, o.unit, o.factor, o.key)
    yield figure_html(recording.tactile.plot_force_time(summary=s, ax=new_axes((6.5, 2.8))),
                      f"{label}: total force and contact area against time",
                      "Blue is the total force (left axis), orange the area of sensels above "
                      "the threshold (right axis); the dotted line marks the peak-force frame "
                      "and red ticks, if any, frames with saturated sensels.")
    yield figure_html(_maps(recording, i, s, cof_min, o.units),
                      f"{label}: peak-pressure map, the peak-force frame and the "
                      "centre-of-force path",
                      "Left, each sensel's largest pressure over the recording with the path of "
                      "the centre of force (white); middle, the pressure at the moment of "
                      "largest total force with its centre (white cross); right, the centre of "
                      "force of every frame with enough force, coloured by time, over the peak "
                      "map in grey; all at the sensor's scale, saturated sensels as red crosses.")
    profiles = new_axes((8.0, 2.8), ncols=2)
    yield figure_html(recording.tactile.plot_profiles(position=i, nonworking=o.nonworking,
                                                      units=o.units, axes=profiles),
                      f"{label}: row and column profiles at the peak-force frame",
                      "The mean pressure of each sensel row (left, row position downwards) "
                      "and column (right) at the peak-force frame, blank and non-working "
                      "sensels left out.")
    yield from _steps_blocks(recording, label, s, o)
    if o.regions is not None:
        yield from _region_blocks(recording, label, o)


def _player_block(pressure, label, s, unit, factor, key):
    return ("<h3>Frames</h3>" + player_html(pressure, label, summary=s, units_label=unit,
                                             factor=factor, key=key)
            + '<p class="caption"><b>Frame player.</b> Move the slider (or use the arrow keys '
              "on it) to show a frame: the map is its pressure on one colour scale for the "
              "whole recording, the white dot its centre of force, red crosses saturated "
              "sensels; the red line on the force trace is the same moment.</p>")


def _maps(recording, i, s, cof_min, units):
    from tactilecal.report._figures import map_row_width

    axes = new_map_axes(recording, 3, width=map_row_width(recording, 3))
    recording.tactile.plot_pressure_map(ax=axes[0], units=units, summary=s)
    axes[0].set_title("peak over all frames", fontsize="small")
    recording.tactile.plot_pressure_map(position=i, ax=axes[1], units=units, summary=s)
    axes[1].set_title(f"frame {recording['frame'].values[i]} (peak force)", fontsize="small")
    recording.tactile.plot_cof_path(summary=s, min_force_N=cof_min, ax=axes[2], units=units)
    for ax in axes[1:]:
        ax.set_ylabel("")
    return axes


def _steps_blocks(recording, label, s, o):
    found = recording.tactile.steps(summary=s)
    if len(found) < 2:
        return
    table = found.table
    rows = [(int(r.step), "yes" if r.complete else "no (cut)",
             number(r.start_s, unit="s"), number(r.duration_s, unit="s"),
             number(r.peak_force_N, unit="N"), number(r.impulse_N_s, unit="N s"),
             number(r.loading_rate_N_s, unit="N/s"),
             number(r.peak_pressure_kPa / o.factor, unit=o.unit),
             number(r.pti_kPa_s / o.factor, unit=f"{o.unit} s"),
             number(r.cop_path_mm, unit="mm"))
            for r in table.itertuples()]
    yield f"<h3>Steps of {html.escape(label)}</h3>"
    yield table_html(rows, header=(
        "step", "complete", "start", "stance", "peak force", "impulse", "loading rate",
        "peak pressure", "PTI", "CoP path"))
    yield (f'<p class="caption">A step is a run of frames with a total force above '
           f"{number(found.threshold_N, unit='N')} (5 % of the peak); impulse and PTI (the "
           "peak pressure integrated over time) span its whole rise and fall; the loading "
           "rate is the mean slope from 20 % to 80 % of its first force peak; CoP path is the "
           "length of its centre-of-pressure path.</p>")
    yield figure_html(found.plot_paths(recording=recording,
                                       ax=new_map_axes(recording, 1,
                                                       width=_small_map_width(recording))),
                      f"{label}: centre-of-pressure path of every step",
                      f"Each line is one step's centre of pressure (a dot at its start), over "
                      f"the peak-pressure map; a step is a run of frames with a total force "
                      f"above {number(found.threshold_N, unit='N')} (5 % of the peak).")


def _small_map_width(recording, height_in=4.2):
    """Width [in] of a one-map figure about ``height_in`` tall."""
    aspect = recording.sizes["row"] * float(recording.attrs["row_spacing_mm"]) / (
        recording.sizes["col"] * float(recording.attrs["col_spacing_mm"]))
    return float(np.clip(1.3 + (height_in - 1.6) / aspect, 2.2, 7.2))


def _region_blocks(recording, label, o):
    found = recording.tactile.regions(o.regions, threshold_kPa=o.threshold_kPa,
                                      gap_mm=o.gap_mm)
    rows = [(r.region, found.regions.how[r.region], r.sensels,
             number(r.peak_force_N, unit="N"), number(r.impulse_N_s, unit="N s"),
             share(r.share_of_impulse), number(r.max_contact_area_mm2, unit="mm2"),
             number(r.peak_pressure_kPa / o.factor, unit=o.unit),
             number(r.pti_max_sensel_kPa_s / o.factor, unit=f"{o.unit} s"),
             f"{number(r.mean_cof_row_mm)}, {number(r.mean_cof_col_mm)}")
            for r in found.table.itertuples()]
    yield f"<h3>Regions of {html.escape(label)}</h3>"
    yield table_html(rows, header=(
        "region", "made by", "sensels", "peak force", "impulse", "share of the impulse",
        "largest contact area", "peak pressure", "largest pressure-time integral of a sensel",
        "mean centre of force (row, column mm)"), wide=True)
    yield figure_html(found.plot_force_time(), f"{label}: force of every region",
                      "Each line is the total force on one region against time; where the "
                      "regions cover the sensor without overlapping, the dashed line is their "
                      "sum and lies on the total force.")
    yield figure_html(found.plot_centres(recording, units=o.units),
                      f"{label}: centre of force of every region",
                      "Each region's outline and the path of its own centre of force over the "
                      "peak-pressure map (grey): one centre per compartment or foot, instead of "
                      "one for the whole sensor that may lie between them.")


def _raw_summary(recording):
    """Per-frame raw sum, loaded area (raw > 0) and raw-weighted centre of a raw recording."""
    import xarray as xr

    raw = recording.fillna(0.0).astype(float)
    total = raw.sum(("row", "col"))
    weight = total.where(total > 0)
    rows = xr.DataArray(np.arange(raw.sizes["row"]) * float(recording.attrs.get(
        "row_spacing_mm", 1.0)), dims="row")
    cols = xr.DataArray(np.arange(raw.sizes["col"]) * float(recording.attrs.get(
        "col_spacing_mm", 1.0)), dims="col")
    ds = xr.Dataset({"force_N": total, "area_mm2": recording.tactile.area(),
                     "cof_row_mm": (raw * rows).sum(("row", "col")) / weight,
                     "cof_col_mm": (raw * cols).sum(("row", "col")) / weight})
    return ds.compute()


def _raw_blocks(recording, label, *, player, key):
    s = _raw_summary(recording)
    raw_sum = np.asarray(s["force_N"].values, float)
    i = int(np.nanargmax(raw_sum)) if np.isfinite(raw_sum).any() else 0
    t = np.asarray(s["time"].values if "time" in s.coords else np.arange(raw_sum.size), float)
    saturated = int((recording >= 255).any(("row", "col")).sum())
    yield note_html(f"{label} holds raw readings and no calibration was given, so forces and "
                    "pressures are not shown: the figures are in raw readings, which rise with "
                    "pressure but not in proportion. Pass a calibration JSON (--cal) for kPa "
                    "and N.")
    yield table_html([("duration", number(float(t[-1] - t[0]), unit="s")),
                      ("largest sum of raw readings", number(float(raw_sum[i]))),
                      ("frame of the largest sum", recording["frame"].values[i]),
                      ("largest loaded area (raw > 0)",
                       number(float(np.nanmax(s["area_mm2"].values)), unit="mm2")),
                      ("frames with saturated sensels (255)", saturated)],
                     header=("quantity", "value"))
    if player:
        yield "<h3>Frames</h3>" + player_html(recording, label, summary=s,
                                               units_label="raw reading", factor=1.0, key=key)
    yield figure_html(_draw_raw_time(t, raw_sum, s["area_mm2"].values),
                      f"{label}: sum of raw readings and loaded area against time",
                      "Blue is the sum of all raw readings of a frame (a stand-in for load that "
                      "is not proportional to it), orange the area of sensels reading above 0.")
    yield figure_html(recording.tactile.plot_pressure_map(summary=s), f"{label}: peak raw map",
                      "Each sensel's largest raw reading over the recording (255 is saturation, "
                      "a red cross), and the path of the raw-weighted centre (white): where the "
                      "contact carried load at any time.")


def _draw_raw_time(t, raw_sum, area):
    ax = new_axes((6.5, 3.2))
    ax.plot(t, raw_sum, color="C0")
    ax.set(xlabel="time [s]")
    ax.set_ylabel("sum of raw readings", color="C0")
    twin = ax.twinx()
    twin.plot(t, area, color="C1", lw=1, alpha=0.8)
    twin.set_ylabel("loaded area [mm2]", color="C1")
    return ax


def aligned_blocks(recordings, *, how="time"):
    """Several calibrated recordings on one time axis: force traces, stances, all steps.

    ``recordings`` is a list of ``(label, recording)``; ``how`` as
    :func:`tactilecal.analysis.align_recordings`.
    """
    from tactilecal.analysis import align_recordings

    labels = [label for label, _ in recordings]
    aligned = align_recordings([rec for _, rec in recordings], how=how)
    ax = new_axes((7.5, 3.6))
    rows = []
    for k, (label, rec) in enumerate(zip(labels, aligned, strict=True)):
        s = rec.tactile.frame_summary().compute()
        t = np.asarray(s["time"].values, float)
        ax.plot(t, s["force_N"].values, lw=1.2, color=f"C{k}", label=label)
        found = rec.tactile.steps(summary=s)
        for r in found.table.itertuples():
            ax.plot([r.start_s, r.end_s], [-0.04 - 0.04 * k] * 2, color=f"C{k}", lw=4,
                    transform=ax.get_xaxis_transform(), clip_on=False, solid_capstyle="butt")
            rows.append((r.start_s, label, int(r.step), number(r.start_s, unit="s"),
                         number(r.end_s, unit="s"), number(r.duration_s, unit="s"),
                         number(r.peak_force_N, unit="N"), number(r.impulse_N_s, unit="N s")))
    ax.set(xlabel="time [s]" + ("" if how == "time" else f" (aligned: {how})"),
           ylabel="total force [N]")
    ax.legend(fontsize="small", frameon=False)
    shifts = ", ".join(f"{label} {number(rec.attrs['time_shift_s'], unit='s')}"
                       for label, rec in zip(labels, aligned, strict=True))
    return ["<h2>Recordings on one time axis</h2>",
            figure_html(ax, "Total force of every recording on one time axis",
                        f"Each line is one recording's total force (time shifts: {shifts}); "
                        "the bars under the axis are the stance phases (steps) of each, so "
                        "that alternating feet and their double support show as overlaps."),
            table_html([row[1:] for row in sorted(rows)], header=(
                "recording", "step", "start", "end", "stance", "peak force", "impulse"))]
