"""``tactilecal apply``: convert a raw recording to pressure with a calibration."""

from tactilecal.cli._common import info, warn_saturated
from tactilecal.cli._library_options import add_option
from tactilecal.cli._outputs import add_output


def register(subparsers):
    """Add the ``apply`` command."""
    p = subparsers.add_parser(
        "apply", help="apply a calibration to a raw recording (NetCDF out)",
        description="Convert RECORDING (Tekscan ASCII, NetCDF or Zarr, raw) to pressure or force "
                    "per sensel with CAL.json and write a compressed NetCDF file carrying the "
                    "calibration (attributes calibration_method, calibration_json). The "
                    "values are stored as float32 (attribute stored_dtype): each is one of "
                    "the 256 values of the law at a raw reading, and 7 significant digits "
                    "are far finer than any calibration.")
    p.add_argument("calibration", metavar="CAL.json")
    p.add_argument("recording", metavar="RECORDING")
    add_output(p, "--out", kind="netcdf", required=True, metavar="OUT.nc")
    p.defer(_add_options)  # defaults read from the library: imported when used
    p.set_defaults(func=run)


def _add_options(p):
    from tactilecal.calibration import CalibrationResult

    add_option(p, "--units", CalibrationResult.apply, "units",
               "output unit: a pressure (kPa, MPa, Pa, psi, bar, mmHg...) or a force per "
               "sensel (N, kN, kgf, lbf)")


def run(args):
    """Run ``tactilecal apply``."""
    import tactilecal.analysis  # noqa: F401 - registers recording.tactile
    from tactilecal.calibration import CalibrationResult
    from tactilecal.io import open_recording, write_netcdf

    result = CalibrationResult.from_json(args.calibration)
    recording = open_recording(args.recording)
    out = result.apply(recording, units=args.units)
    write_netcdf(out, args.out, compress=True, dtype="float32",  # from raw readings
                 overwrite=args.overwrite)
    counts, _ = recording.tactile.saturated_sensels()
    n_saturated = int((counts > 0).sum())
    if n_saturated:
        warn_saturated(n_saturated, recording.sizes["frame"], args.recording)
    info(args, f"{args.recording}: {out.sizes['frame']} frames calibrated with "
               f"{result.method} ({args.units}) -> {args.out}")
    return 0
