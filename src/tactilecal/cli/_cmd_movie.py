"""``tactilecal movie RECORDING --out rec.mp4|rec.gif``: the pressure map frame by frame."""

from tactilecal.cli._common import info, progress_for
from tactilecal.cli._inputs import load_calibration, load_recording
from tactilecal.cli._library_options import add_option
from tactilecal.cli._outputs import add_output
from tactilecal.cli._types import positive_float, positive_int


def register(subparsers):
    """Add the ``movie`` command."""
    p = subparsers.add_parser(
        "movie", help="write a recording as a movie (MP4 with ffmpeg, else GIF)",
        description="Draw every frame of RECORDING (Tekscan export, .nc, .zarr) as a pressure "
                    "map with its centre of force and saturated sensels marked, and write "
                    "the movie: MP4 when ffmpeg is installed, else an animated GIF (an .mp4 "
                    "asked for is then written as .gif next to it, and said so). Long "
                    "recordings show every k-th frame (--max-frames).")
    p.add_argument("recording", metavar="RECORDING")
    add_output(p, "--out", kind="movie", required=True, metavar="rec.mp4|rec.gif")
    p.add_argument("--cal", metavar="CAL.json", help="calibration for raw readings")
    p.add_argument("--units", help="pressure unit shown (kPa, MPa, psi; default the "
                                   "recording's own)")
    p.add_argument("--fps", type=positive_float, help="frames per second (default real time)")
    p.defer(_add_options)  # defaults read from the library: imported when used
    p.set_defaults(func=run)


def _add_options(p):
    from tactilecal.analysis import TactileAccessor

    add_option(p, "--max-frames", TactileAccessor.write_movie, "max_frames",
               "show at most N frames, every k-th of longer recordings", type=positive_int,
               metavar="N")


def run(args):
    """Run ``tactilecal movie``."""
    recording = load_recording(args.recording)
    path = recording.tactile.write_movie(args.out, calibration=load_calibration(args.cal),
                                         units=args.units, fps=args.fps,
                                         max_frames=args.max_frames,
                                         progress=progress_for(args),
                                         overwrite=args.overwrite)
    if str(path) != str(args.out):
        info(args, f"ffmpeg is not installed: wrote an animated GIF, {path}, instead of "
                   f"{args.out}")
    info(args, f"movie of {recording.sizes['frame']} frames written to {path}")
    return 0
