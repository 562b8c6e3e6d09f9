"""``tactilecal simulate``: write synthetic sessions with their known truth.

``tactilecal simulate deadweight OUTDIR`` writes a dead-weight calibration session (one I-Scan
ASCII file per patch, ``manifest.csv``, ``truth.json``); ``tactilecal simulate ramp-hold
OUTDIR`` writes a loading-machine recording, its load-cell CSV and ``truth.json``.
"""

from collections import Counter

from tactilecal.cli._common import (
    info,
    non_negative_int,
    positive_float,
    positive_int,
    print_json,
    share,
)

__all__ = ["register", "run_deadweight", "run_ramp_hold", "scaled_sensor"]

_REF_A_N = 0.0035
"""Default law: A_N = 0.0035 N on a 5051 sensel (1.27 mm pitch, Zvyagin 2022 Table 2)."""


def register(subparsers):
    """Add the ``simulate`` command and its ``deadweight`` and ``ramp-hold`` sub-commands."""
    parser = subparsers.add_parser(
        "simulate", help="write synthetic sessions with known truth",
        description="Write synthetic tactile-sensor sessions whose truth is known.")
    sub = parser.add_subparsers(dest="simulate_command", metavar="KIND", required=True)
    dw = sub.add_parser(
        "deadweight", help="dead-weight calibration session (Zvyagin 2022)",
        description="Write a dead-weight calibration session as I-Scan ASCII files, one per "
                    "patch, plus manifest.csv (file, frame, mass_kg, pad_mass_g, label) and "
                    "truth.json.")
    dw.add_argument("outdir", metavar="OUTDIR", help="output folder (created if missing)")
    dw.add_argument("--patches", type=positive_int, default=150, help="number of patches (150)")
    _common_options(dw)
    dw.add_argument("--saturated-share", type=share, default=0.0,
                    help="share of patches with a saturated reading (0)")
    dw.set_defaults(func=run_deadweight)
    rh = sub.add_parser(
        "ramp-hold", help="ramp-and-hold loading-machine session (Gillis 2013)",
        description="Write a ramp-and-hold recording (recording.csv, I-Scan ASCII), the load "
                    "cell's record (loadcell.csv, header 'Time (s),Load (N)') and truth.json.")
    rh.add_argument("outdir", metavar="OUTDIR", help="output folder (created if missing)")
    _common_options(rh)
    rh.add_argument("--hold", type=positive_float, default=3.0, help="hold time per level in s (3)")
    rh.add_argument("--ramp", type=positive_float, default=2.0, help="transition time in s (2)")
    rh.add_argument("--frame-rate", type=positive_float, default=100.0,
                    help="sensor rate in Hz (100)")
    rh.add_argument("--loadcell-rate", type=positive_float, default=500.0,
                    help="load-cell rate in Hz (500)")
    rh.set_defaults(func=run_ramp_hold)


def _common_options(parser):
    parser.add_argument("--seed", type=non_negative_int, default=0, help="random seed (0)")
    parser.add_argument("--model", default="5051",
                        help="sensor model (5051); A_N is scaled by its sensel area so every "
                             "model has the 5051's pressure per raw count")
    parser.add_argument("--json", action="store_true", help="print the summary as JSON")


def scaled_sensor(model, seed):
    """Return ``make_sensor(model)`` with ``A_N`` scaled to the 5051's pressure per count.

    ``A_N = 0.0035 N * sensel_area_mm2 / 1.6129 mm2``, so a 9500 (25.8 mm2 sensels) reads
    the same raw value as a 5051 under the same pressure instead of saturating.
    """
    from tactilecal.sensors import get_sensor
    from tactilecal.simulate import make_sensor, sensor_geometry

    area_mm2 = sensor_geometry(model)[5]
    reference_mm2 = get_sensor("5051").sensel_area_mm2
    return make_sensor(model, A_N=_REF_A_N * area_mm2 / reference_mm2, seed=seed)


def run_deadweight(args):
    """Write the dead-weight session and print what was written."""
    from tactilecal.simulate import deadweight_session

    session = deadweight_session(scaled_sensor(args.model, args.seed),
                                 n_patches=args.patches, saturated_share=args.saturated_share,
                                 seed=args.seed)
    info(args, f"writing {len(session)} recordings to {args.outdir} ...")
    manifest = session.write(args.outdir)
    combos = Counter(f"{m:g} kg on {s:d} cm" for m, s in zip(session.mass_kg,
                                                             session.pad_side_cm, strict=True))
    summary = {"manifest": str(manifest), "truth": str(manifest.parent / "truth.json"),
               "recordings": len(session), "sensor": session.sensor.sensor_type,
               "A_N": session.sensor.A_N, "b": session.sensor.b,
               "saturated_patches": int(session.saturated.sum()),
               "blank_frame_rows": int(session.blank_frame.sum()),
               "patches_by_load": dict(sorted(combos.items()))}
    _print(args, summary)
    return 0


def run_ramp_hold(args):
    """Write the ramp-and-hold session and print what was written."""
    from tactilecal.simulate import ramp_hold

    session = ramp_hold(scaled_sensor(args.model, args.seed), hold_s=args.hold,
                        ramp_s=args.ramp, frame_rate_hz=args.frame_rate,
                        loadcell_rate_hz=args.loadcell_rate, seed=args.seed)
    info(args, f"writing {session.raw.sizes['frame']} frames to {args.outdir} ...")
    paths = session.write(args.outdir)
    summary = {**{k: str(v) for k, v in paths.items()},
               "frames": session.raw.sizes["frame"], "loadcell_samples": session.loadcell.size,
               "loadcell_start_offset_s": session.loadcell_start_offset_s,
               "loads_N": session.loads_N.tolist()}
    _print(args, summary)
    return 0


def _print(args, summary):
    if args.json:
        print_json(summary)
        return
    width = max(map(len, summary))
    for key, value in summary.items():
        if isinstance(value, dict):
            print(f"{key}:")
            for k, v in value.items():
                print(f"  {k:<{width}}  {v}")
        else:
            print(f"{key:<{width}}  {value}")
