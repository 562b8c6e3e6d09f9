"""``tactilecal info FILE [--json]``: what a recording holds, at a glance."""

from tactilecal._text import number
from tactilecal.cli._common import print_json


def register(subparsers):
    """Add the ``info`` command."""
    p = subparsers.add_parser(
        "info", help="summarise a recording (Tekscan export, NetCDF, Zarr)",
        description="Sensor, size, frames, duration, units, calibration header, blank "
                    "(all-B) and never-loaded sensels, largest value (with its unit, and as "
                    "a raw reading through the header's calibration) and frames with "
                    "saturated sensels of a recording: a Tekscan I-Scan/F-Scan ASCII export, "
                    "a NetCDF file or a Zarr store.")
    p.add_argument("file", help="Tekscan ASCII export (.csv, .asf, ...), .nc or .zarr")
    p.add_argument("--json", action="store_true", help="print the summary as JSON")
    p.set_defaults(func=run)


def _text(summary):
    lines = []
    for key, value in summary.items():
        if key == "calibration":
            lines.append("calibration: " + ("none in header" if not value else ""))
            lines.extend(f"  {k}: {number(v)}" for k, v in value.items())
        elif key == "saturated_frame_numbers" and value is not None:
            shown = ", ".join(map(str, value[:20])) + (" ..." if len(value) > 20 else "")
            lines.append(f"{key}: {shown or 'none'}")
        elif key == "max_value" and value is not None:
            lines.append(f"{key}: {number(value)} {summary.get('units') or ''}".rstrip())
        elif value is not None:
            lines.append(f"{key}: {number(value)}")
    return "\n".join(lines)


def run(args):
    """Read the file and print its summary (text or JSON); return 0."""
    from tactilecal.io import open_recording, recording_format

    try:
        known = recording_format(args.file) is not None
    except (OSError, ValueError):
        known = False
    if known:
        recording = open_recording(args.file)
    else:  # a JSON result or another file: say what it is (the report's reader knows)
        from tactilecal.cli._inputs import load_recording

        recording = load_recording(args.file, what="FILE")
    summary = recording.tactile.describe()
    if args.json:
        print_json(summary)
    else:
        print(_text(summary))
    return 0
