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


def _table(out):
    lines = [f"{'file':<28} {'frame':>6} {'load_N':>10} {'predicted_N':>12} {'error_%':>8}"]
    for p in out.points:
        flag = "  saturated" if p["saturated"] else ""
        lines.append(f"{str(p['file'])[:28]:<28} {p['frame']:>6} {p['load_N']:>10.4g} "
                     f"{p['predicted_N']:>12.4g} {p['error_pct']:>8.2f}{flag}")
    s = out.metrics
    lines.append(f"n = {s['n']} (saturated left out: {s['n_saturated_excluded']}): "
                 f"{s['within_5pct']:.1%} within 5 %, {s['within_10pct']:.1%} within 10 %, "
                 f"median |error| {s['median_abs_error_pct']:.2f} %, "
                 f"max {s['max_abs_error_pct']:.2f} %")
    return "\n".join(lines)


def run(args):
    """Run ``tactilecal validate``."""
    from tactilecal.calibration import load_calibration, validate

    # the manifest's frames get the calibration's equilibration gains, as for the fit
    out = validate(load_calibration(args.calibration), args.manifest,
                   progress=progress_for(args),
                   include_saturated=args.include_saturated)
    if args.json:
        print_json(out.to_dict())
    else:
        print(_table(out))
    return 0
