"""``tactilecal demo [--out DIR]``: the end-to-end example on bundled synthetic data."""

from tactilecal.cli._outputs import add_output


def register(subparsers):
    """Add the ``demo`` command."""
    parser = subparsers.add_parser(
        "demo", help="run the end-to-end example on bundled synthetic data",
        description="Calibrate the bundled dead-weight sessions by every method, validate "
                    "them, analyse a recording, fit a dynamic filter and write the report.")
    add_output(parser, "--out", kind="demo", default="tactilecal-demo",
               help="output folder (default: tactilecal-demo)")
    parser.set_defaults(func=run)


def run(args):
    """Run the demo."""
    from tactilecal.demo import run_demo

    run_demo(args.out, quiet=args.quiet, overwrite=args.overwrite)
    return 0
