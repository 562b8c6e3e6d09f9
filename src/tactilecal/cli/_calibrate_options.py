"""The fit options of ``tactilecal calibrate``: their flags and the library keywords they give."""

from tactilecal._errors import TactilecalError
from tactilecal._saturation import SATURATED_CHOICES, SATURATED_DEFAULT, resolve_saturated
from tactilecal.cli._types import non_negative_int, positive_int

__all__ = ["add_fit_options", "fit_options"]


def add_fit_options(p):
    """Add the method, its options, the preprocessing and the bootstrap flags to ``p``."""
    p.add_argument("--method", default="power",
                   help="linear, power-2pt, power (default), linear-offset, piecewise, lut, "
                        "polynomial, zvyagin")
    p.add_argument("--objective", help="power, piecewise, lut: l1 (default), l2 or relative; "
                                       "zvyagin: also cv (robust's default); linear-offset, "
                                       "polynomial: l2 or relative")
    p.add_argument("--mode", choices=("faithful", "robust"),
                   help="zvyagin: follow the paper as written or the robust variant "
                        "(docs/zvyagin.md; default robust, as in the Python API)")
    p.add_argument("--degree", type=positive_int, help="polynomial degree (default 3)")
    p.add_argument("--knots", help="piecewise/lut knots, comma-separated raw values")
    p.add_argument("--point", type=non_negative_int,
                   help="linear: index of the one usable point (I-Scan 1-point calibration)")
    p.add_argument("--pair", help="power-2pt: two usable-point indices 'I,J' (default: the "
                                  "points nearest 20 %% and 80 %% of the largest load)")
    p.add_argument("--saturated", choices=SATURATED_CHOICES,
                   help="patches with a sensel at 255: drop them from the fit or keep them "
                        f"(default {SATURATED_DEFAULT}, as in the Python API)")
    p.add_argument("--keep-saturated", action="store_true",
                   help="same as --saturated keep (older spelling)")
    p.add_argument("--scale-by-working", action="store_true",
                   help="linear/power-2pt: scale loads by working / all sensels")
    p.add_argument("--mask-dead", action="store_true",
                   help="detect non-working sensels across the frames and leave them out")
    p.add_argument("--equilibration", metavar="EQ.json",
                   help="per-sensel gains from 'tactilecal equilibrate', applied first")
    p.add_argument("--n-bootstrap", type=non_negative_int, default=0,
                   help="accepted and recorded; no parameter interval is reported (none held "
                        "90-99 %% in simulation, issue 12: the JSON's stderr_method says why); "
                        "use --intervals")
    p.add_argument("--intervals", type=non_negative_int, default=0, metavar="N",
                   help="bootstrap refits for the 95 %% prediction interval of a new patch's "
                        "load (stored in the JSON, used by validate; default 0: none)")


def fit_options(args):
    """Return the method options of the command line (absent flags: library defaults)."""
    saturated = resolve_saturated(args.saturated, args.keep_saturated or None)
    if args.mode and args.method != "zvyagin":
        raise TactilecalError(f"--mode {args.mode} applies to --method zvyagin only, "
                              f"not {args.method!r}")
    knots = numbers(args.knots, "--knots", float, "comma-separated numbers")
    pair = numbers(args.pair, "--pair", int, "two integers 'I,J'")
    opts = {"saturated": saturated, "objective": args.objective or None, "mode": args.mode,
            "degree": args.degree, "knots": knots, "point": args.point,
            "pair": None if pair is None else tuple(pair),
            "scale_by_working": args.scale_by_working or None,
            "n_bootstrap": args.n_bootstrap or None,
            "n_interval_resamples": args.intervals or None}
    return {key: value for key, value in opts.items() if value is not None}


def numbers(text, flag, kind, expected):
    """Parse a comma-separated flag value (``--knots 1,2.5``) into a list, or None if empty.

    Raises
    ------
    ValueError
        ``"--knots '1,a': expected comma-separated numbers"`` (``flag`` and ``expected``).
    """
    if not text:
        return None
    try:
        return [kind(item) for item in text.split(",")]
    except ValueError:
        raise TactilecalError(f"{flag} {text!r}: expected {expected}") from None
