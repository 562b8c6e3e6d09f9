"""``tactilecal dynamic evaluate``: error before and after correction, and its figures."""

from functools import partial

from tactilecal._atomic import make_folder
from tactilecal.cli._common import print_json, progress
from tactilecal.cli._outputs import add_output


def register(sub):
    """Add the ``evaluate`` action to the ``dynamic`` command's actions."""
    e = sub.add_parser("evaluate", help="error before/after correction, figures",
                       description="Amplitude error against frequency and RMS error of the "
                                   "dynamic part before and after correction; with --out, "
                                   "evaluation.json and the figures (thesis Figs 4.9-4.14).")
    e.add_argument("filter", metavar="FILTER.json")
    e.add_argument("sensor", metavar="SENSOR")
    e.add_argument("reference", metavar="REFERENCE")
    e.add_argument("--json", action="store_true", help="print the result as JSON")
    add_output(e, "--out", kind="evaluation", metavar="DIR",
               help="folder for evaluation.json and PNG figures")
    e.set_defaults(func=run)


def run(args):
    """Run ``tactilecal dynamic evaluate``."""
    import numpy as np

    from tactilecal.dynamic import CorrectionFilter, evaluate, read_record

    filt = CorrectionFilter.from_json(args.filter)
    ev = evaluate(filt, read_record(args.sensor), read_record(args.reference),
                  progress=partial(progress, desc="filtering", quiet=args.quiet))
    result = {**ev.to_dict(), "filter": args.filter, "sensor": args.sensor,
              "reference": args.reference}
    if args.out:
        result = ev.save(make_folder(args.out, what="--out"), filt,
                         extra={k: result[k] for k in ("filter", "sensor", "reference")})
    if args.json:
        print_json(result)
    else:
        print(ev.summary())
        if ev.f_hz.size:
            print(f"amplitude error over {ev.f_hz.size} coherent bins "
                  f"({ev.f_hz.min():g}..{ev.f_hz.max():g} Hz): median |error| "
                  f"{np.median(np.abs(ev.error_before_pct)):.3g} % before, "
                  f"{np.median(np.abs(ev.error_after_pct)):.3g} % after")
    return 0
