"""``tactilecal convert``: a Tekscan export to Zarr or NetCDF, streamed block by block."""

from pathlib import Path

from tactilecal.cli._common import info
from tactilecal.cli._library_options import add_option
from tactilecal.cli._outputs import add_output
from tactilecal.cli._types import positive_int


def register(subparsers):
    """Add the ``convert`` command."""
    p = subparsers.add_parser(
        "convert", help="a Tekscan export to Zarr (.zarr) or NetCDF (.nc), block by block",
        description="Write a Tekscan ASCII export as a Zarr store (OUT.zarr) or a NetCDF file "
                    "(OUT.nc) without holding it in memory: the file is indexed once, then "
                    "parsed and written FRAMES frames at a time. OUT is written under a "
                    "temporary name and renamed at the end, so an error leaves no output.")
    p.add_argument("recording", metavar="IN", help="Tekscan ASCII export")
    add_output(p, "out", kind=_kind, metavar="OUT", help="output ending in .zarr or .nc")
    p.defer(_add_options)  # defaults read from the library: imported when used
    p.set_defaults(func=run)


def _add_options(p):
    from tactilecal.io import convert

    add_option(p, "--chunks", convert, "chunks", "frames per block", type=positive_int,
               metavar="FRAMES")
    add_option(p, "--dtype", convert, "dtype", "type of the stored values (float32 halves "
               "the array and holds raw 8-bit readings exactly)",
               choices=["float64", "float32"])


def _kind(args):
    return "zarr" if Path(args.out).suffix.lower() == ".zarr" else "netcdf"


def run(args):
    """Run ``tactilecal convert``."""
    from tactilecal.io import convert

    data = convert(args.recording, args.out, chunks=args.chunks, dtype=args.dtype,
                   overwrite=args.overwrite)
    frames, rows, cols = data.shape
    info(args, f"wrote {args.out}: {frames} frames of {rows} x {cols} sensels ({args.dtype}) "
               f"in blocks of {args.chunks} frames")
    return 0
