"""Figures of a calibration: the curve, predicted vs applied load, the error histogram.

They are the methods ``plot_curve``, ``plot_points``, ``plot_error_histogram`` and
``save_figures`` of :class:`~tactilecal.calibration.CalibrationResult`. matplotlib is
imported inside each function so that importing the package stays fast.
"""

from pathlib import Path

import numpy as np

from tactilecal._png import FIGURE_DPI, write_png
from tactilecal._units import N_PER_MM2_TO_KPA

__all__ = ["plot_calibration_curve", "plot_points", "plot_error_histogram", "save_figures"]


def _axes(ax):
    if ax is None:
        import matplotlib.pyplot as plt

        _, ax = plt.subplots(figsize=(5, 4))
    return ax


def plot_calibration_curve(result, ax=None):
    """Plot the calibration law over raw 0..255 with the points' mean raw vs load per cell.

    Pressure in kPa when the sensel area is known, else force per sensel in N. Each point
    is drawn at its mean raw reading of loaded sensels (raw_sum / loaded_cells) against its
    load per loaded cell (what I-Scan's mean-raw calibrations assume); used points filled,
    unused ones hollow. On uneven patches the points sit above a convex (b > 1) curve,
    since the mean of raw**b exceeds the b-th power of the mean raw: the bias of the
    mean-raw methods (``power-2pt``) made visible.

    Returns
    -------
    matplotlib.axes.Axes
    """
    ax = _axes(ax)
    area = result.sensel_area_mm2
    scale, ylabel = ((N_PER_MM2_TO_KPA / area, "pressure (kPa)") if np.isfinite(area) and area > 0
                     else (1.0, "force per sensel (N)"))
    raw = np.arange(256)
    ax.plot(raw, result.force_table() * scale, color="C0",
            label=f"{result.method} ({result.model})")
    tab = result.points
    cells = tab["loaded_cells"].to_numpy(float)
    with np.errstate(divide="ignore", invalid="ignore"):
        x = tab["raw_sum"].to_numpy(float) / cells
        y = tab["load_N"].to_numpy(float) / cells * scale
    used = tab["used"].to_numpy(bool)
    ax.plot(x[used], y[used], "o", color="C1", ms=4, label="points used")
    if (~used).any():
        ax.plot(x[~used], y[~used], "o", mfc="none", color="C3", ms=4, label="not used")
    ax.set_xlabel("raw reading (0..255)")
    ax.set_ylabel(ylabel)
    ax.set_xlim(0, 255)
    ax.legend(frameon=False)
    return ax


def plot_points(result, ax=None):
    """Plot predicted vs applied load for every point, with the 1:1 line and +-5 % band.

    Returns
    -------
    matplotlib.axes.Axes
    """
    ax = _axes(ax)
    tab = result.points
    load = tab["load_N"].to_numpy(float)
    pred = tab["predicted_N"].to_numpy(float)
    used = tab["used"].to_numpy(bool)
    top = np.nanmax(np.r_[load, pred, 1e-9]) * 1.05
    line = np.array([0.0, top])
    ax.plot(line, line, color="k", lw=1)
    ax.fill_between(line, 0.95 * line, 1.05 * line, color="0.85", label="+-5 %")
    ax.plot(load[used], pred[used], "o", color="C0", ms=4, label="used")
    if (~used).any():
        ax.plot(load[~used], pred[~used], "o", mfc="none", color="C3", ms=4, label="not used")
    ax.set_xlabel("applied load (N)")
    ax.set_ylabel("calibrated load (N)")
    ax.legend(frameon=False)
    return ax


def plot_error_histogram(result, ax=None):
    """Histogram of the per-point errors in percent of the applied load (used points).

    Returns
    -------
    matplotlib.axes.Axes
    """
    ax = _axes(ax)
    tab = result.points
    err = tab.loc[tab["used"].astype(bool), "error_pct"].to_numpy(float)
    err = err[np.isfinite(err)]
    # one filled outline: the bars, without a rectangle artist per bin
    ax.hist(err, bins=max(5, min(40, len(err) // 3 or 5)), color="C0", histtype="stepfilled")
    ax.axvline(0, color="k", lw=1)
    ax.set_xlabel("error (% of applied load)")
    ax.set_ylabel("points")
    return ax


#: The PNG files of a calibration that is not Zvyagin's, and what draws each.
FIGURES = {"calibration_curve": plot_calibration_curve, "calibration_points": plot_points,
           "calibration_errors": plot_error_histogram}


def save_figures(result, outdir, *, dpi=FIGURE_DPI):
    """Write a calibration's figures as PNG files into ``outdir`` (atomically).

    A Zvyagin calibration writes the paper's Figures 7-11 and E(b0)
    (:meth:`ZvyaginResult.save_figures`); any other writes the
    calibration curve, predicted vs applied loads and the error histogram (:data:`FIGURES`).

    Parameters
    ----------
    outdir : str or os.PathLike
        An existing folder.
    dpi : int, optional
        Resolution of the PNG files.

    Returns
    -------
    list of pathlib.Path
        The files written, in the order drawn.
    """
    if result.method_result is not None:  # Zvyagin's figures of the paper
        return result.method_result.save_figures(outdir, dpi=dpi)
    from matplotlib.figure import Figure

    paths = []
    for name, draw in FIGURES.items():
        fig = Figure(figsize=(5.5, 4.2), layout="constrained")
        draw(result, ax=fig.add_subplot())
        path = Path(outdir) / f"{name}.png"
        write_png(fig, path, dpi=dpi)
        paths.append(path)
    return paths
