"""``tactilecal equilibrate``: per-sensel gains from uniform-load recordings."""

from tactilecal._errors import TactilecalError
from tactilecal.cli._common import info, print_json
from tactilecal.cli._outputs import add_output


def register(subparsers):
    """Add the ``equilibrate`` command."""
    p = subparsers.add_parser(
        "equilibrate", help="per-sensel gains from uniform-load recordings",
        description="Compute per-sensel gains that equalise the raw output under a uniform "
                    "load (one RECORDING per load level; all frames of a recording are "
                    "averaged) and write them as JSON for 'calibrate --equilibration'.")
    p.add_argument("recordings", nargs="+", metavar="RECORDING")
    add_output(p, "--out", kind="json", required=True, metavar="EQ.json")
    p.add_argument("--json", action="store_true", help="print the per-level report as JSON")
    p.set_defaults(func=run)


def run(args):
    """Run ``tactilecal equilibrate``."""
    from tactilecal.calibration import equilibrate
    from tactilecal.io import open_recording

    levels = []
    for path in args.recordings:
        rec = open_recording(path)
        if rec.attrs.get("units", "raw") != "raw":
            raise TactilecalError(f"{path} has units {rec.attrs['units']!r}; expected raw readings")
        levels.append(rec)
    eq = equilibrate(levels)
    eq.to_json(args.out, overwrite=args.overwrite)
    for lv, path in zip(eq.levels, args.recordings, strict=True):
        info(args, f"{path}: {lv['n_frames']} frames, mean raw {lv['mean_raw']:.1f}, "
                   f"sensel variation {lv['cv_before']:.1%} -> {lv['cv_after']:.1%}")
    info(args, f"gains written to {args.out}")
    if args.json:
        print_json({"levels": eq.levels, "out": args.out})
    return 0
