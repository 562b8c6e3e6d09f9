"""``tactilecal dynamic fit``: fit a correction filter on sine sweeps (FILTER.json out)."""

import sys

from tactilecal.cli._common import info, print_json
from tactilecal.cli._library_options import add_option
from tactilecal.cli._outputs import add_output
from tactilecal.cli._types import positive_float, share


def register(sub):
    """Add the ``fit`` action to the ``dynamic`` command's actions."""
    f = sub.add_parser("fit", help="fit a filter on a sweep (FILTER.json out)",
                       description="SENSOR and REFERENCE are time-series CSVs (time, value); "
                                   "SENSOR may also be a Tekscan recording or NetCDF, whose "
                                   "frames are summed. Records may have different rates "
                                   "and start times: they are aligned first.")
    f.add_argument("sensor", metavar="SENSOR")
    f.add_argument("reference", metavar="REFERENCE")
    f.add_argument("--sweep", nargs=2, action="append", default=[],
                   metavar=("SENSOR", "REFERENCE"),
                   help="another sweep (e.g. at another amplitude); repeatable")
    add_output(f, "--out", kind="json", required=True, metavar="FILTER.json")
    f.add_argument("--json", action="store_true", help="print the result as JSON")
    f.defer(_add_options)  # defaults read from the library: imported when used
    f.set_defaults(func=run)


def _add_options(f):
    from tactilecal.dynamic import fit_filter

    add_option(f, "--model", fit_filter, "model",
               help="auto: of log10, rational and wiener, the simplest that predicts held-out "
                    "bins within 10 %% of the best or to 1 %%; log10 / log: the thesis' "
                    "Y = 1 + A log(f + 1); log-quadratic; rational: real corners and "
                    "resonances, undone with their phase; wiener: the measured correction, "
                    "shrunk where it is within its random error. Every model has a delay")
    add_option(f, "--band", fit_filter, "band_hz", nargs=2, type=float, metavar=("LO", "HI"),
               help="fit only LO..HI Hz; also the calibrated band (default: the bins with "
                    "coherent energy)")
    add_option(f, "--method", fit_filter, "method",
               help="transfer-function estimator: h2, h1 or ratio")
    add_option(f, "--min-coherence", fit_filter, "min_coherence", type=share,
               help="bins with less coherence are not calibrated")
    add_option(f, "--min-power-db", fit_filter, "min_power_db", type=positive_float,
               help="coherent bins more than this many dB below their median are not "
                    "calibrated (leakage above the sweep)")
    add_option(f, "--outside", fit_filter, "outside", choices=("taper", "hold"),
               help="gain above the band: taper to 1, or hold")
    add_option(f, "--max-noise-gain", fit_filter, "max_noise_gain", type=positive_float,
               help="refuse a filter whose gain exceeds this anywhere")
    add_option(f, "--force", fit_filter, "force",
               help="write the filter even when its model is refused (marked forced)")


def run(args):
    """Run ``tactilecal dynamic fit``."""
    from tactilecal.dynamic import fit_filter, read_record

    pairs = [(args.sensor, args.reference), *args.sweep]
    sensors, references = ([read_record(p[k]) for p in pairs] for k in (0, 1))
    filt = fit_filter(sensors if len(pairs) > 1 else sensors[0],
                      references if len(pairs) > 1 else references[0], model=args.model,
                      band_hz=args.band_hz, method=args.method,
                      min_coherence=args.min_coherence, min_power_db=args.min_power_db,
                      outside=args.outside, max_noise_gain=args.max_noise_gain,
                      force=args.force)
    if filt.forced:
        print(f"tactilecal dynamic fit: warning: written with --force: {filt.forced}",
              file=sys.stderr)
    filt.to_json(args.out, overwrite=args.overwrite)
    if args.json:
        print_json(filt.to_dict())
    else:
        print(filt.summary())
    info(args, f"filter written to {args.out}")
    return 0
