"""The fit options of ``tactilecal calibrate``: flags made from the library's options.

Every option of :func:`tactilecal.calibration.calibrate` is a field of
:class:`tactilecal.calibration.CommonOptions` or of a method's ``Options``
(:data:`tactilecal.calibration.METHOD_OPTIONS`); the flags, their help and their defaults
are made from those fields (:mod:`tactilecal.cli._options`), and a flag not given leaves the
library's default.
"""

from tactilecal._errors import TactilecalError
from tactilecal.calibration import DEFAULT_METHOD, METHOD_OPTIONS, METHODS, CommonOptions
from tactilecal.cli._options import add_option_flags, given_options, option_fields

__all__ = ["add_fit_options", "fit_options"]

_METHOD_FIELDS = option_fields(METHOD_OPTIONS)


def add_fit_options(p):
    """Add the method, its options, the common options and the preprocessing flags to ``p``."""
    p.add_argument("--method", default=DEFAULT_METHOD, metavar="METHOD",
                   help=f"calibration method: {', '.join(METHODS)} (default {DEFAULT_METHOD})")
    add_option_flags(p, {"every method": CommonOptions})
    add_option_flags(p, METHOD_OPTIONS)
    p.add_argument("--mask-dead", action="store_true",
                   help="detect non-working sensels across the frames and leave them out")
    p.add_argument("--equilibration", metavar="EQ.json",
                   help="per-sensel gains from 'tactilecal equilibrate', applied first")


def fit_options(args):
    """Return the options given on the command line (absent flags: library defaults).

    Raises
    ------
    TactilecalError
        A method option given for a method that does not take it.
    """
    method_opts = given_options(args, _METHOD_FIELDS)
    for name in method_opts:
        owners = [label for label, _ in _METHOD_FIELDS[name]]
        if args.method not in owners:
            flag = "--" + name.replace("_", "-")
            raise TactilecalError(f"{flag} applies to --method {' or '.join(owners)}; not "
                                  f"{args.method!r}")
    return {**given_options(args, CommonOptions.names()), **method_opts}
