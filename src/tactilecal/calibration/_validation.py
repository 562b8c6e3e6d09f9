"""What :func:`tactilecal.calibration.validate` returns: points and scores, a saved result."""

from dataclasses import dataclass, field

from tactilecal._jsonutil import to_jsonable, to_python
from tactilecal._result import SavedResult
from tactilecal._validate import check_type, require_keys

__all__ = ["ValidationResult"]

#: The keys of the JSON (``validate --json`` prints it).
KEYS = ("points", "summary")


@dataclass(repr=False, eq=False)
class ValidationResult(SavedResult):
    """A calibration's predicted loads against the applied loads of (held-out) points.

    Every value is a plain Python ``float``, ``int``, ``bool``, ``str`` or ``None`` (NaN
    stays a float in Python, null in the JSON). Saved as ``"format": "tactilecal-validation/1"``.

    Attributes
    ----------
    points : list of dict
        One row per point: file, frame, load_N, predicted_N, error_pct, saturated,
        predicted_is_lower_bound, label (and predicted_low_N, predicted_high_N when the
        calibration has a prediction interval).
    metrics : dict
        The scores over the points summarised (the ``"summary"`` key): n, within_3pct,
        within_5pct, within_10pct (fractions in 0..1), median_abs_error_pct,
        max_abs_error_pct, n_saturated_excluded, calibration_method (and
        interval_coverage).
    """

    FORMAT_KIND = "validation"
    DESCRIPTION = "a validation JSON"

    points: list = field(default_factory=list)
    metrics: dict = field(default_factory=dict)

    def __post_init__(self):
        self.points = to_python(list(self.points))
        self.metrics = to_python(dict(self.metrics))

    # ---------------------------------------------------------------- text
    def summary(self):
        """One line: how many points, the shares within 5 % and 10 %, median and max error."""
        m = self.metrics
        return (f"n = {m['n']} (saturated left out: {m['n_saturated_excluded']}): "
                f"{m['within_5pct']:.1%} within 5 %, {m['within_10pct']:.1%} within 10 %, "
                f"median |error| {m['median_abs_error_pct']:.2f} %, "
                f"max {m['max_abs_error_pct']:.2f} %")

    def _repr_fields(self):
        keys = ("calibration_method", "n", "within_5pct", "within_10pct",
                "median_abs_error_pct", "max_abs_error_pct")
        return [("points", len(self.points))] + [(k, self.metrics.get(k)) for k in keys]

    # ---------------------------------------------------------------- JSON
    def _to_dict(self):
        return to_jsonable({"points": self.points, "summary": self.metrics})

    @classmethod
    def _from_dict(cls, data, source):
        require_keys(data, KEYS, source, expected=cls.DESCRIPTION)
        points = check_type(data["points"], list, f"key 'points' of {source}",
                            expected="a list of points")
        for k, row in enumerate(points):
            check_type(row, dict, f"key 'points' of {source}, entry {k}",
                       expected="an object")
        metrics = check_type(data["summary"], dict, f"key 'summary' of {source}",
                             expected="an object")
        require_keys(metrics, ("n", "within_5pct", "within_10pct", "median_abs_error_pct",
                               "max_abs_error_pct", "n_saturated_excluded"),
                     f"key 'summary' of {source}", expected="the validation scores")
        return cls(points=points, metrics=metrics)
