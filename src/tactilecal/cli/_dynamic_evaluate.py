"""``tactilecal dynamic evaluate``: error before and after correction, and its figures."""

from functools import partial

from tactilecal._atomic import make_folder
from tactilecal.cli._common import print_json, progress_for
from tactilecal.cli._library_options import add_option
from tactilecal.cli._outputs import add_output


def register(sub):
    """Add the ``evaluate`` action to the ``dynamic`` command's actions."""
    e = sub.add_parser("evaluate", help="error before/after correction, figures",
                       description="RMS error of the dynamic part and amplitude and phase "
                                   "error against frequency, before and after correction, "
                                   "at the clock the filter was fitted with (or a known one: "
                                   "--lag); with --out, evaluation.json and the figures "
                                   "(thesis Figs 4.9-4.14).")
    e.add_argument("filter", metavar="FILTER.json")
    e.add_argument("sensor", metavar="SENSOR")
    e.add_argument("reference", metavar="REFERENCE")
    e.add_argument("--json", action="store_true", help="print the result as JSON")
    add_output(e, "--out", kind="evaluation", metavar="DIR",
               help="folder for evaluation.json and PNG figures")
    e.defer(_add_options)  # defaults read from the library: imported when used
    e.set_defaults(func=run)


def _add_options(e):
    from tactilecal.dynamic import evaluate

    add_option(e, "--lag", evaluate, "lag_s", type=float, metavar="S",
               help="the records' known clock offset in s (added to the reference's times; "
                    "default: found as the fit found the filter's)")
    add_option(e, "--realign", evaluate, "realign",
               help="also report the error at the lag that aligns the corrected record best "
                    "(what a perfectly re-timed record would give), labelled as such")
    add_option(e, "--causal", evaluate, "causal",
               help="evaluate a rational filter's causal inverse")


def run(args):
    """Run ``tactilecal dynamic evaluate``."""
    from tactilecal.dynamic import CorrectionFilter, evaluate, read_record

    filt = CorrectionFilter.from_json(args.filter)
    ev = evaluate(filt, read_record(args.sensor), read_record(args.reference),
                  lag_s=args.lag_s, realign=args.realign, causal=args.causal,
                  progress=partial(progress_for(args), desc="filtering"))
    ev.inputs = {"filter": args.filter, "sensor": args.sensor, "reference": args.reference}
    if args.out:
        ev.save(make_folder(args.out, what="--out"), filt)
    if args.json:
        print_json(ev.to_dict())
    else:
        print(ev.summary())
    return 0
