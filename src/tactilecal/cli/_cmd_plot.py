"""``tactilecal plot CAL.json --out DIR``: the figures of a calibration as PNG files."""

from tactilecal._atomic import make_folder
from tactilecal.cli._common import info, print_json
from tactilecal.cli._outputs import add_output
from tactilecal.cli._types import positive_int


def register(subparsers):
    """Add the ``plot`` command."""
    p = subparsers.add_parser(
        "plot", help="draw the figures of a calibration JSON as PNG files",
        description="Write the figures of CAL.json into DIR. A Zvyagin calibration gives "
                    "Zvyagin (2022) Figures 7-11 (d map at I1*, pair chart, (A, b) scatter "
                    "with the power law and T1/T2, calibration and terminal curves, error "
                    "histogram) and E(b0); any other method the calibration curve, predicted "
                    "vs applied loads and the error histogram.")
    p.add_argument("calibration", metavar="CAL.json")
    add_output(p, "--out", kind="figures", metavar="DIR", required=True,
               help="folder for the PNG files (created if missing)")
    p.add_argument("--dpi", type=positive_int, default=120, help="resolution (default 120)")
    p.add_argument("--json", action="store_true", help="print the written paths as JSON")
    p.set_defaults(func=run)


def run(args):
    """Run ``tactilecal plot``."""
    from tactilecal.calibration import CalibrationResult

    result = CalibrationResult.from_json(args.calibration)
    outdir = make_folder(args.out, what="--out")
    paths = result.save_figures(outdir, dpi=args.dpi)
    if args.json:
        print_json({"calibration": str(args.calibration), "method": result.method,
                    "figures": [str(p) for p in paths]})
    else:
        for p in paths:
            print(p)
    info(args, f"{len(paths)} figures of {result.method!r} written to {outdir}")
    return 0
