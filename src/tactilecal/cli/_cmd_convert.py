"""``tactilecal convert``: a Tekscan export to Zarr or NetCDF, streamed block by block."""

from pathlib import Path

from tactilecal.cli._common import info
from tactilecal.cli._outputs import add_output
from tactilecal.cli._types import positive_int

DEFAULT_CHUNK_FRAMES = 1000  # tactilecal.io.convert's default (not imported: keeps --help fast)


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
    p.add_argument("--chunks", type=positive_int, default=DEFAULT_CHUNK_FRAMES,
                   metavar="FRAMES",
                   help=f"frames per block (default {DEFAULT_CHUNK_FRAMES})")
    p.add_argument("--dtype", default="float64", choices=["float64", "float32"],
                   help="type of the stored values (default float64; float32 halves the "
                        "array and holds raw 8-bit readings exactly)")
    p.set_defaults(func=run)


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
