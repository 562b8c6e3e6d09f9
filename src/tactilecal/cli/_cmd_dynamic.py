"""``tactilecal dynamic fit|apply|evaluate``: dynamic calibration (Gillis 2013, section 4)."""

import sys

from tactilecal._atomic import make_folder
from tactilecal.cli._common import info, positive_int, print_json, progress


def register(subparsers):
    """Add the ``dynamic`` command and its ``fit``, ``apply`` and ``evaluate`` actions."""
    p = subparsers.add_parser(
        "dynamic", help="dynamic calibration: fit, apply and evaluate a correction filter",
        description="Dynamic calibration of Gillis (2013): fit Y = A log(f + 1) + 1 to "
                    "|reference(f)| / |sensor(f)| on a sine sweep, correct records with the "
                    "zero-phase filter, and evaluate it on blind tests.")
    sub = p.add_subparsers(dest="action", metavar="ACTION", required=True)

    f = sub.add_parser("fit", help="fit a filter on a sweep (FILTER.json out)",
                       description="SENSOR and REFERENCE are time-series CSVs (time, value); "
                                   "SENSOR may also be a Tekscan recording or NetCDF, whose "
                                   "frames are summed. Records may have different rates "
                                   "and start times: they are aligned first.")
    f.add_argument("sensor", metavar="SENSOR")
    f.add_argument("reference", metavar="REFERENCE")
    f.add_argument("--out", required=True, metavar="FILTER.json")
    f.add_argument("--json", action="store_true", help="print the result as JSON")
    f.add_argument("--model", default="auto",
                   choices=["auto", "log", "log10", "log-quadratic", "rational", "wiener"],
                   help="auto (default): of log, rational and wiener, the simplest that "
                        "predicts held-out bins within 10 %% of the best or to 1 %%; log: "
                        "natural log (MATLAB's log); log10: decimal log; log-quadratic: Y = A "
                        "L + B L^2 + 1, L = ln(f + 1); rational: the complex response's poles "
                        "and zeros (orders 1-4), undone with their phase; wiener: the measured "
                        "complex correction, shrunk where it is within its random error")
    f.add_argument("--band", nargs=2, type=float, metavar=("LO", "HI"),
                   help="fit only LO..HI Hz; also the calibrated band (default: the "
                        "coherent bins)")
    f.add_argument("--method", default="h2", choices=["h2", "h1", "ratio"],
                   help="transfer-function estimator (default h2)")
    f.add_argument("--outside", default="taper", choices=["taper", "hold"],
                   help="gain above the band: taper to 1 (default) or hold")
    f.add_argument("--force", action="store_true",
                   help="write the filter even when the model explains less than 90 %% of "
                        "the complex response (marked forced in FILTER.json)")
    f.set_defaults(func=run_fit)

    a = sub.add_parser("apply", help="correct a record or every sensel of a recording",
                       description="INPUT a time-series CSV (output CSV with the same "
                                   "columns, every value column filtered) or a Tekscan "
                                   "recording / NetCDF (every sensel filtered along time, "
                                   "NetCDF out; NetCDF is streamed in chunks).")
    a.add_argument("filter", metavar="FILTER.json")
    a.add_argument("input", metavar="INPUT")
    a.add_argument("--out", required=True, metavar="OUTPUT")
    a.add_argument("--chunk-frames", type=positive_int, default=65536,
                   help="frames per chunk when streaming NetCDF (default 65536)")
    a.add_argument("--causal", action="store_true",
                   help="apply a rational filter's causal inverse (IIR, second-order "
                        "sections; streaming) instead of the offline one over the whole "
                        "record; a zero-phase (log) filter has no causal form")
    a.add_argument("--method", default="auto", choices=["auto", "direct"],
                   help="auto (default): multirate when the correction is band-limited "
                        "well below Nyquist, else direct; direct: the FIR at the full rate")
    a.set_defaults(func=run_apply)

    e = sub.add_parser("evaluate", help="error before/after correction, figures",
                       description="Amplitude error against frequency and RMS error of the "
                                   "dynamic part before and after correction; with --out, "
                                   "evaluation.json and the figures (thesis Figs 4.9-4.14).")
    e.add_argument("filter", metavar="FILTER.json")
    e.add_argument("sensor", metavar="SENSOR")
    e.add_argument("reference", metavar="REFERENCE")
    e.add_argument("--json", action="store_true", help="print the result as JSON")
    e.add_argument("--out", metavar="DIR", help="folder for evaluation.json and PNG figures")
    e.set_defaults(func=run_evaluate)


def _bar(args, desc):
    quiet = getattr(args, "quiet", False)
    return lambda blocks, total=None: progress(blocks, total=total, desc=desc, quiet=quiet)


def run_fit(args):
    """Run ``tactilecal dynamic fit``."""
    from tactilecal.dynamic import fit_filter, read_record

    sensor, reference = read_record(args.sensor), read_record(args.reference)
    filt = fit_filter(sensor, reference, model=args.model, band_hz=args.band,
                      method=args.method, outside=args.outside, force=args.force)
    if filt.forced:
        print(f"warning: written with --force: {filt.forced}", file=sys.stderr)
    filt.save(args.out)
    if args.json:
        print_json(filt.to_dict())
    else:
        print(filt.fit.summary())
        if "rational" in filt.fit.excluded:
            print(filt.fit.excluded["rational"])
        print(f"model choice: {filt.fit.excluded.get('model_choice', args.model)}")
        print(f"lag_s = {filt.lag_s:.6g} (added to {args.reference}'s times; clock offset, "
              f"without the sensor's own delay), static factor "
              f"{filt.fit.excluded['static_factor']:.6g}")
        print(filt.summary())
    info(args, f"filter written to {args.out}")
    return 0


def _apply_csv(filt, args):
    import numpy as np
    import pandas as pd
    import xarray as xr

    from tactilecal._atomic import atomic_path
    from tactilecal.dynamic import apply_filter
    from tactilecal.io import read_timeseries

    series = read_timeseries(args.input)  # checks the time column, units, numbers
    table = pd.read_csv(args.input, encoding="utf-8-sig", skipinitialspace=True)
    table.columns = [str(c).strip() for c in table.columns]
    time_col = series.attrs["time_column"]
    value_cols = [c for c in table.columns
                  if c != time_col and pd.api.types.is_numeric_dtype(table[c])]
    data = xr.DataArray(table[value_cols].to_numpy(float), dims=("time", "column"),
                        coords={"time": series["time"].values},
                        attrs={"source": args.input})
    out = apply_filter(data, filt, progress=_bar(args, "filtering"), method=args.method,
                       causal=args.causal)
    table[value_cols] = np.asarray(out.values)
    with atomic_path(args.out) as tmp:
        table.to_csv(tmp, index=False, float_format="%.10g")
    return f"{len(value_cols)} column(s) x {len(table)} rows"


def _apply_recording(filt, args):
    from tactilecal.dynamic import apply_filter
    from tactilecal.io import open_recording, recording_format, write_netcdf

    lazy = recording_format(args.input) in ("netcdf", "zarr")
    data = open_recording(args.input, chunks=args.chunk_frames if lazy else None)
    if lazy and data.dims and data.dims[0] in data.chunksizes:
        data = data.chunk({data.dims[0]: args.chunk_frames})
    out = apply_filter(data, filt, progress=_bar(args, "filtering"), method=args.method,
                       causal=args.causal)
    if out.chunks is not None and not args.quiet:
        from dask.diagnostics import ProgressBar

        with ProgressBar(out=sys.stderr):
            write_netcdf(out, args.out)
    else:
        write_netcdf(out, args.out)
    jitter = (f" (frame times up to {out.attrs['time_jitter_s']:.3g} s off a uniform "
              f"{out.attrs['sampling_rate_hz']:.6g} Hz grid: filtered at that mean rate)"
              if out.attrs["time_jitter_s"] * out.attrs["sampling_rate_hz"] > 0.01 else "")
    return f"{out.shape[0]} frames x {out[0].size} sensels{jitter}"


def run_apply(args):
    """Run ``tactilecal dynamic apply``."""
    from tactilecal.dynamic import load_filter
    from tactilecal.io import recording_format

    filt = load_filter(args.filter)
    if recording_format(args.input) is None:
        what = _apply_csv(filt, args)
    else:
        what = _apply_recording(filt, args)
    info(args, f"{args.input}: {what} corrected with {args.filter} -> {args.out}")
    return 0


def _write_figures(ev, filt, folder):
    from tactilecal.dynamic import plot_error, plot_spectra, plot_time, plot_transfer

    figures = {"time.png": plot_time(ev), "spectra.png": plot_spectra(ev),
               "error.png": plot_error(ev), "transfer.png": plot_transfer(filt)}
    from tactilecal._atomic import atomic_path

    for name, fig in figures.items():
        with atomic_path(folder / name) as tmp:
            fig.savefig(tmp, dpi=120)
    return sorted(figures)


def run_evaluate(args):
    """Run ``tactilecal dynamic evaluate``."""
    import numpy as np

    from tactilecal._jsonutil import write_json
    from tactilecal.dynamic import evaluate, load_filter, read_record

    filt = load_filter(args.filter)
    ev = evaluate(filt, read_record(args.sensor), read_record(args.reference),
                  progress=_bar(args, "filtering"))
    result = ev.to_dict()
    result.update(filter=args.filter, sensor=args.sensor, reference=args.reference)
    if args.out:
        folder = make_folder(args.out, what="--out")
        result["figures"] = _write_figures(ev, filt, folder)
        write_json(folder / "evaluation.json", result)
    if args.json:
        print_json(result)
    else:
        print(ev.summary())
        if ev.f_hz.size:
            print(f"amplitude error over {ev.f_hz.size} coherent bins "
                  f"({ev.f_hz.min():g}..{ev.f_hz.max():g} Hz): median |error| "
                  f"{np.median(np.abs(ev.error_before_pct)):.3g} % before, "
                  f"{np.median(np.abs(ev.error_after_pct)):.3g} % after")
    return 0
