"""Figures like Zvyagin (2022) Figures 7-11, from a ZvyaginResult or a calibration JSON.

matplotlib is imported inside the functions; figures are built with
:class:`matplotlib.figure.Figure` (no pyplot state, no display needed).
"""

import numpy as np

from tactilecal._png import FIGURE_DPI, write_png
from tactilecal._units import N_PER_MM2_TO_KPA

__all__ = ["plot_d_map", "plot_pair_chart", "plot_ab_scatter",
           "plot_calibration_curves", "plot_patch_errors", "plot_energy", "save_figures"]

#: colours of the pair chart (Figure 8): valid green, outlier cyan, 10% rule orange
PAIR_COLOURS = {"V": "#2ca02c", "O": "#17becf", "R": "#ff7f0e", "N": "#ffffff",
                "X": "#bdbdbd", "-": "#000000"}


def _axes(ax, size=(5.5, 4.2)):
    if ax is None:
        from matplotlib.figure import Figure

        ax = Figure(figsize=size, layout="constrained").add_subplot()
    return ax


def plot_d_map(result, ax=None):
    """Figure 7: d_{T}(I) at I1 = I1*, minimised over I2, as a map over (I3, I4).

    Returns
    -------
    matplotlib.axes.Axes
    """
    res = result
    ax = _axes(ax)
    dm = res.d_summary
    (lo3, hi3), (lo4, hi4) = dm["ranges"][2], dm["ranges"][3]
    img = np.asarray(dm["I3_I4_at_I1"], dtype=float)
    mesh = ax.imshow(img, origin="lower", aspect="auto", cmap="viridis",
                     extent=(lo4 - 0.5, hi4 + 0.5, lo3 - 0.5, hi3 + 0.5))
    ax.figure.colorbar(mesh, ax=ax, label="d (raw units per sensel)")
    ax.plot(res.separation[3], res.separation[2], "r*", ms=12,
            label=f"I* = {tuple(res.separation)}, d = {res.d_min:.3f}")
    ax.set_xlabel("I4")
    ax.set_ylabel("I3")
    ax.set_title(f"d(I) at I1 = {dm['I1']} (min over I2)")
    ax.legend(loc="upper left", fontsize=8)
    return ax


def _patch_order(res):
    return np.lexsort((res.load_N, res.group))


def plot_pair_chart(result, ax=None):
    """Figure 8: the chart of pairs, patches sorted by load; grey patches shaded.

    Returns
    -------
    matplotlib.axes.Axes
    """
    from matplotlib.colors import ListedColormap
    from matplotlib.patches import Patch

    res = result
    ax = _axes(ax, (6.5, 6))
    order = _patch_order(res)
    letters = list(PAIR_COLOURS)
    chart = res.pair_matrix[np.ix_(order, order)]
    codes = np.searchsorted(np.array(letters), chart, sorter=np.argsort(letters))
    codes = np.argsort(letters)[codes]
    ax.imshow(codes, cmap=ListedColormap([PAIR_COLOURS[k] for k in letters]),
              vmin=-0.5, vmax=len(letters) - 0.5, interpolation="nearest")
    pos = np.argsort(order)
    for k in res.grey:
        ax.axhspan(pos[k] - 0.5, pos[k] + 0.5, color="0.5", alpha=0.35, lw=0)
        ax.axvspan(pos[k] - 0.5, pos[k] + 0.5, color="0.5", alpha=0.35, lw=0)
    groups = res.group[order]
    for edge in np.nonzero(np.diff(groups))[0]:
        ax.axhline(edge + 0.5, color="k", lw=0.8)
        ax.axvline(edge + 0.5, color="k", lw=0.8)
    ticks = [np.mean(np.nonzero(groups == g)[0]) for g in np.unique(groups)]
    names = [res.group_names[g] for g in np.unique(groups)]
    ax.set_xticks(ticks, names)
    ax.set_yticks(ticks, names)
    counts = res.category_counts()
    handles = [Patch(color=PAIR_COLOURS[k], label=f"{k}: {counts.get(k, 0)}")
               for k in "VORNX" if counts.get(k)]
    handles.append(Patch(color="0.5", alpha=0.35, label=f"grey patches: {len(res.grey)}"))
    ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.01, 1), fontsize=8)
    ax.set_title("pairs of patches (eq. 12)")
    return ax


def plot_ab_scatter(result, ax=None):
    """Figure 9: the (A, b) set, the fitted power law, T1/T2 and (A0, b0).

    Returns
    -------
    matplotlib.axes.Axes
    """
    res = result
    ax = _axes(ax)
    cat = res.pairs["category"]
    for letter, colour, label in (("V", "C0", "pairs (A, b)"), ("O", "C7", "outside the fit")):
        sel = cat == letter
        if sel.any():
            ax.plot(res.pairs["b"][sel], res.pairs["A"][sel], ".", ms=2, color=colour,
                    label=f"{label} ({sel.sum()})")
    b = res.pairs["b"][np.isin(cat, ("V", "O"))]
    grid = np.linspace(b.min(), b.max(), 200)
    ax.plot(grid, res.alpha * grid ** res.beta, "k-", lw=1,
            label=f"A = {res.alpha:.4g} b^{res.beta:.3f}, R2 = {res.power_law['r2']:.3f}")
    for name, pt in res.terminal_points().items():
        ax.plot(pt["b"], pt["A"], "s", color="C3", ms=6)
        ax.annotate(f"{name} ({pt['b']:.3f}; {pt['A']:.4g})", (pt["b"], pt["A"]),
                    textcoords="offset points", xytext=(6, 4), fontsize=8)
    ax.plot(res.b0, res.A0, "*", color="C1", ms=14, label=f"(A0, b0) = ({res.A0:.4g}, "
                                                            f"{res.b0:.4f})")
    inl = res.pairs["b"][cat == "V"]
    pad = 0.1 * (inl.max() - inl.min()) + 1e-3
    ax.set_xlim(inl.min() - pad, inl.max() + pad)
    off = int(np.sum(b > inl.max() + pad))
    ax.set_xlabel(f"b ({off} pairs beyond the axis)" if off else "b")
    ax.set_ylabel("A (N per sensel)")
    ax.set_yscale("log")
    shown = res.pairs["A"][np.isin(cat, ("V", "O")) & (res.pairs["b"] <= inl.max() + pad)]
    ax.set_ylim(shown.min() / 1.5, shown.max() * 1.5)
    ax.legend(fontsize=8)
    return ax


def plot_calibration_curves(result, ax=None):
    """Figure 10: force per sensel (or pressure) vs raw for (A0, b0) and for T1 and T2.

    Returns
    -------
    matplotlib.axes.Axes
    """
    res = result
    ax = _axes(ax)
    area = res.sensel_area_mm2
    known = np.isfinite(area) and area > 0
    scale, unit = ((N_PER_MM2_TO_KPA / area, "pressure (kPa)") if known
                   else (1.0, "force per sensel (N)"))
    raw = np.arange(256.0)
    ax.plot(raw, res.A0 * raw ** res.b0 * scale, "k-",
            label=f"(A0, b0): p_s = {res.p_s_MPa:.3f} MPa" if known else "(A0, b0)")
    for (name, pt), style in zip(res.terminal_points().items(), ("--", ":"), strict=True):
        ax.plot(raw, pt["A"] * raw ** pt["b"] * scale, style, color="0.4",
                label=f"terminal {name} ({pt['A']:.4g}, {pt['b']:.3f})")
    ax.set_xlim(0, 255)
    ax.set_xlabel("raw reading")
    ax.set_ylabel(unit)
    ax.legend(fontsize=8)
    return ax


def plot_patch_errors(result, ax=None):
    """Figure 11: per-patch discrepancy (%) between calibrated and applied load, by weight.

    Returns
    -------
    matplotlib.axes.Axes
    """
    res = result
    ax = _axes(ax)
    err = res.error_pct
    top = max(12.0, float(np.ceil(np.nanmax(np.abs(err[res.usable])))))
    bins = np.arange(-top, top + 1.0, 1.0)
    data = [err[res.usable & (res.group == g)] for g in range(len(res.group_names))]
    # one filled outline per weight: the stacked bars, without a rectangle artist per bin
    ax.hist(data, bins=bins, stacked=True, label=res.group_names, histtype="stepfilled")
    for x in (-5, 5):
        ax.axvline(x, color="k", lw=0.8, ls="--")
    ax.set_xlabel("(calibrated - applied) / applied load (%)")
    ax.set_ylabel("patches")
    ax.set_title(f"within 5%: {res.within(5):.0%}, within 10%: {res.within(10):.0%}")
    ax.legend(fontsize=8)
    return ax


def plot_energy(result, ax=None):
    """E(b0) along the power-law curve (eq. 15), its minimum, and the law the result returned.

    The grey line marks the minimum of E on the curve A0 = alpha b0^beta (the faithful
    method's b0). In robust mode the returned law is a free power-law fit, not on that
    curve: its b is marked apart (dashed) and the title says so.

    Returns
    -------
    matplotlib.axes.Axes
    """
    res = result
    ax = _axes(ax)
    ax.plot(res.final["b_grid"], res.final["E_grid"], "k-")
    on_curve = res.final.get("curve_b0", res.b0)
    ax.axvline(on_curve, color="C1", label=f"minimum of E on the curve: b0 = {on_curve:.4f}")
    if res.final.get("free"):
        ax.axvline(res.b0, color="C0", ls="--",
                   label=f"returned law (robust free fit): b = {res.b0:.4f}")
        ax.set_title("robust mode returned a free fit, not the curve's minimum",
                     fontsize="small")
    ax.set_yscale("log")
    ax.set_xlabel("b0 (on A0 = alpha b0^beta)")
    ax.set_ylabel("E (N^2)")
    ax.legend(fontsize=8)
    return ax


FIGURES = {"zvyagin_d_map": plot_d_map, "zvyagin_pairs": plot_pair_chart,
           "zvyagin_ab": plot_ab_scatter, "zvyagin_curves": plot_calibration_curves,
           "zvyagin_errors": plot_patch_errors, "zvyagin_energy": plot_energy}


def save_figures(result, outdir, *, dpi=FIGURE_DPI):
    """Write every Zvyagin figure as PNG into ``outdir`` (atomically); return the paths.

    Examples
    --------
    >>> import tempfile
    >>> from tactilecal.calibration.methods.zvyagin import Options, zvyagin_fit
    >>> from tactilecal.simulate import patch_histograms
    >>> res = zvyagin_fit(*patch_histograms(20, seed=1)[:2], Options())
    >>> sorted(p.name for p in res.save_figures(tempfile.mkdtemp()))[:2]
    ['zvyagin_ab.png', 'zvyagin_curves.png']
    """
    from pathlib import Path

    res = result
    outdir = Path(outdir)
    paths = []
    for name, func in FIGURES.items():
        ax = func(res)
        path = outdir / f"{name}.png"
        write_png(ax.figure, path, dpi=dpi)
        paths.append(path)
    return paths
