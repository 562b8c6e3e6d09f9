"""``tactilecal info FILE [--json]``: what a Tekscan export holds, at a glance."""

import numpy as np

from tactilecal.cli._common import print_json

_CALIBRATION_PREFIXES = ("calibration_point_", "calibration_mode_", "saturation_pressure",
                         "scale_factor", "exponent")


def register(subparsers):
    """Add the ``info`` command."""
    p = subparsers.add_parser(
        "info", help="summarise a Tekscan ASCII export",
        description="Sensor, size, frames, duration, units, calibration header, blank "
                    "(all-B) and never-loaded sensels, maximum reading and frames with "
                    "saturated sensels of a Tekscan I-Scan/F-Scan ASCII export.")
    p.add_argument("file", help="Tekscan ASCII export (.csv, .asf, ...)")
    p.add_argument("--json", action="store_true", help="print the summary as JSON")
    p.set_defaults(func=run)


def summarise(data):
    """Return the ``info`` summary of a recording as a JSON-ready dict.

    Parameters
    ----------
    data : xarray.DataArray
        A recording as returned by :func:`tactilecal.io.read_tekscan`.

    Returns
    -------
    dict
        Keys ``file, sensor_type, catalogue_sensor, catalogue_match, rows, cols, sensels, frames,
        first_frame, last_frame, duration_s, seconds_per_frame, units, row_spacing_mm,
        col_spacing_mm, sensel_area_mm2, sensitivity, noise_threshold, calibration,
        blank_sensels, never_loaded_sensels, max_value, max_raw, max_raw_source,
        saturation_rule, saturated_frames, saturated_frame_numbers``.

    Notes
    -----
    For calibrated files ``max_raw`` is the largest value turned back into raw units through
    the header's calibration where it can be inverted: ``SCALE_FACTOR``/``EXPONENT``
    (p = SCALE_FACTOR x raw^EXPONENT) or a single ``CALIBRATION_POINT_1`` (linear through
    zero, p = load_N / (raw_sum x sensel_area_mm2) per raw count); else None.
    """
    from tactilecal.analysis import saturated_sensels
    from tactilecal.sensors import match_sensor

    attrs, values = data.attrs, data.values
    blank = np.isnan(values).all(axis=0)
    never_loaded = ~blank & ~(np.nan_to_num(values, nan=0.0) > 0).any(axis=0)
    times = data.time.values
    counts, rule = saturated_sensels(data)
    saturated = None if counts is None else counts.values > 0
    match = match_sensor(attrs.get("sensor_type"), rows=data.sizes["row"], cols=data.sizes["col"],
                         row_spacing_mm=attrs.get("row_spacing_mm"),
                         col_spacing_mm=attrs.get("col_spacing_mm"))
    finite = values[np.isfinite(values)]
    max_value = float(finite.max()) if finite.size else None
    return {
        "file": attrs.get("source"), "sensor_type": attrs.get("sensor_type"),
        "catalogue_sensor": None if match.entry is None else match.entry.name,
        "catalogue_match": match.how,
        "rows": data.sizes["row"], "cols": data.sizes["col"],
        "sensels": data.sizes["row"] * data.sizes["col"], "frames": data.sizes["frame"],
        "first_frame": int(data.frame[0]) if data.sizes["frame"] else None,
        "last_frame": int(data.frame[-1]) if data.sizes["frame"] else None,
        "duration_s": float(times[-1] - times[0]) if times.size else None,
        **{key: attrs.get(key) for key in (
            "seconds_per_frame", "units", "row_spacing_mm", "col_spacing_mm",
            "sensel_area_mm2", "sensitivity", "noise_threshold")},
        "calibration": {k: v for k, v in attrs.items() if k.startswith(_CALIBRATION_PREFIXES)},
        "blank_sensels": int(blank.sum()), "never_loaded_sensels": int(never_loaded.sum()),
        "max_value": max_value,
        **_max_raw(max_value, attrs),
        "saturation_rule": rule,
        "saturated_frames": None if saturated is None else int(saturated.sum()),
        "saturated_frame_numbers": (None if saturated is None
                                    else data.frame.values[saturated].tolist()),
    }


def _max_raw(max_value, attrs):
    units = attrs.get("units")
    if max_value is None or units == "raw":
        return {"max_raw": max_value, "max_raw_source": "file" if max_value is not None else None}
    if units not in ("kPa", "MPa", "Pa", "psi"):
        return {"max_raw": None, "max_raw_source": None}
    from tactilecal._units import pressure_to_kPa

    p_kPa = pressure_to_kPa(max_value, units)
    if "scale_factor" in attrs and "exponent" in attrs:
        raw = (p_kPa / pressure_to_kPa(attrs["scale_factor"], units)) ** (1 / attrs["exponent"])
        return {"max_raw": float(raw), "max_raw_source": "inverted SCALE_FACTOR x raw^EXPONENT"}
    points = {k for k in attrs if k.startswith("calibration_point_") and k.endswith("_raw_sum")}
    if points == {"calibration_point_1_raw_sum"} and "calibration_point_1_load_N" in attrs \
            and "sensel_area_mm2" in attrs:
        kPa_per_raw = (attrs["calibration_point_1_load_N"] * 1000.0
                       / (attrs["calibration_point_1_raw_sum"] * attrs["sensel_area_mm2"]))
        return {"max_raw": p_kPa / kPa_per_raw,
                "max_raw_source": "inverted 1-point linear calibration (CALIBRATION_POINT_1)"}
    return {"max_raw": None, "max_raw_source": None}


def _text(summary):
    lines = []
    for key, value in summary.items():
        if key == "calibration":
            lines.append("calibration: " + ("none in header" if not value else ""))
            lines.extend(f"  {k}: {v}" for k, v in value.items())
        elif key == "saturated_frame_numbers" and value is not None:
            shown = ", ".join(map(str, value[:20])) + (" ..." if len(value) > 20 else "")
            shown = shown or "none"
            lines.append(f"{key}: {shown}")
        elif value is not None:
            lines.append(f"{key}: {value:.6g}" if isinstance(value, float) else f"{key}: {value}")
    return "\n".join(lines)


def run(args):
    """Read the file and print its summary (text or JSON); return 0."""
    from tactilecal.io import read_tekscan

    summary = summarise(read_tekscan(args.file))
    if args.json:
        print_json(summary)
    else:
        print(_text(summary))
    return 0
