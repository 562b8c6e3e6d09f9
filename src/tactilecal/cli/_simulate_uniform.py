"""``tactilecal simulate uniform OUTDIR``: uniform-load recordings to equilibrate."""

from functools import partial

from tactilecal.cli._common import info
from tactilecal.cli._library_options import add_option
from tactilecal.cli._outputs import add_output
from tactilecal.cli._types import positive_int

__all__ = ["add_uniform"]


def _pressures(text):
    import argparse

    from tactilecal.cli._options import _scalar

    try:
        values = [float(_scalar(v)) for v in text.split(",")]
    except ValueError:
        values = []
    if not values or any(not v > 0 for v in values):
        raise argparse.ArgumentTypeError(f"{text!r}; expected comma-separated positive "
                                         "pressures in kPa, e.g. 50,100,200")
    return values


_pressures.checks_value = True


def add_uniform(sub, common_options):
    """Add ``simulate uniform``."""
    p = sub.add_parser(
        "uniform", help="uniform pressure at several levels (equilibration input)",
        description="Write one I-Scan ASCII recording per uniform pressure level "
                    "(uniform-<k>-<p>kPa.csv) and truth.json (the sensor's law and "
                    "per-sensel gains): the input of 'tactilecal equilibrate'.")
    add_output(p, "outdir", kind="session", metavar="OUTDIR",
               help="output folder (created if missing)")
    p.add_argument("--pressures-kpa", type=_pressures, default=[50.0, 100.0, 200.0],
                   metavar="P1,P2,...", help="pressure levels in kPa (50,100,200)")
    p.defer(partial(_options, common_options=common_options))  # the library's defaults
    p.set_defaults(func=run_uniform)


def _options(parser, common_options):
    from tactilecal.simulate import uniform_load

    common_options(parser, uniform_load)
    add_option(parser, "--frames", uniform_load, "frames_per_level", "frames per level",
               type=positive_int, metavar="N")


def run_uniform(args):
    """Write the uniform-load recordings and say what was written."""
    from tactilecal.cli._simulate_run import _print, _sensor
    from tactilecal.simulate import uniform_load

    sensor = _sensor(args)
    session = uniform_load(sensor, args.pressures_kpa, frames_per_level=args.frames_per_level,
                           seed=args.seed)
    paths = session.write(args.outdir, sensor, overwrite=args.overwrite)
    info(args, f"next: tactilecal equilibrate {args.outdir}/uniform-*.csv --out eq.json")
    _print(args, {**{k: str(v) for k, v in paths.items()}, "sensor": sensor.sensor_type,
                  "pressures_kPa": args.pressures_kpa, "frames_per_level": args.frames_per_level})
    return 0
