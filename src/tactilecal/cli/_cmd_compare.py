"""``tactilecal compare CAL.json...``: calibrations side by side, curves on one plot."""

from pathlib import Path

from tactilecal._atomic import make_folder
from tactilecal.cli._common import info, print_json
from tactilecal.cli._outputs import add_output


def register(subparsers):
    """Add the ``compare`` command."""
    p = subparsers.add_parser(
        "compare", help="compare calibrations: Table-2-like table and curves on one plot",
        description="One row per CAL.json of any method: points used, I* and d(I*) (Zvyagin "
                    "calibrations), A0, b0 (power model), the force at raw 128, the "
                    "saturation pressure p_s and the fit's median error, like Zvyagin (2022) "
                    "Table 2, to see a sensor's drift across sessions or a used sensor "
                    "against a new one. --out DIR also draws every curve on one plot.")
    p.add_argument("calibrations", metavar="CAL.json", nargs="+")
    p.add_argument("--json", action="store_true", help="print the table as JSON")
    add_output(p, "--out", kind="figures", metavar="DIR", help="write compare_curves.png into DIR")
    p.set_defaults(func=run)


def _row_names(paths):
    """Row names from file names, made unique with their folder when stems repeat."""
    paths = [Path(p) for p in paths]
    stems = [p.stem for p in paths]
    return [f"{p.parent.name}/{p.stem}" if stems.count(p.stem) > 1 else p.stem for p in paths]


def run(args):
    """Run ``tactilecal compare``."""
    from tactilecal._png import FIGURE_DPI, write_png
    from tactilecal.calibration import CalibrationResult, compare_calibrations

    comparison = compare_calibrations(
        [CalibrationResult.from_json(p) for p in args.calibrations],
        _row_names(args.calibrations))
    figure = None
    if args.out:
        outdir = make_folder(args.out, what="--out")
        figure = outdir / "compare_curves.png"
        ax = comparison.plot()
        write_png(ax.figure, figure, dpi=FIGURE_DPI)
        info(args, f"curves written to {figure}")
    if args.json:
        print_json({"rows": comparison.rows, "figure": None if figure is None else str(figure)})
    else:
        print(comparison.table())
    return 0
