"""``tactilecal simulate``: write synthetic sessions with their known truth.

``tactilecal simulate deadweight OUTDIR`` writes a dead-weight calibration session (one I-Scan
ASCII file per patch, ``manifest.csv``, ``truth.json``); ``tactilecal simulate uniform
OUTDIR`` one recording per uniform pressure level (equilibration); ``tactilecal simulate ramp-hold
OUTDIR`` writes a loading-machine recording, its load-cell CSV and ``truth.json``;
``tactilecal simulate sweep|blind OUTDIR`` writes a dynamic session's sensor and load-cell
records (``sensor.csv``, ``reference.csv``) and ``truth.json``.
"""

from tactilecal.cli import _simulate_run
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
    dw.add_argument("--patches", type=positive_int, default=150, help="number of patches (150)")
    _common_options(dw)
    dw.add_argument("--saturated-share", type=share, default=0.0,
                    help="share of patches with a saturated reading (0)")
    dw.set_defaults(func=_simulate_run.run_deadweight)
    rh = sub.add_parser(
        "ramp-hold", help="ramp-and-hold loading-machine session (Gillis 2013)",
        description="Write a ramp-and-hold recording (recording.csv, I-Scan ASCII), the load "
                    "cell's record (loadcell.csv, header 'Time (s),Load (N)') and truth.json.")
    add_output(rh, "outdir", kind="session", metavar="OUTDIR",
               help="output folder (created if missing)")
    _common_options(rh)
    rh.add_argument("--hold", type=positive_float, default=3.0, help="hold time per level in s (3)")
    rh.add_argument("--ramp", type=positive_float, default=2.0, help="transition time in s (2)")
    rh.add_argument("--frame-rate", type=positive_float, default=100.0,
                    help="sensor rate in Hz (100)")
    rh.add_argument("--loadcell-rate", type=positive_float, default=500.0,
                    help="load-cell rate in Hz (500)")
    rh.set_defaults(func=_simulate_run.run_ramp_hold)
    add_uniform(sub, _common_options)
    for kind, what in (("sweep", "sine sweep 1-140 Hz (Gillis 2013, Table 4.2)"),
                       ("blind", "blind test: 20 random sine sets (Gillis 2013, Table 4.2)")):
        dyn = sub.add_parser(kind, help=f"dynamic session: {what}", description=(
            f"Write a {what} as the sensor's and the load cell's time series (sensor.csv, "
            "reference.csv: 'Time (s),force (N)') and truth.json (gain law, lag, sets)."))
        add_output(dyn, "outdir", kind="session", metavar="OUTDIR",
                   help="output folder (created if missing)")
        dyn.add_argument("--A", type=positive_float, default=0.11, dest="A",
                         help="true gain law Y = 1 + A log10(f + 1) (0.11)")
        dyn.add_argument("--seed", type=non_negative_int, default=0 if kind == "sweep" else 1,
                         help=f"random seed ({0 if kind == 'sweep' else 1})")
        dyn.add_argument("--json", action="store_true", help="print the summary as JSON")
        dyn.set_defaults(func=_simulate_run.run_dynamic, kind=kind)


def _common_options(parser):
    parser.add_argument("--seed", type=non_negative_int, default=0, help="random seed (0)")
    parser.add_argument("--model", default="5051",
                        help="sensor model (5051); A_N is scaled by its sensel area so every "
                             "model has the 5051's pressure per raw count")
    parser.add_argument("--json", action="store_true", help="print the summary as JSON")
