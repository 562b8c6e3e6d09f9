"""``tactilecal calibrate``: fit a static calibration from a manifest or a movie."""

from pathlib import Path

from tactilecal._saturation import SATURATED_CHOICES, SATURATED_DEFAULT, resolve_saturated
from tactilecal.cli._common import (
    info,
    info_grouped,
    non_negative_int,
    positive_float,
    positive_int,
    print_json,
    progress_for,
)


def register(subparsers):
    """Add the ``calibrate`` command."""
    p = subparsers.add_parser(
        "calibrate", help="fit a static calibration (manifest of frames, or a movie)",
        description="Fit a static calibration to the points of a manifest CSV (file, frame, "
                    "load_N or mass_kg [+ pad_mass_g], label), or to every frame of a movie "
                    "paired with a load-cell record (--movie REC --loads CSV).")
    p.add_argument("manifest", nargs="?", help="manifest CSV (not with --movie)")
    p.add_argument("--method", default="power",
                   help="linear, power-2pt, power (default), linear-offset, piecewise, lut, "
                        "polynomial, zvyagin")
    p.add_argument("--objective", help="power: l2, l1 or relative; others: l2 or relative")
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
                   help="bootstrap refits for the parameters' 95 %% intervals and standard "
                        "errors (default 0: none)")
    p.add_argument("--intervals", type=non_negative_int, default=0, metavar="N",
                   help="bootstrap refits for the 95 %% prediction interval of a new patch's "
                        "load (stored in the JSON, used by validate; default 0: none)")
    p.add_argument("--movie", metavar="RECORDING", help="raw recording for movie calibration")
    p.add_argument("--loads", metavar="LOADCELL.csv",
                   help="load-cell CSV for --movie (time and load columns, or one load column "
                        "with one row per frame)")
    p.add_argument("--time-col", help="--loads time column (name or 0-based index)")
    p.add_argument("--load-col", help="--loads load column (name or 0-based index)")
    p.add_argument("--lag", type=float, help="--movie: known lag in s (skip cross-correlation)")
    p.add_argument("--max-lag", type=positive_float,
                   help="--movie: search lags up to this many seconds (periodic loadings)")
    p.add_argument("--out", metavar="CAL.json", help="write the calibration JSON here")
    p.add_argument("--json", action="store_true", help="print the calibration JSON")
    p.set_defaults(func=run)


def _options(args):
    opts = {"saturated": resolve_saturated(args.saturated, args.keep_saturated or None)}
    if args.objective:
        opts["objective"] = args.objective
    if args.mode:
        if args.method != "zvyagin":
            raise ValueError(f"--mode {args.mode} applies to --method zvyagin only, "
                             f"not {args.method!r}")
        opts["mode"] = args.mode
    if args.degree is not None:
        opts["degree"] = args.degree
    if args.knots:
        try:
            opts["knots"] = [float(k) for k in args.knots.split(",")]
        except ValueError:
            raise ValueError(f"--knots {args.knots!r}: expected comma-separated numbers") \
                from None
    if args.point is not None:
        opts["point"] = args.point
    if args.pair:
        try:
            opts["pair"] = tuple(int(k) for k in args.pair.split(","))
        except ValueError:
            raise ValueError(f"--pair {args.pair!r}: expected two integers 'I,J'") from None
    if args.scale_by_working:
        opts["scale_by_working"] = True
    if args.n_bootstrap:
        opts["n_bootstrap"] = args.n_bootstrap
    if args.intervals:
        opts["n_interval_resamples"] = args.intervals
    return opts


def _manifest_points(args, equilibration):
    from tactilecal.calibration import find_dead_sensels, load_frames, load_points

    kw = {"equilibration": equilibration, "progress": progress_for(args)}
    if not args.mask_dead:
        return load_points(args.manifest, **kw), None
    dead = find_dead_sensels(load_frames(args.manifest, **kw))
    return load_points(args.manifest, mask=dead.mask, **kw), dead


def run(args):
    """Run ``tactilecal calibrate``."""
    from tactilecal.calibration import METHODS, calibrate, load_equilibration

    if args.method not in METHODS:  # before any manifest file is read
        raise ValueError(f"--method {args.method!r}; expected one of {', '.join(METHODS)}")
    equilibration = load_equilibration(args.equilibration) if args.equilibration else None
    if args.movie:
        if args.manifest or not args.loads:
            raise ValueError("--movie needs --loads LOADCELL.csv and no MANIFEST; expected "
                             "'tactilecal calibrate --movie REC --loads LOADCELL.csv'")
        from tactilecal.calibration import calibrate_movie

        result = calibrate_movie(args.movie, args.loads, method=args.method,
                                 time_col=args.time_col, load_col=args.load_col,
                                 lag_s=args.lag, max_lag_s=args.max_lag,
                                 mask_dead=args.mask_dead,
                                 equilibration=equilibration, progress=progress_for(args),
                                 **_options(args))
        info(args, result.details["movie"]["report"])
    else:
        if not args.manifest:
            raise ValueError("no MANIFEST given; expected 'tactilecal calibrate MANIFEST' "
                             "or '--movie REC --loads LOADCELL.csv'")
        points, dead = _manifest_points(args, equilibration)
        info_grouped(args, [f"{p.source}: {p.note}" for p in points if p.note])
        try:
            result = calibrate(points, method=args.method, **_options(args))
        except ValueError as err:  # name the manifest: the points' names are in the text
            raise ValueError(f"{args.manifest}: {err}") from None
        if dead is not None:
            result.details["non_working_sensels"] = dead.to_dict()
            info(args, dead.report())
        if equilibration is not None:
            result.details["equilibration"] = equilibration.to_dict()
    if args.out:
        result.to_json(Path(args.out))
        info(args, f"calibration written to {args.out}")
    if args.json:
        print_json(result.to_dict())
    else:
        print(result.summary())
    return 0
