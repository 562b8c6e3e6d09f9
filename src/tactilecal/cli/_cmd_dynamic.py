"""``tactilecal dynamic fit|apply|evaluate``: dynamic calibration (Gillis 2013, section 4).

One module per action (``_dynamic_fit``, ``_dynamic_apply``, ``_dynamic_evaluate``), each
with its ``register(actions)`` and ``run(args)``.
"""

from tactilecal.cli import _dynamic_apply, _dynamic_evaluate, _dynamic_fit


def register(subparsers):
    """Add the ``dynamic`` command and its ``fit``, ``apply`` and ``evaluate`` actions."""
    p = subparsers.add_parser(
        "dynamic", help="dynamic calibration: fit, apply and evaluate a correction filter",
        description="Dynamic calibration of Gillis (2013): fit a model of reference(f) / "
                    "sensor(f) (the thesis' Y = A log(f + 1) + 1, a rational response with "
                    "resonances, or the measured correction; each with a delay) on sine "
                    "sweeps, in the band where they carried coherent energy; correct records "
                    "with its filter, and evaluate it on blind tests at the fitted clock.")
    actions = p.add_subparsers(dest="action", metavar="ACTION", required=True)
    for action in (_dynamic_fit, _dynamic_apply, _dynamic_evaluate):
        action.register(actions)
