"""``tactilecal report INPUT... --out report.html``: one self-contained HTML page."""

from tactilecal import _contact
from tactilecal.cli._common import info, progress_for
from tactilecal.cli._inputs import add_region_options, gap_mm, regions
from tactilecal.cli._library_options import add_option
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
                    "recordings (the export's own calibration, a frame player, force and area "
                    "against time, the maps with the centre of force, profiles, steps; "
                    "several recordings also on one time axis), and a provenance section. It "
                    "prints to paper as it shows on screen.")
    p.add_argument("inputs", nargs="+", metavar="INPUT",
                   help="calibration or validation JSON, FILTER.json, blind-test JSON, "
                        "Tekscan export or NetCDF recording")
    add_output(p, "--out", kind="html", required=True, metavar="report.html",
               help="output HTML file")
    p.add_argument("--cal", metavar="CAL.json", help="calibration for raw recordings")
    p.add_argument("--filter", metavar="FILTER.json", help="dynamic filter to report")
    p.add_argument("--title", help="page title")
    p.add_argument("--units", help="pressure unit of the recordings: kPa, MPa, psi... "
                                   "(default each recording's own)")
    p.add_argument("--cof-min-force-n", type=non_negative_float, metavar="N",
                   help="draw the centre-of-force path only where the total force is at "
                        "least N newtons (default "
                        f"{100 * _contact.CONTACT_FORCE_SHARE:g}%% of the peak force)")
    add_region_options(p)
    p.add_argument("--no-player", action="store_true",
                   help="leave out the frame players (a smaller page)")
    p.defer(_add_options)  # defaults read from the library: imported when used
    p.set_defaults(func=run)


def _add_options(p):
    from tactilecal.report import write_report

    add_option(p, "--threshold-kpa", write_report, "threshold_kPa",
               "loaded-sensel threshold for contact areas", type=non_negative_float,
               metavar="KPA")
    add_option(p, "--align", write_report, "align",
               "several recordings on one time axis: 'time' (by their own times, one "
               "session's clock), 'start' (their first frames at 0) or 'onset' (their first "
               "loading at 0)", metavar="HOW")


def run(args):
    """Build the report and write it atomically."""
    from tactilecal.report import write_report

    path = write_report(args.inputs, args.out, calibration=args.cal, filter=args.filter,
                        title=args.title, threshold_kPa=args.threshold_kPa,
                        cof_min_force_N=args.cof_min_force_n, command=args.command_line,
                        progress=progress_for(args), units=args.units, regions=regions(args),
                        gap_mm=gap_mm(args), align=args.align, player=not args.no_player,
                        overwrite=args.overwrite)
    info(args, f"report written to {path}")
    return 0
