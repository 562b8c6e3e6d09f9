"""``tactilecal analyze RECORDING [--cal CAL.json] [--json] [--out summary.csv]``."""

from tactilecal._errors import TactilecalError
from tactilecal.cli._common import info, print_aligned, print_json, progress, warn_saturated
from tactilecal.cli._outputs import add_output
from tactilecal.cli._types import non_negative_float


def register(subparsers):
    """Add the ``analyze`` command."""
    p = subparsers.add_parser(
        "analyze", help="per-frame force, area, centre of force and pressures of a recording",
        description="Total force [N], contact area [mm2], centre of force [mm], peak and mean "
                    "pressure [kPa] of every frame of a recording (Tekscan ASCII export or "
                    "NetCDF). Raw recordings need --cal.")
    p.add_argument("recording", help="Tekscan ASCII export (.csv, .asf...) or NetCDF (.nc)")
    p.add_argument("--cal", metavar="CAL.json", help="calibration JSON for raw recordings")
    p.add_argument("--threshold-kpa", type=non_negative_float, default=0.0, metavar="KPA",
                   help="a sensel is loaded above this pressure (default 0)")
    add_output(p, "--out", kind="csv", sidecar=True, metavar="summary.csv",
               help="write the per-frame table as CSV (and its provenance beside it)")
    p.add_argument("--json", action="store_true",
                   help="print the overview and the per-frame table as JSON")
    p.set_defaults(func=run)


def run(args):
    """Analyse one recording; print an overview (or JSON) and optionally write the CSV."""
    from tactilecal._atomic import atomic_path
    from tactilecal._provenance import provenance_of, write_sidecar
    from tactilecal.analysis import overview
    from tactilecal.report import load_input

    bar = progress(total=3, desc="analyze", quiet=args.quiet)
    kind, recording, _ = load_input(args.recording, what="RECORDING")
    if kind != "recording":
        raise TactilecalError(f"{args.recording} is a {kind} file; expected a recording")
    bar.update()
    calibration = None
    if args.cal:
        kind, calibration, _ = load_input(args.cal, what="--cal")
        if kind != "calibration":
            raise TactilecalError(f"--cal {args.cal} is a {kind} file; expected a calibration JSON")
    table = recording.tactile.frame_table(calibration=calibration,
                                          threshold_kPa=args.threshold_kpa)
    bar.update()
    if args.out:
        with atomic_path(args.out) as tmp:
            table.to_csv(tmp, index=False)
        inputs = provenance_of([recording], files=[args.cal] if args.cal else [],
                               options={"cal": args.cal, "threshold_kPa": args.threshold_kpa})
        side = write_sidecar(args.out, inputs)
        info(args, f"per-frame table written to {args.out} (provenance: {side})")
    bar.update()
    bar.close()
    head = overview(table, source=str(args.recording))
    if head["saturated_frames"]:
        warn_saturated(head["saturated_frames"], len(table), args.recording)
    if args.json:
        print_json({"overview": head, "calibration": args.cal,
                    "threshold_kPa": args.threshold_kpa,
                    "frames": table.to_dict(orient="records")})
        return 0
    print_aligned(head, float_format=".6g")
    return 0
