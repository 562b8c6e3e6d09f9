"""``tactilecal report INPUT... --out report.html``: one self-contained HTML page."""


from tactilecal.cli._common import info, progress_for
from tactilecal.cli._outputs import add_output
from tactilecal.cli._types import non_negative_float


def register(subparsers):
    """Add the ``report`` command."""
    p = subparsers.add_parser(
        "report", help="write a self-contained HTML report",
        description="One HTML page with embedded figures for calibration JSONs (a method "
                    "comparison when there are several; curve, points, error histogram, "
                    "Zvyagin figures), validation JSONs (held-out errors), FILTER.json files "
                    "(transfer function), blind-test JSONs (error before and after) and "
                    "recordings (force and area against time, peak-pressure map, "
                    "centre-of-force path, profiles), and a provenance section.")
    p.add_argument("inputs", nargs="+", metavar="INPUT",
                   help="calibration or validation JSON, FILTER.json, blind-test JSON, "
                        "Tekscan export or NetCDF recording")
    add_output(p, "--out", kind="html", required=True, metavar="report.html",
               help="output HTML file")
    p.add_argument("--cal", metavar="CAL.json", help="calibration for raw recordings")
    p.add_argument("--filter", metavar="FILTER.json", help="dynamic filter to report")
    p.add_argument("--title", help="page title")
    p.add_argument("--threshold-kpa", type=non_negative_float, default=0.0, metavar="KPA",
                   help="loaded-sensel threshold for contact areas (default 0)")
    p.add_argument("--cof-min-force-n", type=non_negative_float, metavar="N",
                   help="draw the centre-of-force path only where the total force is at "
                        "least N newtons (default 5%% of the peak force)")
    p.set_defaults(func=run)


def run(args):
    """Build the report and write it atomically."""
    from tactilecal.report import write_report

    path = write_report(args.inputs, args.out, calibration=args.cal, filter=args.filter,
                        title=args.title, threshold_kPa=args.threshold_kpa,
                        cof_min_force_N=args.cof_min_force_n,
                        command=args.command_line,
                        progress=progress_for(args), overwrite=args.overwrite)
    info(args, f"report written to {path}")
    return 0
