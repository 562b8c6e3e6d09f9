"""Output safety of the CLI: never replace an input; stop quietly when stdout goes away."""

import sys
from pathlib import Path

from tactilecal._errors import TactilecalError

__all__ = ["check_outputs", "silence_stdout"]


def check_outputs(args):
    """Refuse an output path that is one of the command's inputs (it would be replaced).

    Every string (or list of strings) among the parsed arguments that names an existing
    file counts as an input; the outputs are ``--out`` and ``OUTDIR``.
    """
    outputs = [getattr(args, key, None) for key in ("out", "outdir")]
    for out in filter(None, outputs):
        out_path = Path(out)
        if not out_path.exists():
            continue
        for key, value in vars(args).items():
            if key in ("out", "outdir"):
                continue
            for item in value if isinstance(value, list) else [value]:
                if isinstance(item, str) and Path(item).is_file() and \
                        out_path.resolve() == Path(item).resolve():
                    raise TactilecalError(f"--out {out} is the input {item}; expected a new path "
                                          "(the input would be replaced)")


def silence_stdout():
    """Point stdout at /dev/null so the interpreter's last flush does not fail again.

    The recipe of the Python documentation (signal module, "Note on SIGPIPE").
    """
    import os

    devnull = os.open(os.devnull, os.O_WRONLY)
    os.dup2(devnull, sys.stdout.fileno())
