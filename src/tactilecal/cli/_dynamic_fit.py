"""``tactilecal dynamic fit``: fit a correction filter on a sine sweep (FILTER.json out)."""

import sys

from tactilecal.cli._common import info, print_json
from tactilecal.cli._outputs import add_output


def register(sub):
    """Add the ``fit`` action to the ``dynamic`` command's actions."""
    f = sub.add_parser("fit", help="fit a filter on a sweep (FILTER.json out)",
                       description="SENSOR and REFERENCE are time-series CSVs (time, value); "
                                   "SENSOR may also be a Tekscan recording or NetCDF, whose "
                                   "frames are summed. Records may have different rates "
                                   "and start times: they are aligned first.")
    f.add_argument("sensor", metavar="SENSOR")
    f.add_argument("reference", metavar="REFERENCE")
    add_output(f, "--out", kind="json", required=True, metavar="FILTER.json")
    f.add_argument("--json", action="store_true", help="print the result as JSON")
    f.add_argument("--model", default="auto",
                   choices=["auto", "log", "log10", "log-quadratic", "rational", "wiener"],
                   help="auto (default): of log, rational and wiener, the simplest that "
                        "predicts held-out bins within 10 %% of the best or to 1 %%; log: "
                        "natural log (MATLAB's log); log10: decimal log; log-quadratic: Y = A "
                        "L + B L^2 + 1, L = ln(f + 1); rational: the complex response's poles "
                        "and zeros (orders 1-4), undone with their phase; wiener: the measured "
                        "complex correction, shrunk where it is within its random error")
    f.add_argument("--band", nargs=2, type=float, metavar=("LO", "HI"),
                   help="fit only LO..HI Hz; also the calibrated band (default: the "
                        "coherent bins)")
    f.add_argument("--method", default="h2", choices=["h2", "h1", "ratio"],
                   help="transfer-function estimator (default h2)")
    f.add_argument("--outside", default="taper", choices=["taper", "hold"],
                   help="gain above the band: taper to 1 (default) or hold")
    f.add_argument("--force", action="store_true",
                   help="write the filter even when the model explains less than 90 %% of "
                        "the complex response (marked forced in FILTER.json)")
    f.set_defaults(func=run)


def run(args):
    """Run ``tactilecal dynamic fit``."""
    from tactilecal.dynamic import fit_filter, read_record

    sensor, reference = read_record(args.sensor), read_record(args.reference)
    filt = fit_filter(sensor, reference, model=args.model, band_hz=args.band,
                      method=args.method, outside=args.outside, force=args.force)
    if filt.forced:
        print(f"warning: written with --force: {filt.forced}", file=sys.stderr)
    filt.to_json(args.out, overwrite=args.overwrite)
    if args.json:
        print_json(filt.to_dict())
    else:
        print(filt.fit.summary())
        if "rational" in filt.fit.excluded:
            print(filt.fit.excluded["rational"])
        print(f"model choice: {filt.fit.excluded.get('model_choice', args.model)}")
        print(f"lag_s = {filt.lag_s:.6g} (added to {args.reference}'s times; clock offset, "
              f"without the sensor's own delay), static factor "
              f"{filt.fit.excluded['static_factor']:.6g}")
        print(filt.summary())
    info(args, f"filter written to {args.out}")
    return 0
