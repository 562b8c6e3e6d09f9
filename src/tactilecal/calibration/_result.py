"""The calibration result: parameters, uncertainty, per-point table, JSON round-trip."""

import warnings
from dataclasses import dataclass, field
from datetime import UTC, datetime

import numpy as np
import pandas as pd
import xarray as xr

from tactilecal._errors import TactilecalError
from tactilecal._jsonutil import dumps, to_jsonable
from tactilecal._result import SavedResult
from tactilecal._units import N_PER_MM2_TO_KPA
from tactilecal._validate import check_number, check_type, require_keys
from tactilecal._version import __version__
from tactilecal.calibration import _plots
from tactilecal.calibration._models import MODELS, force_table, sensel_force
from tactilecal.zvyagin import ZvyaginResult

__all__ = ["CalibrationResult", "load_calibration"]

# kPa per unit; ``N`` (force per sensel) is handled apart.
POINT_COLUMNS = ["file", "frame", "load_N", "raw_sum", "loaded_cells", "saturated_cells",
                 "used", "reason", "predicted_N", "error_pct"]
REQUIRED_KEYS = ["method", "model", "params", "sensel_area_mm2", "saturation_pressure_kPa",
                 "points", "metrics"]


@dataclass(repr=False)
class CalibrationResult(SavedResult):
    """A fitted static calibration (force per sensel as a function of its raw reading).

    Saved as ``"format": "tactilecal-calibration/1"`` (:mod:`tactilecal._result`).

    Attributes
    ----------
    method : str
        Calibration method (``"power"``, ``"linear"``, ``"zvyagin"``...).
    model : str
        Per-sensel law, a key of :data:`tactilecal.calibration._models.MODELS`. For
        ``"power"``, force per sensel in newtons = ``A * raw**b``.
    params : dict
        Fitted parameters.
    params_stderr : dict
        Standard errors of ``params`` (None where not estimated; ``details`` says how).
    sensel_area_mm2 : float
        Area of one sensel (NaN when unknown).
    saturation_pressure_kPa : float
        Pressure at raw = 255 (NaN when the area is unknown).
    points : pandas.DataFrame
        One row per calibration point: file, frame, load_N, raw_sum, loaded_cells,
        saturated_cells, used, reason, predicted_N, error_pct.
    metrics : dict
        Fit quality over the used points.
    details : dict
        Method-specific JSON-serialisable intermediate results.
    options : dict
        The options the method was called with.
    provenance : dict
        Where it came from (:func:`tactilecal._provenance.provenance`): package version,
        the manifest and recordings with their SHA-256, the sensor type and serial from the
        export headers. Empty for points made in memory.
    method_result : tactilecal.zvyagin.ZvyaginResult or None
        The method's own result with every intermediate: the :class:`ZvyaginResult` for
        ``method="zvyagin"`` (rebuilt from ``details`` when the JSON is loaded), None for
        the other methods. Not saved itself: ``details`` holds its JSON form.
    """

    FORMAT_KIND = "calibration"
    DESCRIPTION = "a calibration JSON"

    method: str
    model: str
    params: dict
    params_stderr: dict
    sensel_area_mm2: float
    saturation_pressure_kPa: float
    points: pd.DataFrame
    metrics: dict
    details: dict = field(default_factory=dict)
    options: dict = field(default_factory=dict)
    version: str = __version__
    created: str = field(default_factory=lambda: datetime.now(UTC).isoformat(timespec="seconds"))
    provenance: dict = field(default_factory=dict)
    method_result: ZvyaginResult | None = field(default=None, compare=False)

    # ------------------------------------------------------------------ predictions
    def force_table(self):
        """Force per sensel in newtons at raw = 0..255 (float64[256])."""
        return force_table(self.model, self.params)

    def predict_sensel_force(self, raw):
        """Force on each sensel in newtons (same shape as ``raw``; NaN stays NaN).

        Equilibration gains and the non-working-sensel mask stored in ``details`` (by
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
        from tactilecal.calibration._sensels import Equilibration

        values = np.asarray(getattr(raw, "values", raw), dtype=float)
        if "equilibration" in self.details:
            values = Equilibration.from_dict(self.details["equilibration"]).apply(values)
        dead = self.details.get("non_working_sensels", {}).get("sensels", [])
        if dead:
            rows, cols = np.asarray(dead).T
            values = values.copy()
            values[..., rows, cols] = np.nan
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
        """
        force = self.predict_sensel_force(raw)
        if force.ndim == 2:
            return float(np.nansum(force))
        return np.nansum(force.reshape(force.shape[0], -1), axis=1)

    def predict_histograms(self, histograms):
        """Total force of frames given as 256-bin histograms (n, 256) -> (n,)."""
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
            For an unknown unit, a recording that is not raw, or a missing/inconsistent
            sensel area.
        """
        from tactilecal._model import check_recording
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
        # apply_ufunc keeps a dask-backed recording lazy (chunk by chunk along frames)
        out = xr.apply_ufunc(lambda raw: self.predict_sensel_force(raw) * scale, recording,
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
        """Human-readable summary: parameters with errors, points used and metrics."""
        lines = [f"Calibration method {self.method!r}, model {self.model!r}"]
        lines.extend(self._param_lines())
        used = self.points["used"].to_numpy(bool)
        lines.append(f"  points used: {used.sum()} of {len(used)}")
        reasons = self.points.loc[~used, "reason"].astype(str)
        kinds = reasons.str.split(":").str[0]  # "saturated: 3 sensels ..." -> "saturated"
        for kind, group in reasons.groupby(kinds, sort=False):
            example = group.iloc[0] if group.nunique() == 1 else f"{kind} (e.g. {group.iloc[0]})"
            lines.append(f"    not used ({len(group)}): {example}")
        lines.append(f"  sensel area: {self.sensel_area_mm2:.4g} mm2, saturation pressure: "
                     f"{self.saturation_pressure_kPa:.5g} kPa")
        interval = self.details.get("prediction_interval")
        if interval:
            lines.append(f"  {interval['level']:.0%} prediction interval of a new patch's load: "
                         f"{100 * interval['rel_low']:+.2f} % .. {100 * interval['rel_high']:+.2f}"
                         f" % of the prediction ({interval['method']}, "
                         f"{interval['n_resamples']} refits)")
        lines.extend(f"  {k}: {v:.4g}" if isinstance(v, float) else f"  {k}: {v}"
                     for k, v in self.metrics.items())
        return "\n".join(lines)

    def _param_lines(self):
        """One line per parameter (with its interval in a calibration saved with one)."""
        intervals = self.details.get("params_interval") or {}
        lines = []
        for name, value in self.params.items():
            val_txt = f"{value:.6g}" if np.ndim(value) == 0 else str(np.round(value, 6).tolist())
            bounds = intervals.get(name)
            if bounds is not None and np.ndim(value) == 0:
                val_txt += (f"  ({intervals['level']:.0%} interval {bounds[0]:.6g} .. "
                            f"{bounds[1]:.6g})")
            lines.append(f"  {name} = {val_txt}")
        if "unbounded" in intervals:  # a calibration saved before issue 12's removal
            lines.append(f"  parameter intervals: unbounded ({intervals['unbounded']})")
        elif intervals:
            lines.append(f"  parameter intervals: {intervals['method']}")
        elif self.options.get("n_bootstrap"):  # asked for, and not given: say why
            lines.append(f"  parameter intervals: {self.details.get('stderr_method')}")
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
            "params_stderr": self.params_stderr, "sensel_area_mm2": self.sensel_area_mm2,
            "saturation_pressure_kPa": self.saturation_pressure_kPa,
            "points": self.points.to_dict(orient="records"), "metrics": self.metrics,
            "details": self.details, "options": self.options, "version": self.version,
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
        return cls(
            method=data["method"], model=data["model"], params=dict(data["params"]),
            params_stderr=dict(data.get("params_stderr") or {}),
            sensel_area_mm2=(nan if data["sensel_area_mm2"] is None
                             else float(data["sensel_area_mm2"])),
            saturation_pressure_kPa=(nan if data["saturation_pressure_kPa"] is None
                                     else float(data["saturation_pressure_kPa"])),
            points=table, metrics=dict(data["metrics"]), details=dict(data.get("details") or {}),
            options=dict(data.get("options") or {}), version=data.get("version", ""),
            created=data.get("created", ""),
            provenance=dict(check_type(data.get("provenance") or {}, dict,
                                       f"key 'provenance' of {source}", expected="an object")),
            method_result=_method_result(data, source),
        )


def _method_result(data, source):
    """Rebuild the ZvyaginResult of a Zvyagin calibration from its ``details`` (else None)."""
    details = data.get("details") or {}
    if data["method"] != "zvyagin" or details.get("method") != "zvyagin":
        return None
    try:
        return ZvyaginResult.from_details(details)
    except (KeyError, IndexError, TypeError, ValueError, AttributeError, ArithmeticError) \
            as exc:  # any malformed part of the details: one line naming the key
        raise TactilecalError(f"key 'details' of {source}: the Zvyagin intermediates cannot be "
                              f"read ({type(exc).__name__}: {exc}); expected those written by "
                              "method='zvyagin'") from None


def check_calibration(data, source):
    """Check the types and values of a calibration JSON's keys before they are used.

    The law must give finite forces at raw 0..255, positive at 255; the power law (eq. 1 of
    Zvyagin 2022) needs A > 0 and b > 0 (A < 0 gives negative forces, b <= 0 no law).
    """
    where = f"key '{{}}' of {source}"
    check_type(data["method"], str, where.format("method"), expected="a method name")
    model = check_type(data["model"], str, where.format("model"), expected="a model name")
    if model not in MODELS:
        raise TactilecalError(f"{where.format('model')} is {model!r}; expected one of "
                              f"{sorted(MODELS)}")
    params = check_type(data["params"], dict, where.format("params"),
                        expected="an object of parameters")
    for key in ("points", "metrics", "details", "options", "params_stderr"):
        if key in REQUIRED_KEYS or data.get(key) is not None:
            check_type(data[key], list if key == "points" else dict, where.format(key),
                       expected="a list of points" if key == "points" else "an object")
    if model == "power":
        require_keys(params, ("A", "b"), where.format("params"), expected="a power law")
        for name in ("A", "b"):
            check_number(params[name], where.format(f"params.{name}"), minimum=0.0,
                         min_inclusive=False)
    for name, value in params.items():
        for item in np.ravel(value if isinstance(value, list) else [value]):
            check_number(item, where.format(f"params.{name}"))
    check_number(data["sensel_area_mm2"], where.format("sensel_area_mm2"), minimum=0.0,
                 min_inclusive=False, allow_none=True)
    check_number(data["saturation_pressure_kPa"], where.format("saturation_pressure_kPa"),
                 allow_none=True)
    try:
        with np.errstate(all="ignore"):  # overflow is caught below as a non-finite force
            table_N = force_table(model, params)
    except (KeyError, IndexError, TypeError, ValueError) as exc:
        raise TactilecalError(f"{where.format('params')}: {exc!r} with model {model!r}; expected "
                              "the parameters of that model") from None
    if not np.all(np.isfinite(table_N)) or not table_N[255] > 0:
        raise TactilecalError(f"{where.format('params')} give forces from {np.nanmin(table_N):g} "
                              f"to {np.nanmax(table_N):g} N at raw 0..255; expected finite forces, "
                              "positive at 255")


def load_calibration(path):
    """Read a calibration JSON written by :meth:`CalibrationResult.to_json`.

    The same as ``CalibrationResult.from_json(path)``.

    Raises
    ------
    ValueError
        If the file is not JSON, lacks a contract key, or holds an impossible value (a law
        that gives negative or non-finite forces, a sensel area <= 0); the message names
        the file and the key.
    TypeError
        If a key holds the wrong type (a string where a number belongs).
    """
    return CalibrationResult.from_json(path)
