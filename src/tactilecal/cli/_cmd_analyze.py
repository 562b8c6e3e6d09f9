"""``tactilecal analyze RECORDING [--cal CAL.json] [--region NAME=SPEC] [--steps] [--json]``."""

from tactilecal.cli._common import info, print_json, progress, warn_saturated
from tactilecal.cli._inputs import (
    add_region_options,
    gap_mm,
    load_calibration,
    load_recording,
    regions,
)
from tactilecal.cli._library_options import add_option
from tactilecal.cli._outputs import add_output
from tactilecal.cli._types import non_negative_float


def register(subparsers):
    """Add the ``analyze`` command."""
    p = subparsers.add_parser(
        "analyze", help="per-frame force, area, centre of force and pressures of a recording",
        description="Total force [N], contact area [mm2], centre of force [mm], peak and mean "
                    "pressure [kPa] of every frame of a recording (Tekscan ASCII export or "
                    "NetCDF), per region with --region or --split-contacts, and its steps "
                    "with --steps. Raw recordings need --cal.")
    p.add_argument("recording", help="Tekscan ASCII export (.csv, .asf...) or NetCDF (.nc)")
    p.add_argument("--cal", metavar="CAL.json", help="calibration JSON for raw recordings")
    p.defer(_add_options)  # defaults read from the library: imported when used
    add_region_options(p)
    p.add_argument("--steps", action="store_true",
                   help="find the steps (stance phases): peak, impulse, loading rate, "
                        "pressure-time integral and centre-of-pressure path of each")
    add_output(p, "--out", kind="csv", sidecar=True, metavar="summary.csv",
               help="write the per-frame table as CSV (each region's columns too) and its "
                    "provenance beside it")
    p.add_argument("--json", action="store_true",
                   help="print the overview and the per-frame table as JSON")
    p.set_defaults(func=run)


def _add_options(p):
    from tactilecal.analysis import TactileAccessor

    add_option(p, "--threshold-kpa", TactileAccessor.analyze, "threshold_kPa",
               "a sensel is loaded above this pressure", type=non_negative_float,
               metavar="KPA")


def run(args):
    """Analyse one recording; print an overview (or JSON) and optionally write the CSV."""
    from tactilecal._atomic import atomic_path
    from tactilecal._provenance import provenance_of, write_sidecar

    bar = progress(total=2, desc="analyze", quiet=args.quiet)
    recording = load_recording(args.recording)
    calibration = load_calibration(args.cal)
    bar.update()
    result = recording.tactile.analyze(calibration=calibration, threshold_kPa=args.threshold_kPa,
                                       regions=regions(args), gap_mm=gap_mm(args),
                                       find_steps=args.steps,
                                       source=str(args.recording))
    bar.update()
    bar.close()
    if args.out:
        with atomic_path(args.out) as tmp:
            result.wide_table().to_csv(tmp, index=False)
        options = {"cal": args.cal, "threshold_kPa": args.threshold_kPa}
        options.update({k: v for k, v in (("regions", args.region), ("split_contacts",
                                           args.split_contacts), ("gap_mm", args.gap_mm)) if v})
        inputs = provenance_of([recording], files=[args.cal] if args.cal else [],
                               options=options)
        info(args, f"per-frame table written to {args.out} (provenance: "
                   f"{write_sidecar(args.out, inputs)})")
    if result.overview["saturated_frames"]:
        warn_saturated(result.overview["saturated_frames"], len(result.frames), args.recording)
    if args.json:
        print_json({**result.to_dict(), "calibration": args.cal,
                    "threshold_kPa": args.threshold_kPa})
    else:
        print(result.text())
    return 0
