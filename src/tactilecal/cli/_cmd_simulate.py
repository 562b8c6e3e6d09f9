"""``tactilecal simulate``: write synthetic sessions with their known truth.

``tactilecal simulate deadweight OUTDIR`` writes a dead-weight calibration session (one I-Scan
ASCII file per patch, ``manifest.csv``, ``truth.json``); ``tactilecal simulate uniform
OUTDIR`` one recording per uniform pressure level (equilibration); ``tactilecal simulate ramp-hold
OUTDIR`` writes a loading-machine recording, its load-cell CSV and ``truth.json``;
``tactilecal simulate sweep|blind OUTDIR`` writes a dynamic session's sensor and load-cell
records (``sensor.csv``, ``reference.csv``) and ``truth.json``.
"""

from functools import partial

from tactilecal.cli import _simulate_run
from tactilecal.cli._library_options import add_option
from tactilecal.cli._outputs import add_output
from tactilecal.cli._simulate_uniform import add_uniform
from tactilecal.cli._types import non_negative_int, positive_float, positive_int, share

__all__ = ["register"]

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
    add_output(dw, "outdir", kind="session", metavar="OUTDIR",
               help="output folder (created if missing)")
    dw.defer(_deadweight_options)  # defaults read from the library: imported when used
    dw.set_defaults(func=_simulate_run.run_deadweight)
    rh = sub.add_parser(
        "ramp-hold", help="ramp-and-hold loading-machine session (Gillis 2013)",
        description="Write a ramp-and-hold recording (recording.csv, I-Scan ASCII), the load "
                    "cell's record (loadcell.csv, header 'Time (s),Load (N)') and truth.json.")
    add_output(rh, "outdir", kind="session", metavar="OUTDIR",
               help="output folder (created if missing)")
    rh.defer(_ramp_hold_options)
    rh.set_defaults(func=_simulate_run.run_ramp_hold)
    add_uniform(sub, _common_options)
    for kind, what in (("sweep", "sine sweep 1-140 Hz (Gillis 2013, Table 4.2)"),
                       ("blind", "blind test: 20 random sine sets (Gillis 2013, Table 4.2)")):
        dyn = sub.add_parser(kind, help=f"dynamic session: {what}", description=(
            f"Write a {what} as the sensor's and the load cell's time series (sensor.csv, "
            "reference.csv: 'Time (s),force (N)') and truth.json (gain law, lag, sets)."))
        add_output(dyn, "outdir", kind="session", metavar="OUTDIR",
                   help="output folder (created if missing)")
        dyn.add_argument("--json", action="store_true", help="print the summary as JSON")
        dyn.defer(partial(_dynamic_options, kind=kind))
        dyn.set_defaults(func=_simulate_run.run_dynamic, kind=kind)


def _deadweight_options(parser):
    from tactilecal.simulate import deadweight_session

    add_option(parser, "--patches", deadweight_session, "n_patches", "number of patches",
               type=positive_int, metavar="N")
    _common_options(parser, deadweight_session)
    add_option(parser, "--saturated-share", deadweight_session, "saturated_share",
               "share of patches with a saturated reading", type=share, metavar="SHARE")


def _ramp_hold_options(parser):
    from tactilecal.simulate import ramp_hold

    _common_options(parser, ramp_hold)
    add_option(parser, "--hold", ramp_hold, "hold_s", "hold time per level in s",
               type=positive_float, metavar="S")
    add_option(parser, "--ramp", ramp_hold, "ramp_s", "transition time in s",
               type=positive_float, metavar="S")
    add_option(parser, "--frame-rate", ramp_hold, "frame_rate_hz", "sensor rate in Hz",
               type=positive_float, metavar="HZ")
    add_option(parser, "--loadcell-rate", ramp_hold, "loadcell_rate_hz", "load-cell rate in Hz",
               type=positive_float, metavar="HZ")


def _dynamic_options(parser, kind):
    from tactilecal.simulate import DynamicSensor, random_sine_sets, sine_sweep

    add_option(parser, "--A", DynamicSensor, "A", "true gain law Y = 1 + A log10(f + 1)",
               type=positive_float)
    add_option(parser, "--seed", sine_sweep if kind == "sweep" else random_sine_sets, "seed",
               "random seed", type=non_negative_int)


def _common_options(parser, session):
    """``--seed`` (the default of ``session``, a simulate function), ``--model``, ``--json``."""
    from tactilecal.simulate import make_sensor

    add_option(parser, "--seed", session, "seed", "random seed", type=non_negative_int)
    add_option(parser, "--model", make_sensor, "model",
               "sensor model; A_N is scaled by its sensel area so every model has the 5051's "
               "pressure per raw count")
    parser.add_argument("--json", action="store_true", help="print the summary as JSON")
