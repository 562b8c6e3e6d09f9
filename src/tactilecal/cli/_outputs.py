"""Output safety of the CLI: never replace a file it did not write; stop quietly on EPIPE.

A command declares each output with :func:`add_output` (``--out``, or a positional such as
``convert``'s ``OUT``) and what it writes there; :func:`check_outputs` runs before the
command: an existing output is refused unless ``--overwrite`` is given, and even then when it
is one of the command's inputs or does not look like an output of that command
(:func:`tactilecal._atomic.check_target`, :func:`tactilecal._atomic.check_folder`).
"""

import sys
from pathlib import Path

from tactilecal._atomic import OUTPUT_FOLDERS, check_folder, check_target
from tactilecal._errors import TactilecalError

__all__ = ["add_output", "check_outputs", "silence_stdout", "OVERWRITE_HELP"]

OVERWRITE_HELP = ("replace an existing output (never an input of the command, nor a file that "
                  "is not an output of this command)")
_HINT = "add --overwrite to replace it"


def add_output(parser, *flags, kind, sidecar=False, **kwargs):
    """Add an output argument and the shared ``--overwrite`` flag; return the argument.

    ``kind`` is a key of :data:`tactilecal._atomic.OUTPUT_KINDS` (a file) or of
    :data:`tactilecal._atomic.OUTPUT_FOLDERS` (a folder), or a callable ``kind(args)``
    returning one (an output whose kind depends on the input or its suffix). ``sidecar``:
    the command also writes the output's provenance JSON beside it
    (:func:`tactilecal._provenance.sidecar_path`).
    """
    action = parser.add_argument(*flags, **kwargs)
    entry = (action.dest, kind, sidecar)
    parser.set_defaults(outputs=(*(parser.get_default("outputs") or ()), entry))
    if not any(a.dest == "overwrite" for a in parser._actions):
        parser.add_argument("--overwrite", action="store_true", help=OVERWRITE_HELP)
    return action


def check_outputs(args):
    """Refuse outputs that would replace an input, or a file this command did not write."""
    for dest, kind, sidecar in getattr(args, "outputs", ()):
        out = getattr(args, dest, None)
        if not out:
            continue
        _refuse_input(dest, out, args)
        kind = kind(args) if callable(kind) else kind
        if kind in OUTPUT_FOLDERS:
            check_folder(out, overwrite=args.overwrite, hint=_HINT, **OUTPUT_FOLDERS[kind])
        else:
            check_target(out, overwrite=args.overwrite, kind=kind, hint=_HINT)
        if sidecar:
            from tactilecal._provenance import sidecar_path

            check_target(sidecar_path(out), overwrite=args.overwrite, kind="json", hint=_HINT)


def _refuse_input(dest, out, args):
    """Refuse an output that is one of the command's inputs (any other path argument)."""
    out_path = Path(out).resolve()
    outputs = {entry[0] for entry in getattr(args, "outputs", ())}
    for key, value in vars(args).items():
        if key in outputs:
            continue
        for item in value if isinstance(value, list) else [value]:
            if isinstance(item, str) and Path(item).exists() and \
                    Path(item).resolve() == out_path:
                flag = "--out" if dest == "out" else dest.upper()
                raise TactilecalError(f"{flag} {out} is the input {item}; expected a new path "
                                      "(the input would be replaced)")


def silence_stdout():
    """Point stdout at /dev/null so the interpreter's last flush does not fail again.

    The recipe of the Python documentation (signal module, "Note on SIGPIPE").
    """
    import os

    devnull = os.open(os.devnull, os.O_WRONLY)
    os.dup2(devnull, sys.stdout.fileno())
