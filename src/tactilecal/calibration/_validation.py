"""What :func:`tactilecal.calibration.validate` returns: points and scores, a saved result."""

from dataclasses import dataclass, field

from tactilecal._jsonutil import to_jsonable, to_python
from tactilecal._result import SavedResult
from tactilecal._text import number, share
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
        max_abs_error_pct, n_saturated_excluded, calibration_method, calibration_sha256
        (the calibration's fingerprint; and interval_coverage).

    Examples
    --------
    >>> from tactilecal.calibration import calibrate, points_from_frames, validate
    >>> from tactilecal.simulate import family_sessions
    >>> train, test = family_sessions("5051-sensor2", seed=1)
    >>> cal = calibrate(points_from_frames(train.raw, train.load_N), method="power")
    >>> check = validate(cal, points_from_frames(test.raw, test.load_N))
    >>> check.metrics["n"], check.metrics["n_saturated_excluded"], check.metrics["within_5pct"]
    (29, 7, 1.0)
    >>> round(check.metrics["median_abs_error_pct"], 2)
    0.78
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
        """Return the points, then one line of scores (what ``tactilecal validate`` prints).

        Examples
        --------
        >>> check = ValidationResult(
        ...     points=[{"file": "a.csv", "frame": 3, "load_N": 10.0, "predicted_N": 10.2,
        ...              "error_pct": 2.0, "saturated": False}],
        ...     metrics={"n": 1, "n_saturated_excluded": 0, "within_5pct": 1.0,
        ...              "within_10pct": 1.0, "median_abs_error_pct": 2.0,
        ...              "max_abs_error_pct": 2.0})
        >>> print(check.summary().splitlines()[-1])  # doctest: +NORMALIZE_WHITESPACE
        n = 1 (saturated left out: 0): 100.0 % within 5 %, 100.0 % within 10 %,
        median |error| 2 %, max 2 %
        """
        lines = [f"{'file':<28} {'frame':>6} {'load_N':>10} {'predicted_N':>12} {'error_%':>8}"]
        for p in self.points:
            flag = "  saturated" if p["saturated"] else ""
            lines.append(f"{str(p['file'])[:28]:<28} {p['frame']:>6} {number(p['load_N']):>10} "
                         f"{number(p['predicted_N']):>12} {number(p['error_pct']):>8}{flag}")
        m = self.metrics
        lines.append(f"n = {m['n']} (saturated left out: {m['n_saturated_excluded']}): "
                     f"{share(m['within_5pct'])} within 5 %, {share(m['within_10pct'])} within "
                     f"10 %, median |error| {number(m['median_abs_error_pct'])} %, "
                     f"max {number(m['max_abs_error_pct'])} %")
        return "\n".join(lines)

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
