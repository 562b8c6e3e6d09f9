"""Command-line interface: ``tactilecal COMMAND ...``.

Each command lives in its own module ``_cmd_<name>.py`` in this package and defines
``register(subparsers)``, which adds its parser and sets ``func`` (a callable taking the
parsed arguments and returning an exit code). Commands are discovered by name, so adding
a command never touches this file.

Exit codes: 0 success, 1 failure (bad input: a :class:`tactilecal.TactilecalError` or an
:class:`OSError`, printed as one line; a bad flag value; or a bug in tactilecal, printed with
its traceback and a request to report it), 2 usage error (argparse: unknown flag, missing
argument). ``--debug`` shows the traceback of every error.
"""

import gc
import shlex
import sys
import traceback
import warnings
from functools import partial

from tactilecal._errors import TactilecalError
from tactilecal.cli._messages import BUG_REPORT, error_line, print_warning
from tactilecal.cli._outputs import check_outputs, silence_stdout
from tactilecal.cli._parser import BadFlagValue, build_parser

__all__ = ["main", "console_main", "build_parser"]


def console_main():
    """Run :func:`main` as the ``tactilecal`` command; return its exit code.

    The objects of the run are then left out of the collections of the interpreter's exit
    (:func:`gc.freeze`): nothing needs collecting once the command is done, and the exit
    no longer tours every object the command made (the modules, figures and arrays).
    """
    code = main()
    gc.freeze()
    return code


def main(argv=None):
    """Run the CLI; return the exit code (also used as the console-script entry point)."""
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except BadFlagValue as exc:
        print(exc, file=sys.stderr)
        return 1
    if args.command is None:
        parser.print_help(sys.stderr)
        return 2
    command = " ".join(filter(None, (args.command, getattr(args, "action", None))))
    try:
        check_outputs(args)
        args.command_line = shlex.join(["tactilecal", *(sys.argv[1:] if argv is None else argv)])
        with warnings.catch_warnings():  # the CLI shows warnings (one line), never raises them
            warnings.simplefilter("default")
            warnings.showwarning = partial(print_warning, command, parser)
            code = args.func(args)
    except BrokenPipeError:  # the reader went away (`tactilecal info F | head`): stop quietly
        silence_stdout()
        return 1
    except (TactilecalError, OSError) as exc:  # bad input: one line naming it
        if args.debug:
            traceback.print_exc()
        print(f"tactilecal {command}: error: {error_line(exc, parser)}", file=sys.stderr)
        return 1
    except Exception:  # noqa: BLE001 (a bug: say so, with everything needed to report it)
        traceback.print_exc()
        print(f"tactilecal {command}: internal error (a bug in tactilecal, not in your "
              f"input); {BUG_REPORT}", file=sys.stderr)
        return 1
    return 0 if code is None else int(code)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
