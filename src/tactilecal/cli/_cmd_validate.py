"""``tactilecal validate``: compare a calibration's loads with a manifest's applied loads."""

from tactilecal.cli._common import print_json, progress_for


def register(subparsers):
    """Add the ``validate`` command."""
    p = subparsers.add_parser(
        "validate", help="validate a calibration on (held-out) manifest points",
        description="Predict the load of every point of MANIFEST with CAL.json and compare "
                    "it with the applied load. Points with saturated sensels are listed and "
                    "left out of the summary unless --include-saturated.")
    p.add_argument("calibration", metavar="CAL.json")
    p.add_argument("manifest", metavar="MANIFEST")
    p.add_argument("--include-saturated", action="store_true",
                   help="count points with saturated sensels in the summary")
    p.add_argument("--json", action="store_true",
                   help="print the Validate JSON (points and summary)")
    p.set_defaults(func=run)


def run(args):
    """Run ``tactilecal validate``."""
    from tactilecal.calibration import CalibrationResult, validate

    # the manifest's frames get the calibration's equilibration gains, as for the fit
    out = validate(CalibrationResult.from_json(args.calibration), args.manifest,
                   progress=progress_for(args),
                   include_saturated=args.include_saturated)
    if args.json:
        print_json(out.to_dict())
    else:
        print(out.summary())
    return 0
