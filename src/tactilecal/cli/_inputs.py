"""Inputs several commands share: a recording, a calibration, regions (``--region``)."""

import argparse

from tactilecal import _contact
from tactilecal._errors import TactilecalError

__all__ = ["add_region_options", "regions", "gap_mm", "load_recording", "load_calibration"]


def _region(text):
    from tactilecal.analysis import Regions

    try:
        return Regions.parse_option(text)
    except TactilecalError as exc:
        raise argparse.ArgumentTypeError(str(exc).removeprefix("--region ")) from None


_region.checks_value = True  # a refused value is bad input (exit 1)


def add_region_options(parser):
    """Add ``--region NAME=SPEC`` (repeatable), ``--split-contacts`` and ``--gap-mm``."""
    from tactilecal.cli._types import non_negative_float

    group = parser.add_mutually_exclusive_group()
    group.add_argument("--region", action="append", type=_region, metavar="NAME=SPEC",
                       help="a named region (repeatable): NAME=R0:R1,C0:C1 (a box of 0-based "
                            "sensel rows and columns, stops excluded), NAME=poly:R,C;R,C;R,C "
                            "(a polygon in sensel coordinates) or NAME=mask.csv|mask.npy (0/1 "
                            "per sensel)")
    group.add_argument("--split-contacts", action="store_true",
                       help="find the separated contact areas (two knee compartments, two "
                            "feet) and analyse each as a region")
    parser.add_argument("--gap-mm", type=non_negative_float, metavar="MM",
                        help="--split-contacts: areas separated by less unloaded sensor are "
                             f"one contact (default {_contact.DEFAULT_GAP_MM:g})")


def regions(args):
    """Return the regions the flags ask for: ``{name: spec}``, ``"contacts"`` or None."""
    if args.gap_mm is not None and not args.split_contacts:
        raise TactilecalError("--gap-mm is given without --split-contacts; expected both")
    if args.region:
        names = [name for name, _ in args.region]
        if len(set(names)) < len(names):
            raise TactilecalError(f"--region names {names} repeat; expected one name per region")
        return dict(args.region)
    return "contacts" if args.split_contacts else None


def gap_mm(args):
    """Return ``--gap-mm`` (None: the library's default)."""
    return args.gap_mm


def load_recording(path, what="RECORDING"):
    """Read a recording; a JSON or other file says what it is and what was expected."""
    import tactilecal.analysis  # noqa: F401 - registers recording.tactile
    from tactilecal.report import load_input

    kind, recording, _ = load_input(path, what=what)
    if kind != "recording":
        raise TactilecalError(f"{what} {path} is a {kind} file; expected a recording (Tekscan "
                              "export, .nc or .zarr)")
    return recording


def load_calibration(path, what="--cal"):
    """Read a calibration JSON (None stays None)."""
    if path is None:
        return None
    from tactilecal.report import load_input

    kind, calibration, _ = load_input(path, what=what)
    if kind != "calibration":
        raise TactilecalError(f"{what} {path} is a {kind} file; expected a calibration JSON")
    return calibration
