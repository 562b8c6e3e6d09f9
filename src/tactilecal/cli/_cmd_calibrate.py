"""``tactilecal calibrate``: fit a static calibration from a manifest or a movie."""

from pathlib import Path

from tactilecal._errors import TactilecalError
from tactilecal.cli._common import info, info_grouped, print_json, progress_for
from tactilecal.cli._outputs import add_output
from tactilecal.cli._types import positive_float


def register(subparsers):
    """Add the ``calibrate`` command."""
    p = subparsers.add_parser(
        "calibrate", help="fit a static calibration (manifest of frames, or a movie)",
        description="Fit a static calibration to the points of a manifest CSV (file, frame, "
                    "load_N or mass_kg [+ pad_mass_g], label), or to every frame of a movie "
                    "paired with a load-cell record (--movie REC --loads CSV).")
    p.add_argument("manifest", nargs="?", help="manifest CSV (not with --movie)")
    p.defer(_add_fit_options)  # made from the library's option classes: imported when used
    p.add_argument("--movie", metavar="RECORDING", help="raw recording for movie calibration")
    p.add_argument("--loads", metavar="LOADCELL.csv",
                   help="load-cell CSV for --movie (time and load columns, or one load column "
                        "with one row per frame)")
    p.add_argument("--time-col", help="--loads time column (name or 0-based index)")
    p.add_argument("--load-col", help="--loads load column (name or 0-based index)")
    p.add_argument("--lag", type=float, help="--movie: known lag in s (skip cross-correlation)")
    p.add_argument("--max-lag", type=positive_float,
                   help="--movie: search lags up to this many seconds (periodic loadings)")
    p.add_argument("--from", dest="from_s", type=float, metavar="S",
                   help="--movie: fit the frames from this time of the recording on")
    p.add_argument("--to", dest="to_s", type=float, metavar="S",
                   help="--movie: fit the frames up to this time of the recording")
    p.add_argument("--min-load", dest="min_load_N", type=positive_float, metavar="N",
                   help="--movie: fit the frames carrying at least this load (e.g. stance)")
    add_output(p, "--out", kind="json", metavar="CAL.json", help="write the calibration JSON here")
    p.add_argument("--json", action="store_true", help="print the calibration JSON")
    p.set_defaults(func=run)


def _add_fit_options(p):
    from tactilecal.cli._calibrate_options import add_fit_options

    add_fit_options(p)


def run(args):
    """Run ``tactilecal calibrate``."""
    from tactilecal.calibration import METHODS, calibrate, calibrate_movie
    from tactilecal.cli._calibrate_options import fit_options

    if args.method not in METHODS:  # before any manifest file is read
        raise TactilecalError(f"--method {args.method!r}; expected one of {', '.join(METHODS)}")
    if args.movie:
        if args.manifest or not args.loads:
            raise TactilecalError("--movie needs --loads LOADCELL.csv and no MANIFEST; expected "
                                  "'tactilecal calibrate --movie REC --loads LOADCELL.csv'")
        result = calibrate_movie(args.movie, args.loads, method=args.method,
                                 time_col=args.time_col, load_col=args.load_col,
                                 lag_s=args.lag, max_lag_s=args.max_lag, from_s=args.from_s,
                                 to_s=args.to_s, min_load_N=args.min_load_N,
                                 mask_dead=args.mask_dead, equilibration=args.equilibration,
                                 progress=progress_for(args), **fit_options(args))
    else:
        if not args.manifest:
            raise TactilecalError("no MANIFEST given; expected 'tactilecal calibrate MANIFEST' "
                                  "or '--movie REC --loads LOADCELL.csv'")
        result = calibrate(args.manifest, method=args.method,
                           progress=progress_for(args),
                           equilibration=args.equilibration,
                           mask="detect" if args.mask_dead else None, **fit_options(args))
        table = result.points
        info_grouped(args, [f"{f}: {n}" for f, n in zip(table["file"], table["note"],
                                                         strict=True) if n])
    if args.out:
        result.to_json(Path(args.out), overwrite=args.overwrite)
        info(args, f"calibration written to {args.out}")
    if args.json:
        print_json(result.to_dict())
    else:
        print(result.summary())
    return 0
