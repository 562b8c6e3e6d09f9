"""The calibration result: the law, the preprocessing, the per-point table, JSON round-trip."""

import warnings
from dataclasses import dataclass, field
from datetime import UTC, datetime

import numpy as np
import pandas as pd
import xarray as xr

from tactilecal._errors import TactilecalError
from tactilecal._jsonutil import dumps, to_jsonable
from tactilecal._result import SavedResult
from tactilecal._text import number, share
from tactilecal._units import N_PER_MM2_TO_KPA
from tactilecal._validate import check_number, check_type, require_keys
from tactilecal._version import __version__
from tactilecal.calibration import _plots
from tactilecal.calibration._lack_of_fit import LackOfFit
from tactilecal.calibration._models import MODELS, check_law, force_table, sensel_force
from tactilecal.calibration._sensels import Equilibration, NonWorkingSensels
from tactilecal.calibration._uncertainty import PredictionInterval
from tactilecal.calibration.methods.auto import Selection
from tactilecal.calibration.methods.zvyagin import ZvyaginResult

__all__ = ["CalibrationResult"]

POINT_COLUMNS = ["file", "frame", "load_N", "raw_sum", "loaded_cells", "saturated_cells",
                 "used", "reason", "predicted_N", "error_pct"]
REQUIRED_KEYS = ["method", "model", "params", "sensel_area_mm2", "saturation_pressure_kPa",
                 "points", "metrics", "options", "equilibration", "non_working_sensels",
                 "prediction_interval", "selection", "lack_of_fit", "diagnostics"]


@dataclass(repr=False, eq=False)
class CalibrationResult(SavedResult):
    """A fitted static calibration (force per sensel as a function of its raw reading).

    Saved as ``"format": "tactilecal-calibration/1"`` (:mod:`tactilecal._result`); two
    results compare equal (``==``) when everything but their creation time is equal.

    Attributes
    ----------
    method : str
        Calibration method (``"power"``, ``"linear"``, ``"zvyagin"``...).
    model : str
        Per-sensel law, a key of :data:`tactilecal.calibration._models.MODELS`. For
        ``"power"``, force per sensel in newtons = ``A * raw**b``.
    params : dict
        Fitted parameters.
    sensel_area_mm2 : float
        Area of one sensel (NaN when unknown).
    saturation_pressure_kPa : float
        Pressure at raw = 255 (NaN when the area is unknown).
    points : pandas.DataFrame
        One row per calibration point: file, frame, load_N, raw_sum, loaded_cells,
        saturated_cells, used, reason, predicted_N, error_pct, label, note.
    metrics : dict
        Fit quality over the used points (:func:`tactilecal.calibration._metrics.fit_metrics`,
        and ``n_points``).
    options : dict
        Every option the fit ran with, defaults included (those of
        :class:`tactilecal.calibration.CommonOptions` and of the method's ``Options``).
    equilibration : Equilibration or None
        Per-sensel gains applied to the frames before the fit; :meth:`apply` applies them to
        a recording first.
    non_working : NonWorkingSensels or None
        Sensels left out of the fit; :meth:`apply` masks them (NaN).
    prediction_interval : PredictionInterval or None
        The bootstrap prediction interval of a new patch's load (``n_interval_resamples``),
        used by :func:`tactilecal.calibration.validate`.
    selection : Selection or None
        How ``method="auto"`` chose ``method``: every candidate's held-out error, the
        choice and why (None for a method given by name).
    lack_of_fit : LackOfFit or None
        Whether the law describes its own patches (systematic error by load, drift over the
        acquisition order); ``flagged`` with one message per finding (None for a law that
        was not fitted here, such as a header's).
    diagnostics : dict
        What the method found on the way (costs, segments, Zvyagin's intermediates, a movie's
        alignment), JSON-ready; for people and reports: :meth:`apply` never reads it.
    provenance : dict
        Where it came from (:func:`tactilecal._provenance.provenance`): package version,
        the manifest and recordings with their SHA-256, the sensor type and serial from the
        export headers.
    method_result : ZvyaginResult or None
        The method's own result with every intermediate: the :class:`ZvyaginResult` for
        ``method="zvyagin"`` (rebuilt from ``diagnostics`` when the JSON is loaded), None
        for the other methods.

    Examples
    --------
    >>> import tactilecal as tc
    >>> from tactilecal.calibration import points_from_frames
    >>> frames = np.zeros((2, 3, 3)); frames[0, 1, 1] = 10; frames[1, 1, 1] = 20
    >>> cal = tc.calibrate(points_from_frames(frames, [1.0, 2.0]), method="linear")
    >>> cal.params, cal.predict_force(frames).tolist()
    ({'A': 0.1, 'b': 1.0}, [1.0, 2.0])
    """

    FORMAT_KIND = "calibration"
    DESCRIPTION = "a calibration JSON"

    method: str
    model: str
    params: dict
    sensel_area_mm2: float
    saturation_pressure_kPa: float
    points: pd.DataFrame
    metrics: dict
    options: dict = field(default_factory=dict)
    equilibration: Equilibration | None = None
    non_working: NonWorkingSensels | None = None
    prediction_interval: PredictionInterval | None = None
    selection: Selection | None = None
    lack_of_fit: LackOfFit | None = None
    diagnostics: dict = field(default_factory=dict)
    version: str = __version__
    created: str = field(default_factory=lambda: datetime.now(UTC).isoformat(timespec="seconds"))
    provenance: dict = field(default_factory=dict)
    method_result: ZvyaginResult | None = None

    # ------------------------------------------------------------------ predictions
    def force_table(self):
        """Force per sensel in newtons at raw = 0..255 (float64[256]).

        Examples
        --------
        >>> from tactilecal.calibration import calibrate, points_from_frames
        >>> frames = np.zeros((1, 2, 2)); frames[0, 0, 0] = 10
        >>> calibrate(points_from_frames(frames, [1.0]), method="linear").force_table()[:3]
        array([0. , 0.1, 0.2])
        """
        return force_table(self.model, self.params)

    def predict_sensel_force(self, raw):
        """Force on each sensel in newtons (same shape as ``raw``; NaN stays NaN).

        The equilibration gains and the non-working-sensel mask of the calibration (from
        ``tactilecal calibrate --equilibration/--mask-dead``) are applied first.

        Examples
        --------
        >>> from tactilecal.calibration import calibrate, points_from_frames
        >>> frames = np.zeros((2, 3, 3)); frames[0, 1, 1] = 10; frames[1, 1, 1] = 20
        >>> res = calibrate(points_from_frames(frames, [1.0, 2.0]), method="linear")
        >>> res.predict_sensel_force(frames)[1, 1, 1].round(6)
        np.float64(2.0)
        """
        return sensel_force(self.model, self.params, self._prepare_raw(raw))

    def _prepare_raw(self, raw):
        """Apply the calibration's equilibration gains and non-working mask, if it has them."""
        values = np.asarray(getattr(raw, "values", raw), dtype=float)
        if self.equilibration is not None:
            values = self.equilibration.apply(values)
        if self.non_working is not None and self.non_working.mask.any():
            values = np.where(self.non_working.mask, np.nan, values)
        return values

    def predict_force(self, raw):
        """Total force per frame in newtons (NaN sensels ignored).

        Parameters
        ----------
        raw : array_like or xarray.DataArray
            One frame (rows, cols) or frames (n, rows, cols).

        Returns
        -------
        float or numpy.ndarray
            A float for one frame, else an array (n,).

        Examples
        --------
        >>> from tactilecal.calibration import calibrate, points_from_frames
        >>> frames = np.zeros((1, 2, 2)); frames[0] = 10
        >>> calibrate(points_from_frames(frames, [4.0]), method="linear").predict_force(frames[0])
        4.0
        """
        force = self.predict_sensel_force(raw)
        if force.ndim == 2:
            return float(np.nansum(force))
        return np.nansum(force.reshape(force.shape[0], -1), axis=1)

    def predict_histograms(self, histograms):
        """Total force of frames given as 256-bin histograms (n, 256) -> (n,).

        Examples
        --------
        >>> from tactilecal.calibration import calibrate, points_from_frames
        >>> frames = np.zeros((1, 2, 2)); frames[0] = 10
        >>> cal = calibrate(points_from_frames(frames, [4.0]), method="linear")
        >>> h = np.zeros((1, 256)); h[0, 20] = 4
        >>> cal.predict_histograms(h)
        array([8.])
        """
        return np.asarray(histograms, dtype=float) @ self.force_table()

    # ------------------------------------------------------------------ apply
    def apply(self, recording, units="kPa"):
        """Convert a raw recording to pressure (or force per sensel).

        Parameters
        ----------
        recording : xarray.DataArray
            Raw recording in the data model (``units`` attribute ``raw``).
        units : str
            Output unit: any pressure unit of :func:`tactilecal._units.normalise_unit` (kPa,
            MPa, Pa, psi, bar, mmHg...) or a force unit (N, kN, kgf, lbf: the force on
            each sensel).

        Returns
        -------
        xarray.DataArray
            Same dims, coords and attributes, with ``units``, ``calibration_method`` and
            ``calibration_json`` set.

        Raises
        ------
        ValueError
            For an unknown unit, a recording that is not raw, a reading outside 0..255 (or
            not a number), or a missing/inconsistent sensel area.
        """
        from tactilecal._model import check_recording, usable_values
        from tactilecal._provenance import provenance_attr, provenance_of
        from tactilecal._units import force_to_N, normalise_unit, pressure_to_kPa, unit_kind

        source = recording.attrs.get("source", "")
        units = normalise_unit(units, where="units=")
        if unit_kind(units) not in ("pressure", "force"):
            raise TactilecalError(f"units={units!r} is a {unit_kind(units)} unit; expected a "
                                  "pressure (kPa, MPa, psi, bar...) or force (N, kN, lbf...) unit")
        # the data model's check; a recording made in memory without units is raw readings
        rec_units, _ = check_recording(recording.assign_attrs(
            units=recording.attrs.get("units", "raw")))
        if rec_units != "raw":
            raise TactilecalError(f"recording {source!r} has units {rec_units!r}; expected raw "
                                  "readings (units 'raw')")
        self._check_sensor(recording, source)
        if unit_kind(units) == "force":
            scale = 1.0 / force_to_N(1.0, units)
        else:
            scale = N_PER_MM2_TO_KPA / self._area_for(recording) / pressure_to_kPa(1.0, units)
        # apply_ufunc keeps a dask-backed recording lazy (chunk by chunk along frames; a
        # frame's sensels are one chunk)
        if recording.chunks is not None:
            recording = recording.chunk({"row": -1, "col": -1})
        out = xr.apply_ufunc(lambda raw: self.predict_sensel_force(raw) * scale,
                             usable_values(recording, "raw"),
                             input_core_dims=[["row", "col"]],
                             output_core_dims=[["row", "col"]], dask="parallelized",
                             output_dtypes=[float]).transpose(*recording.dims)
        # the pressure at raw 255 is this calibration's, not the header's: saturation
        # stays recognisable in the output (recording.tactile.saturated_sensels())
        out.attrs = {**recording.attrs, "units": units, "calibration_method": self.method,
                     "calibration_json": self.to_json_text(),
                     "saturation_pressure_kPa": float(self.saturation_pressure_kPa),
                     "provenance": provenance_attr(provenance_of([recording],
                                                                 options={"units": units}))}
        return out

    def _check_sensor(self, recording, source):
        """Refuse a recording of another sensel area; warn when its sensor type differs.

        A law in N per sensel does not transfer between sensel sizes; another sensor type
        of the same size (or the same type from another handle) may be a mistake, but it
        may also be intended, so it only warns.
        """
        rec_area = recording.attrs.get("sensel_area_mm2")
        if rec_area is not None and np.isfinite(self.sensel_area_mm2) and not np.isclose(
                float(rec_area), self.sensel_area_mm2, rtol=0.01):
            raise TactilecalError(f"recording {source!r}: sensel_area_mm2 = {rec_area} differs "
                                  f"from "
                                  f"the calibration's {self.sensel_area_mm2}; expected the same "
                                  "sensor model (a law per sensel does not transfer between sizes)")
        made_on = self.provenance.get("sensor_type")
        rec_type = recording.attrs.get("sensor_type")
        if isinstance(made_on, str) and rec_type is not None and str(rec_type) != made_on:
            warnings.warn(f"recording {source!r} is from a {rec_type} sensor, the calibration "
                          f"was made on a {made_on}: check that it applies", UserWarning,
                          stacklevel=3)

    def _area_for(self, recording):
        rec_area = recording.attrs.get("sensel_area_mm2")
        area = self.sensel_area_mm2
        if not np.isfinite(area):
            area = float("nan") if rec_area is None else float(rec_area)
        if not np.isfinite(area) or area <= 0:
            raise TactilecalError("sensel area unknown: neither the calibration nor the recording "
                                  "has sensel_area_mm2; expected a positive area to give pressures")
        return area

    # ------------------------------------------------------------------ figures
    plot_curve = _plots.plot_calibration_curve
    plot_points = _plots.plot_points
    plot_error_histogram = _plots.plot_error_histogram
    save_figures = _plots.save_figures

    # ------------------------------------------------------------------ reporting
    def summary(self):
        """Human-readable summary: the law, the points used, the preprocessing and metrics.

        The command line prints this text (``tactilecal calibrate``).

        Examples
        --------
        >>> from tactilecal.calibration import calibrate, points_from_frames
        >>> frames = np.zeros((2, 3, 3)); frames[0, 1, 1] = 10; frames[1, 1, 1] = 20
        >>> print(calibrate(points_from_frames(frames, [1.0, 2.0]), "linear").summary())
        ... # doctest: +ELLIPSIS
        Calibration method 'linear', model 'power'
          A = 0.1
          b = 1
          points used: 2 of 2
        ...
        """
        lines = [f"Calibration method {self.method!r}, model {self.model!r}"]
        if self.selection is not None:
            lines.extend(f"  {line}" for line in self.selection.lines())
        if self.lack_of_fit is not None:
            lines.extend(f"  warning: {m}" for m in self.lack_of_fit.messages)
        for name, value in self.params.items():
            text = number(value) if np.ndim(value) == 0 else \
                "[" + ", ".join(number(v) for v in np.ravel(value)) + "]"
            lines.append(f"  {name} = {text}")
        used = self.points["used"].to_numpy(bool)
        lines.append(f"  points used: {used.sum()} of {len(used)}")
        reasons = self.points.loc[~used, "reason"].astype(str)
        kinds = reasons.str.split(":").str[0]  # "saturated: 3 sensels ..." -> "saturated"
        for kind, group in reasons.groupby(kinds, sort=False):
            example = group.iloc[0] if group.nunique() == 1 else f"{kind} (e.g. {group.iloc[0]})"
            lines.append(f"    not used ({len(group)}): {example}")
        lines.append(f"  sensel area: {number(self.sensel_area_mm2)} mm2, saturation pressure: "
                     f"{number(self.saturation_pressure_kPa)} kPa")
        lines.extend(f"  {line}" for line in self._preprocessing_lines())
        movie = self.diagnostics.get("movie")
        if movie:
            lines.append(f"  {movie['report']}")
        note = self.diagnostics.get("note")
        if note:
            lines.append(f"  note: {note}")
        pi = self.prediction_interval
        if pi is not None:
            lines.append(f"  {share(pi.level)} prediction interval of a new patch's load: "
                         f"{100 * pi.rel_low:+.2f} % .. {100 * pi.rel_high:+.2f} % of the "
                         f"prediction ({pi.method}, {pi.n_resamples} refits)")
        lines.extend(f"  {k}: {share(v) if k.startswith('within_') else number(v)}"
                     for k, v in self.metrics.items())
        return "\n".join(lines)

    def _preprocessing_lines(self):
        lines = []
        if self.equilibration is not None:
            lines.append("equilibration: " + self.equilibration.summary().splitlines()[0])
        if self.non_working is not None:
            lines.append(self.non_working.report())
        return lines

    def _repr_fields(self):
        used = self.points["used"].to_numpy(bool) if "used" in self.points else []
        return [("method", self.method), ("model", self.model), ("params", self.params),
                ("points used", f"{int(np.sum(used))} of {len(self.points)}"),
                ("sensel_area_mm2", self.sensel_area_mm2),
                ("saturation_pressure_kPa", self.saturation_pressure_kPa),
                ("rmse_N", self.metrics.get("rmse_N")), ("created", self.created)]

    def _to_dict(self):
        """JSON-ready dictionary (keys of the calibration JSON contract)."""
        return to_jsonable({
            "method": self.method, "model": self.model, "params": self.params,
            "sensel_area_mm2": self.sensel_area_mm2,
            "saturation_pressure_kPa": self.saturation_pressure_kPa,
            "points": self.points.to_dict(orient="records"), "metrics": self.metrics,
            "options": self.options,
            "equilibration": None if self.equilibration is None
            else self.equilibration.to_dict(),
            "non_working_sensels": None if self.non_working is None
            else self.non_working.to_dict(),
            "prediction_interval": None if self.prediction_interval is None
            else self.prediction_interval.to_dict(),
            "selection": None if self.selection is None else self.selection.to_dict(),
            "lack_of_fit": None if self.lack_of_fit is None else self.lack_of_fit.to_dict(),
            "diagnostics": self.diagnostics, "version": self.version,
            "created": self.created, "provenance": self.provenance,
        })

    def to_json_text(self):
        """Return the calibration JSON as text.

        Indented for people; without indentation (the C encoder, several times faster)
        when there are more than 1000 points, as after a movie calibration.
        """
        return dumps(self.to_dict(), indent=2 if len(self.points) <= 1000 else None)

    @classmethod
    def _from_dict(cls, data, source):
        """Rebuild a result from :meth:`to_dict` output (``source`` names it in errors)."""
        require_keys(data, REQUIRED_KEYS, source, expected="a calibration JSON")
        check_calibration(data, source)
        table = pd.DataFrame(data["points"], columns=None if data["points"] else POINT_COLUMNS)
        nan = float("nan")
        where = f"key '{{}}' of {source}"
        return cls(
            method=data["method"], model=data["model"], params=dict(data["params"]),
            sensel_area_mm2=(nan if data["sensel_area_mm2"] is None
                             else float(data["sensel_area_mm2"])),
            saturation_pressure_kPa=(nan if data["saturation_pressure_kPa"] is None
                                     else float(data["saturation_pressure_kPa"])),
            points=table, metrics=dict(data["metrics"]), options=dict(data["options"]),
            equilibration=None if data["equilibration"] is None else Equilibration.from_dict(
                data["equilibration"], source=where.format("equilibration")),
            non_working=None if data["non_working_sensels"] is None
            else NonWorkingSensels.from_dict(data["non_working_sensels"],
                                             source=where.format("non_working_sensels")),
            prediction_interval=None if data["prediction_interval"] is None
            else PredictionInterval.from_dict(data["prediction_interval"],
                                              where.format("prediction_interval")),
            selection=None if data["selection"] is None
            else Selection.from_dict(data["selection"], where.format("selection")),
            lack_of_fit=None if data["lack_of_fit"] is None
            else LackOfFit.from_dict(data["lack_of_fit"], where.format("lack_of_fit")),
            diagnostics=dict(data["diagnostics"]), version=data.get("version", ""),
            created=data.get("created", ""),
            provenance=dict(check_type(data.get("provenance") or {}, dict,
                                       where.format("provenance"), expected="an object")),
            method_result=_method_result(data, source),
        )


def _method_result(data, source):
    """Rebuild the ZvyaginResult of a Zvyagin calibration from its ``diagnostics``."""
    if data["method"] != "zvyagin":
        return None
    try:
        return ZvyaginResult.from_details(data["diagnostics"])
    except (KeyError, IndexError, TypeError, ValueError, AttributeError, ArithmeticError) \
            as exc:  # any malformed part of the intermediates: one line naming the key
        raise TactilecalError(f"key 'diagnostics' of {source}: the Zvyagin intermediates "
                              f"cannot be read ({type(exc).__name__}: {exc}); expected those "
                              "written by method='zvyagin'") from None


def check_calibration(data, source):
    """Check the types and values of a calibration JSON's keys before they are used.

    The law must be a force per sensel (:func:`tactilecal.calibration._models.check_law`:
    finite, never negative, never decreasing on raw 0..255, positive at 255); the power law
    (eq. 1 of Zvyagin 2022) needs A > 0 and b > 0.
    """
    where = f"key '{{}}' of {source}"
    check_type(data["method"], str, where.format("method"), expected="a method name")
    model = check_type(data["model"], str, where.format("model"), expected="a model name")
    if model not in MODELS:
        raise TactilecalError(f"{where.format('model')} is {model!r}; expected one of "
                              f"{sorted(MODELS)}")
    params = check_type(data["params"], dict, where.format("params"),
                        expected="an object of parameters")
    check_type(data["points"], list, where.format("points"), expected="a list of points")
    for key in ("metrics", "options", "diagnostics"):
        check_type(data[key], dict, where.format(key), expected="an object")
    for key in ("equilibration", "non_working_sensels", "prediction_interval", "selection",
                "lack_of_fit"):
        if data[key] is not None:
            check_type(data[key], dict, where.format(key), expected="an object or null")
    if model == "power":
        require_keys(params, ("A", "b"), where.format("params"), expected="a power law")
        for name in ("A", "b"):
            check_number(params[name], where.format(f"params.{name}"), minimum=0.0,
                         min_inclusive=False)
    for name, value in params.items():
        items = value if isinstance(value, list) else [value]
        for k, item in enumerate(items):
            check_number(item, where.format(f"params.{name}")
                         + (f", entry {k}" if isinstance(value, list) else ""))
    check_number(data["sensel_area_mm2"], where.format("sensel_area_mm2"), minimum=0.0,
                 min_inclusive=False, allow_none=True)
    check_number(data["saturation_pressure_kPa"], where.format("saturation_pressure_kPa"),
                 minimum=0.0, min_inclusive=False, allow_none=True)
    try:
        check_law(model, params, where.format("params"))
    except (KeyError, IndexError, TypeError, ValueError) as exc:
        if isinstance(exc, TactilecalError):
            raise
        raise TactilecalError(f"{where.format('params')}: {exc!r} with model {model!r}; "
                              "expected the parameters of that model") from None
