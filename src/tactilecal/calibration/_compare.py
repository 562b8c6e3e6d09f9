"""Compare calibrations of any method, like Zvyagin (2022) Table 2 and Figure 10."""

import numpy as np

from tactilecal._errors import TactilecalError
from tactilecal._result import ShortRepr
from tactilecal._units import N_PER_MM2_TO_KPA, pressure_to_kPa

__all__ = ["Comparison", "compare_calibrations", "format_compare_table",
           "plot_compare"]

COLUMNS = ("name", "method", "points", "I1", "I2", "I3", "I4", "d", "A0", "b0", "f128_N",
           "p_s_MPa", "median_abs_error_pct")


def _row(name, cal):
    used = int(np.sum(cal.points["used"])) if len(cal.points) else 0
    row = dict.fromkeys(COLUMNS)
    row.update(name=name, method=cal.method, points=used)
    if cal.model == "power":
        row.update(A0=float(cal.params["A"]), b0=float(cal.params["b"]))
    row["f128_N"] = float(cal.force_table()[128])
    sat = cal.saturation_pressure_kPa
    row["p_s_MPa"] = float(pressure_to_kPa(sat, "kPa") / pressure_to_kPa(1.0, "MPa")) \
        if np.isfinite(sat) else None
    error = cal.metrics.get("median_abs_error_pct")
    row["median_abs_error_pct"] = float(error) if error is not None and np.isfinite(error) \
        else None
    if cal.method == "zvyagin":
        sep = cal.diagnostics["separation"]
        row.update(I1=sep[0], I2=sep[1], I3=sep[2], I4=sep[3], d=cal.diagnostics["d_min"])
    return row


class Comparison(ShortRepr):
    """Calibrations side by side: Zvyagin (2022) Table 2 as :attr:`rows`, Figure 10 as :meth:`plot`.

    Attributes
    ----------
    calibrations : list of CalibrationResult
    names : list of str
    rows : list of dict
        One per calibration, keys :data:`COLUMNS`: ``points`` used, the separation ``I1``..
        ``I4`` and ``d`` (Zvyagin calibrations only), ``A0``, ``b0`` (power model only),
        the force per sensel at raw 128 ``f128_N`` and the saturation pressure ``p_s_MPa``
        (any law), the median absolute error of the fit in percent of the load; None where
        a calibration has no such value.
    """

    def __init__(self, calibrations, names, rows):
        self.calibrations, self.names, self.rows = calibrations, names, rows

    def _repr_fields(self):
        return [("names", self.names), ("methods", [r["method"] for r in self.rows])]

    def table(self):
        """Return :attr:`rows` as a fixed-width text table (what ``tactilecal compare`` prints)."""
        return format_compare_table(self.rows)

    def plot(self, ax=None):
        """Draw every calibration's curve on one plot (Figure 10 across calibrations).

        Pressure in kPa when every calibration knows its sensel area, else force per
        sensel. Returns the matplotlib Axes.
        """
        return plot_compare(self.calibrations, self.names, ax=ax)


def compare_calibrations(calibrations, names=None):
    """Put calibrations side by side, like Zvyagin (2022) Table 2 and Figure 10.

    To see a sensor's drift across sessions, or a used sensor against a new one.

    Parameters
    ----------
    calibrations : sequence of CalibrationResult
        Any methods; I* and d only exist for Zvyagin calibrations, A0 and b0 for the power
        model (None elsewhere).
    names : sequence of str, optional
        Row names (default ``"cal <k>"``).

    Returns
    -------
    Comparison
        ``.rows`` (the table), ``.table()`` (as text), ``.plot()`` (the curves).

    Raises
    ------
    TactilecalError
        With no calibration, or a number of names other than one per calibration.

    Examples
    --------
    >>> from tactilecal.calibration import calibrate, points_from_frames
    >>> raw = np.zeros((3, 2, 2)); raw[:, 0, 0] = [10, 50, 200]
    >>> points = points_from_frames(raw, 0.004 * raw[:, 0, 0] ** 1.2)
    >>> cals = [calibrate(points, method=m) for m in ("power", "lut", "linear")]
    >>> [r["method"] for r in compare_calibrations(cals).rows]
    ['power', 'lut', 'linear']
    """
    calibrations = list(calibrations)
    if not calibrations:
        raise TactilecalError("no calibration to compare; expected at least one CAL.json")
    names = [f"cal {k}" for k in range(len(calibrations))] if names is None else list(names)
    if len(names) != len(calibrations):
        raise TactilecalError(f"{len(names)} names for {len(calibrations)} calibrations; expected "
                              "one name each")
    rows = [_row(n, c) for n, c in zip(names, calibrations, strict=True)]
    return Comparison(calibrations, names, rows)


def _fmt(value, spec):
    width = int("".join(ch for ch in spec.split(".")[0] if ch.isdigit()))
    return "-".rjust(width) if value is None else format(value, spec)


def format_compare_table(rows):
    """Format :attr:`Comparison.rows` as a fixed-width text table."""
    width = max(12, *(len(r["name"]) for r in rows))
    head = (f"{'calibration':<{width}} {'method':<13} {'|T|':>4} {'I1':>3} {'I2':>3} "
            f"{'I3':>3} {'I4':>4} {'d':>6} {'A0':>9} {'b0':>7} {'f(128) N':>9} "
            f"{'p_s MPa':>8} {'|err| %':>7}")
    lines = [head]
    for r in rows:
        lines.append(f"{r['name']:<{width}} {r['method']:<13} {r['points']:>4} "
                     f"{_fmt(r['I1'], '>3')} {_fmt(r['I2'], '>3')} {_fmt(r['I3'], '>3')} "
                     f"{_fmt(r['I4'], '>4')} {_fmt(r['d'], '>6.2f')} {_fmt(r['A0'], '>9.5f')} "
                     f"{_fmt(r['b0'], '>7.4f')} {_fmt(r['f128_N'], '>9.4g')} "
                     f"{_fmt(r['p_s_MPa'], '>8.3f')} {_fmt(r['median_abs_error_pct'], '>7.2f')}")
    return "\n".join(lines)


def plot_compare(calibrations, names, ax=None):
    """Figure 10 across calibrations: every calibration's curve on one plot.

    Pressure in kPa when every calibration knows its sensel area, else force per sensel.

    Returns
    -------
    matplotlib.axes.Axes
    """
    if ax is None:
        from matplotlib.figure import Figure

        ax = Figure(figsize=(6, 4.5), layout="constrained").add_subplot()
    areas = np.array([c.sensel_area_mm2 for c in calibrations], dtype=float)
    pressure = bool(np.all(np.isfinite(areas) & (areas > 0)))
    raw = np.arange(256)
    for cal, name, area in zip(calibrations, names, areas, strict=True):
        y = cal.force_table() * (N_PER_MM2_TO_KPA / area if pressure else 1.0)
        ax.plot(raw, y, label=f"{name} ({cal.method})")
    ax.set_xlim(0, 255)
    ax.set_xlabel("raw reading")
    ax.set_ylabel("pressure (kPa)" if pressure else "force per sensel (N)")
    ax.legend(fontsize=8)
    return ax
