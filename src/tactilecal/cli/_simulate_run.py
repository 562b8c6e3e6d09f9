"""The runs of ``tactilecal simulate``: write the session, then say what was written."""

from collections import Counter

from tactilecal._units import N_PER_MM2_TO_KPA
from tactilecal.cli._common import info, print_aligned, print_json

__all__ = ["run_deadweight", "run_ramp_hold", "run_dynamic"]

_A_N_5051 = 0.0035  # N at reading 1 on a 5051 sensel (Zvyagin 2022, Table 2)


def _sensor(args):
    """Return ``make_sensor(--model)`` at the 5051's 2.17 kPa at reading 1 (so a 9500 too)."""
    from tactilecal.sensors import get_sensor  # here, not at every command's start-up
    from tactilecal.simulate import make_sensor

    a_kpa = _A_N_5051 * N_PER_MM2_TO_KPA / get_sensor("5051").sensel_area_mm2
    return make_sensor(args.model, A_kPa=a_kpa, seed=args.seed)


def run_deadweight(args):
    """Write the dead-weight session and print what was written."""
    from tactilecal.simulate import deadweight_session

    session = deadweight_session(_sensor(args), n_patches=args.n_patches,
                                 saturated_share=args.saturated_share, seed=args.seed)
    info(args, f"writing {len(session)} recordings to {args.outdir} ...")
    manifest = session.write(args.outdir, overwrite=args.overwrite)
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

    session = ramp_hold(_sensor(args), hold_s=args.hold_s, ramp_s=args.ramp_s,
                        frame_rate_hz=args.frame_rate_hz,
                        loadcell_rate_hz=args.loadcell_rate_hz, seed=args.seed)
    info(args, f"writing {session.raw.sizes['frame']} frames to {args.outdir} ...")
    paths = session.write(args.outdir, overwrite=args.overwrite)
    summary = {**{k: str(v) for k, v in paths.items()},
               "frames": session.raw.sizes["frame"], "loadcell_samples": session.loadcell.size,
               "loadcell_start_offset_s": session.loadcell_start_offset_s,
               "loads_N": session.loads_N.tolist()}
    _print(args, summary)
    return 0


def run_dynamic(args):
    """Write a sine sweep or a blind test (sensor and load-cell CSVs, truth) and say so."""
    from tactilecal.simulate import random_sine_sets, sine_sweep

    make = sine_sweep if args.kind == "sweep" else random_sine_sets
    session = make(A=args.A, seed=args.seed)
    paths = session.write(args.outdir, overwrite=args.overwrite)
    _print(args, {**{k: str(v) for k, v in paths.items()},
                  "sensor_samples": session.sensor.size,
                  "reference_samples": session.reference.size, "sets": len(session.sets),
                  "A": session.A, "log_base": session.log_base, "lag_s": session.lag_s})
    return 0


def _print(args, summary):
    """Print the summary as JSON or as aligned ``key  value`` lines."""
    if args.json:
        print_json(summary)
    else:
        print_aligned(summary)
