"""``tactilecal info FILE [--json]``: what a Tekscan export holds, at a glance."""

from tactilecal.cli._common import print_json


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

    summary = read_tekscan(args.file).tactile.describe()
    if args.json:
        print_json(summary)
    else:
        print(_text(summary))
    return 0
