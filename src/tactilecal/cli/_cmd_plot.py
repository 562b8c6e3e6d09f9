"""``tactilecal plot INPUT --out DIR``: the figures of a calibration or a recording as PNG."""

from tactilecal._atomic import make_folder
from tactilecal._png import FIGURE_DPI
from tactilecal.cli._common import info, print_json
from tactilecal.cli._inputs import add_region_options, gap_mm, load_calibration, regions
from tactilecal.cli._outputs import add_output
from tactilecal.cli._types import non_negative_int, positive_int


def register(subparsers):
    """Add the ``plot`` command."""
    p = subparsers.add_parser(
        "plot", help="draw the figures of a calibration JSON or a recording as PNG files",
        description="Write the figures of INPUT into DIR. A calibration JSON: Zvyagin (2022) "
                    "Figures 7-11 and E(b0) for a Zvyagin calibration, else the calibration "
                    "curve, predicted vs applied loads and the error histogram. A recording "
                    "(Tekscan export, .nc, .zarr): one frame's pressure map, the peak map, "
                    "force and contact area, and the centre of force against time and over "
                    "the map (saturated sensels marked); per region with --region or "
                    "--split-contacts.")
    p.add_argument("input", metavar="INPUT", help="calibration JSON or recording")
    add_output(p, "--out", kind="figures", metavar="DIR", required=True,
               help="folder for the PNG files (created if missing)")
    p.add_argument("--dpi", type=positive_int, default=FIGURE_DPI,
                   help="resolution (default %(default)s)")
    p.add_argument("--cal", metavar="CAL.json", help="recording: calibration for raw readings")
    p.add_argument("--frame", type=non_negative_int, metavar="N",
                   help="recording: the frame number to draw (default the peak-force frame)")
    p.add_argument("--units", help="recording: pressure unit of the maps (kPa, MPa, psi; "
                                   "default the recording's own)")
    add_region_options(p)
    p.add_argument("--json", action="store_true", help="print the written paths as JSON")
    p.set_defaults(func=run)


def run(args):
    """Run ``tactilecal plot``."""
    import tactilecal.analysis  # noqa: F401 - registers recording.tactile
    from tactilecal.report import load_input

    kind, obj, _ = load_input(args.input, what="INPUT")
    outdir = make_folder(args.out, what="--out")
    if kind == "calibration":
        paths = obj.save_figures(outdir, dpi=args.dpi)
        what = f"the {obj.method!r} calibration"
    elif kind == "recording":
        paths = obj.tactile.save_figures(outdir, frame=args.frame, units=args.units,
                                         calibration=load_calibration(args.cal),
                                         regions=regions(args), gap_mm=gap_mm(args),
                                         dpi=args.dpi)
        what = "the recording"
    else:
        from tactilecal._errors import TactilecalError

        raise TactilecalError(f"INPUT {args.input} is a {kind} file; expected a calibration "
                              "JSON or a recording (Tekscan export, .nc, .zarr)")
    if args.json:
        print_json({"input": str(args.input), "kind": kind,
                    "figures": [str(p) for p in paths]})
    else:
        print("\n".join(str(p) for p in paths))
    info(args, f"{len(paths)} figures of {what} written to {outdir}")
    return 0
