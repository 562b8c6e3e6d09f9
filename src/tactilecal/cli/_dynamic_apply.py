"""``tactilecal dynamic apply``: correct a time-series CSV or every sensel of a recording."""

from functools import partial

from tactilecal.cli._common import info, progress_for
from tactilecal.cli._library_options import add_option
from tactilecal.cli._outputs import add_output
from tactilecal.cli._types import positive_int


def register(sub):
    """Add the ``apply`` action to the ``dynamic`` command's actions."""
    a = sub.add_parser("apply", help="correct a record or every sensel of a recording",
                       description="INPUT a time-series CSV (output CSV with the same "
                                   "columns, every value column filtered) or a Tekscan "
                                   "recording / NetCDF (every sensel filtered along time, "
                                   "NetCDF out; NetCDF is streamed in chunks).")
    a.add_argument("filter", metavar="FILTER.json")
    a.add_argument("input", metavar="INPUT")
    add_output(a, "--out", kind=_kind, required=True, metavar="OUTPUT")
    a.defer(_add_options)  # defaults read from the library: imported when used
    a.set_defaults(func=run)


def _add_options(a):
    from tactilecal.dynamic import filter_recording

    add_option(a, "--chunk-frames", filter_recording, "chunk_frames", type=positive_int,
               help="frames per chunk when streaming NetCDF")
    add_option(a, "--causal", filter_recording, "causal",
               help="apply a rational filter's causal inverse (IIR, second-order sections; "
                    "streaming) instead of the offline one over the whole record; a "
                    "zero-phase (log) filter has no causal form")
    add_option(a, "--method", filter_recording, "method",
               help="auto: multirate when the correction is band-limited well below "
                    "Nyquist, else direct; direct: the FIR at the full rate")
    add_option(a, "--dtype", filter_recording, "dtype", choices=("float64", "float32"),
               help="type of the corrected values (float32 halves the output and is the "
                    "fastest path for a float32 recording)")


def _kind(args):
    """Return the output's kind: a CSV for a time-series input, else NetCDF."""
    from tactilecal.io import recording_format

    try:
        return "csv" if recording_format(args.input) is None else "netcdf"
    except (OSError, ValueError):  # a missing input: the command says so when it reads it
        return "csv"


def run(args):
    """Run ``tactilecal dynamic apply``."""
    from tactilecal._progress import dask_progress
    from tactilecal.dynamic import CorrectionFilter, filter_recording, filter_timeseries_csv
    from tactilecal.io import recording_format, write_netcdf

    filt = CorrectionFilter.from_json(args.filter)
    options = {"method": args.method, "causal": args.causal, "dtype": args.dtype,
               "progress": partial(progress_for(args), desc="filtering")}
    if recording_format(args.input) is None:  # a time-series CSV
        columns, rows = filter_timeseries_csv(filt, args.input, args.out, **options)
        what = f"{columns} column(s) x {rows} rows"
    else:
        out = filter_recording(filt, args.input, chunk_frames=args.chunk_frames, **options)
        with dask_progress(desc="filtering", quiet=args.quiet or out.chunks is None):
            write_netcdf(out, args.out, overwrite=args.overwrite)
        what = f"{out.shape[0]} frames x {out[0].size} sensels{_jitter(out.attrs)}"
    info(args, f"{args.input}: {what} corrected with {args.filter} -> {args.out}")
    return 0


def _jitter(attrs):
    if attrs["time_jitter_s"] * attrs["sampling_rate_hz"] <= 0.01:
        return ""
    return (f" (frame times up to {attrs['time_jitter_s']:.3g} s off a uniform "
            f"{attrs['sampling_rate_hz']:.6g} Hz grid: filtered at that mean rate)")
