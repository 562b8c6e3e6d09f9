"""Typed parts of a dynamic fit that a filter keeps: how its model was chosen, amplitude check.

Both are plain records with a one-line :meth:`summary`, a JSON dict round trip and value
equality (arrays compared element by element, NaN equal to NaN where it means "unknown").
"""

from dataclasses import dataclass, field, fields

import numpy as np

from tactilecal._errors import TactilecalError
from tactilecal._jsonutil import to_jsonable
from tactilecal._validate import check_number, check_type, require_keys

__all__ = ["ModelChoice", "AmplitudeCheck", "same_values"]


def same_values(a, b):
    """Return True when ``a`` and ``b`` hold the same JSON-ready values (NaN is None)."""
    return to_jsonable(a) == to_jsonable(b)


class _ByValue:
    """Equality by the JSON-ready values of :meth:`to_dict` (arrays, NaN as unknown)."""

    def __eq__(self, other):
        if type(other) is not type(self):
            return NotImplemented
        return same_values(self.to_dict(), other.to_dict())

    __hash__ = None


def _number(data, name, where, **bounds):
    value = check_number(data.get(name), f"key '{name}' of {where}", allow_none=True, **bounds)
    return float("nan") if value is None else float(value)


def _scores(data, name, where):
    """Return a ``{label: number}`` object of ``data`` (>= 0, or null for a failed fit)."""
    value = check_type(data.get(name, {}), dict, f"key '{name}' of {where}",
                       expected="an object of held-out errors")
    return {str(k): _number(value, k, f"{name} of {where}", minimum=0.0) for k in value}


@dataclass(eq=False)
class ModelChoice(_ByValue):
    """How ``fit_filter`` chose the model of a filter (held-out error of each candidate).

    Attributes
    ----------
    chosen : str
        The model the filter uses (``"log10"``, ``"rational"``, ``"wiener"``, ...).
    scores : dict
        ``{candidate: held-out error}`` (RMS relative error of the correction on held-out
        blocks of bins, :func:`~tactilecal.dynamic._ratfit.held_out_score`).
    refused : dict
        ``{candidate: why}`` for candidates tried before the chosen one and refused.
    structures : dict
        ``{rational structure: held-out error}`` of every structure tried.
    rational : str
        The fitted rational model in words (empty when none was fitted).
    delay_s : float
        The chosen model's delay, fitted jointly with it (the clock offset is the
        alignment's lag minus it).
    r2_complex : float
        Share of the complex correction the chosen model explains (wiener: of the
        held-out bins; NaN when unknown).
    notes : tuple of str
        Candidates that could not be fitted, and why.
    """

    chosen: str
    scores: dict = field(default_factory=dict)
    refused: dict = field(default_factory=dict)
    structures: dict = field(default_factory=dict)
    rational: str = ""
    delay_s: float = 0.0
    r2_complex: float = float("nan")
    notes: tuple = ()

    def summary(self):
        """Return the choice as one readable line."""
        scores = ", ".join(f"{name} {value:.2%}" for name, value in self.scores.items())
        text = f"held-out error {scores} -> {self.chosen}" if scores else self.chosen
        if self.refused:
            text += "; refused first: " + "; ".join(f"{k}: {v}" for k, v in self.refused.items())
        if self.notes:
            text += "; " + "; ".join(self.notes)
        return text

    def to_dict(self):
        """Return the JSON-ready dict (FILTER.json ``fit.model_choice``)."""
        return to_jsonable({"chosen": self.chosen, "scores": self.scores,
                            "refused": self.refused, "structures": self.structures,
                            "rational": self.rational, "delay_s": self.delay_s,
                            "r2_complex": self.r2_complex, "notes": list(self.notes)})

    @classmethod
    def from_dict(cls, data, where="model_choice"):
        """Rebuild from :meth:`to_dict`, checking every key (messages name ``where``)."""
        check_type(data, dict, where, expected="an object")
        require_keys(data, ("chosen",), where, expected="a model choice")
        refused = check_type(data.get("refused", {}), dict, f"key 'refused' of {where}",
                             expected="an object of reasons")
        notes = check_type(data.get("notes", []), list, f"key 'notes' of {where}",
                           expected="a list of texts")
        return cls(chosen=str(check_type(data["chosen"], str, f"key 'chosen' of {where}",
                                         expected="a model name")),
                   scores=_scores(data, "scores", where),
                   refused={str(k): str(v) for k, v in refused.items()},
                   structures=_scores(data, "structures", where),
                   rational=str(data.get("rational") or ""),
                   delay_s=_number(data, "delay_s", where, minimum=-1.0, maximum=1.0),
                   r2_complex=_number(data, "r2_complex", where, maximum=1.0),
                   notes=tuple(str(n) for n in notes))


@dataclass(eq=False)
class AmplitudeCheck(_ByValue):
    """Transfer functions of sweeps at different amplitudes, compared within their error bars.

    Attributes
    ----------
    amplitudes_N : tuple of float
        Each sweep's load amplitude (``sqrt(2)`` x the median of the absolute dynamic part
        of its load-cell record: a sine's amplitude), largest first.
    f_hz : numpy.ndarray
        Bins coherent in the largest and the smallest sweep, compared.
    difference : numpy.ndarray
        ``|C_small - C_large| / |C_large|`` per bin (relative difference of the corrections).
    z : numpy.ndarray
        That difference over its standard error (both sweeps' random errors).
    rms_difference : float
        RMS of ``difference``.
    rms_z : float
        RMS of ``z`` (about 1 for a linear sensor).
    depends : bool
        The responses differ beyond their error bars (``rms_z > MAX_RMS_Z``) by a material
        amount (``rms_difference > MATERIAL_ERROR``): one linear filter cannot correct it.
    """

    amplitudes_N: tuple
    f_hz: np.ndarray
    difference: np.ndarray
    z: np.ndarray
    rms_difference: float
    rms_z: float
    depends: bool

    def summary(self):
        """Return the comparison as one readable line."""
        amps = " and ".join(f"{a:.3g} N" for a in self.amplitudes_N)
        if not self.f_hz.size:
            return f"sweeps at {amps}: no bin is coherent in both; not compared"
        k = int(np.argmax(self.difference))
        verdict = ("the response depends on the amplitude" if self.depends else
                   "no material dependence on the amplitude")
        return (f"sweeps at {amps} amplitude differ by {self.rms_difference:.2%} RMS (up to "
                f"{self.difference[k]:.2%} at {self.f_hz[k]:.4g} Hz), {self.rms_z:.3g} times "
                f"their error bars over {self.f_hz.size} bins: {verdict}")

    def to_dict(self):
        """Return the JSON-ready dict (FILTER.json ``fit.amplitude``)."""
        return to_jsonable({"amplitudes_N": list(self.amplitudes_N), "f_hz": self.f_hz,
                            "difference": self.difference, "z": self.z,
                            "rms_difference": self.rms_difference, "rms_z": self.rms_z,
                            "depends": self.depends})

    @classmethod
    def from_dict(cls, data, where="amplitude"):
        """Rebuild from :meth:`to_dict`, checking every key (messages name ``where``)."""
        from tactilecal._validate import check_numbers

        check_type(data, dict, where, expected="an object")
        names = [f.name for f in fields(cls)]
        require_keys(data, names, where, expected="an amplitude check")
        arrays = {k: np.asarray(check_numbers(data[k], f"key '{k}' of {where}"), float)
                  for k in ("f_hz", "difference", "z")}
        if len({a.size for a in arrays.values()}) > 1:
            raise TactilecalError(f"key 'f_hz' of {where}: f_hz, difference and z of lengths "
                                  f"{[a.size for a in arrays.values()]}; expected one length")
        amplitudes = check_numbers(data["amplitudes_N"], f"key 'amplitudes_N' of {where}")
        return cls(tuple(float(a) for a in amplitudes), **arrays,
                   rms_difference=_number(data, "rms_difference", where, minimum=0.0),
                   rms_z=_number(data, "rms_z", where, minimum=0.0),
                   depends=bool(check_type(data["depends"], bool, f"key 'depends' of {where}",
                                           expected="true or false")))
