"""Command-line flags made from the library's option dataclasses, so defaults live once.

A method's ``Options`` (and :class:`tactilecal.calibration.CommonOptions`) declare each
option with its default, help text and choices (:func:`tactilecal.calibration._fit.option`);
:func:`add_option_flags` turns every field into ``--<name>`` with that text and the default
read from the dataclass, and :func:`given_options` returns the flags the user gave, for the
library to apply over its own defaults.
"""

import argparse
import dataclasses
import types

from tactilecal._text import number

__all__ = ["add_option_flags", "given_options", "option_fields"]


def option_fields(classes):
    """Map each option name to ``[(owner label, dataclass field), ...]`` in order."""
    fields = {}
    for label, cls in classes.items():
        for f in dataclasses.fields(cls):
            fields.setdefault(f.name, []).append((label, f))
    return fields


def _kinds(annotation):
    """Return the non-None types an annotation allows (``int | None`` -> ``{int}``)."""
    args = annotation.__args__ if isinstance(annotation, types.UnionType) else (annotation,)
    return {a for a in args if a is not type(None)}


def _converter(kinds):
    """Return an argparse ``type`` for the annotation's kinds (a refused value exits 1)."""
    def convert(text):
        try:
            if tuple in kinds and ("," in text or kinds == {tuple}):
                return tuple(_scalar(item) for item in text.split(","))
            if kinds & {int, float} and not kinds & {str}:
                return int(text) if kinds == {int} else _scalar(text)
            return text
        except ValueError:
            expected = "comma-separated numbers" if tuple in kinds else \
                " or ".join(sorted(k.__name__ for k in kinds))
            raise argparse.ArgumentTypeError(f"{text!r}; expected {expected}") from None
    convert.checks_value = True
    convert.__name__ = "/".join(sorted(k.__name__ for k in kinds))
    return convert


def _scalar(text):
    text = text.strip()
    try:
        return int(text)
    except ValueError:
        return float(text)


def _default_text(value):
    if value is None:
        return "chosen by the method"
    if isinstance(value, tuple):
        return ",".join(number(v) for v in value)
    return number(value)


def _help(owners):
    """Return the flag's help: the option's text and each owner's default."""
    text = owners[0][1].metadata.get("help", "")
    if len(owners) == 1:
        default = _default_text(owners[0][1].default)
        text += "" if "(default" in text else f" (default {default})"
    else:
        text += " (default " + "; ".join(f"{label}: {_default_text(f.default)}"
                                         for label, f in owners) + ")"
    return text.replace("%", "%%")


def add_option_flags(parser, classes):
    """Add ``--<name>`` to ``parser`` for every field of the option ``classes``.

    Parameters
    ----------
    parser : argparse.ArgumentParser
    classes : dict
        ``{label: dataclass}``; a field several classes share (``objective``) is one flag
        whose help gives each class's default.

    Returns
    -------
    list of str
        The option names added.
    """
    fields = option_fields(classes)
    for name, owners in fields.items():
        kinds = set().union(*(_kinds(f.type) for _, f in owners))
        flag = "--" + name.replace("_", "-")
        metavar = owners[0][1].metadata.get("metavar")
        if owners[0][1].metadata.get("flag"):  # a flag that sets one choice
            flag, const = owners[0][1].metadata["flag"]
            parser.add_argument(flag, dest=name, action="store_const", const=const,
                                default=None, help=owners[0][1].metadata["help"])
            continue
        if kinds == {bool}:
            parser.add_argument(flag, dest=name, action="store_const", const=True,
                                default=None, help=_help(owners))
            continue
        choices = [c for _, f in owners for c in (f.metadata.get("choices") or ())
                   if c is not None]
        parser.add_argument(flag, dest=name, default=None, type=_converter(kinds),
                            choices=list(dict.fromkeys(choices)) or None, metavar=metavar,
                            help=_help(owners))
    return list(fields)


def given_options(args, names):
    """Return the options among ``names`` given on the command line (not None)."""
    return {name: getattr(args, name) for name in names if getattr(args, name) is not None}
