"""Figures of a dynamic calibration, like Gillis (2013) Figures 4.9 to 4.14.

Every function returns a :class:`matplotlib.figure.Figure` built without pyplot (no global
state), so the report can embed it and the CLI can save it.
"""

import numpy as np

__all__ = ["plot_transfer", "plot_time", "plot_spectra", "plot_error"]


def _axes(figsize, rows=1):
    """Return a figure and its axes (``rows`` stacked, sharing x, when more than one)."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=figsize, layout="constrained")
    return fig, fig.subplots(rows, 1, sharex=True) if rows > 1 else fig.subplots()


def plot_transfer(filt, *, figsize=(6.0, 4.0)):
    """Measured transfer function, fitted model and filter gain (thesis Figure 4.9).

    A filter that undoes the sensor's phase (rational, wiener) gets a second panel: the
    correction's phase, targeted and realised by the FIR (and the measured bins, wiener).

    Parameters
    ----------
    filt : CorrectionFilter
        With ``fit`` when it came from :func:`fit_filter` (the measured bins are shown).

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> from tactilecal.dynamic import CorrectionFilter
    >>> f = CorrectionFilter.from_model(("log10", {"A": 0.11}), fs_hz=4000, band_hz=(1, 140))
    >>> plot_transfer(f).axes[0].get_xlabel()
    'frequency (Hz)'
    """
    fig, axes = _axes((figsize[0], figsize[1] * 1.6), rows=2) if filt.has_phase else \
        _axes(figsize)
    ax = axes[0] if filt.has_phase else axes
    top = min(filt.fs_hz / 2, filt.band_hz[1] + 2 * filt.taper_hz)
    f = np.linspace(0.0, top, 800)
    if filt.fit is not None:
        ax.plot(filt.fit.f_hz, filt.fit.measured, ".", ms=3, color="0.5",
                label=f"measured ({filt.fit.method}, coherent bins)")
    model = _model_line(filt, f)
    if model is not None:
        ax.plot(f, np.abs(model[1]), "-", color="k", lw=1, label=model[0])
    ax.plot(f, filt.gain(f), "-", color="C3", label=f"filter gain ({filt.outside} above band)")
    ax.plot(f, filt.realised_gain(f), "--", color="C0", lw=1, label=f"FIR, {filt.n_taps} taps")
    for edge in filt.band_hz:
        ax.axvline(edge, color="0.8", lw=0.8)
    pars = ", ".join(f"{k} = {v:.4g}" for k, v in filt.params.items()) \
        if filt.rational is None else filt.rational.describe()
    ax.set(xlabel="frequency (Hz)", ylabel="|reference| / |sensor|",
           title=f"transfer function: {filt.model} ({pars})")
    ax.legend(fontsize="small")
    if filt.has_phase:
        _phase_panel(axes[1], filt, f)
    return fig


def _model_line(filt, f_hz):
    """``(label, complex values)`` of the fitted model without the taper, or None."""
    from tactilecal.dynamic._fit import MODELS, model_gain

    if filt.model in MODELS:
        return f"fitted model: {filt.model}", model_gain(filt.model, filt.params, f_hz)
    if filt.rational is not None:
        return "fitted model: rational", filt.rational.correction(f_hz)
    if filt.model == "wiener":
        keep = f_hz <= filt.band_hz[1]
        return "fitted model: wiener (measured, shrunk)", np.where(keep, filt.target(f_hz),
                                                                   np.nan)
    return None


def _phase_panel(ax, filt, f):
    """Plot the correction's phase (degrees; positive = the filter advances) on ``ax``."""
    if filt.model == "wiener":
        ax.plot(filt.response_f_hz, np.degrees(np.angle(filt.response_gain)), ".", ms=3,
                color="0.5", label="measured (coherent bins, regularised)")
    ax.plot(f, np.degrees(np.angle(filt.target(f))), "-", color="C3", label="correction")
    ax.plot(f, np.degrees(np.angle(filt.realised_target(f))), "--", color="C0", lw=1,
            label=f"FIR, {filt.n_taps} taps")
    ax.axhline(0.0, color="0.8", lw=0.8)
    ax.set(xlabel="frequency (Hz)", ylabel="phase of the correction (deg)")
    ax.legend(fontsize="small")


def plot_time(ev, *, window_s=None, figsize=(8.0, 6.0)):
    """Plot reference, sensor and corrected sensor against time (Figs 4.10, 4.13a, 4.14a).

    Two panels: the whole record (when the evaluation holds it; not after reading
    ``evaluation.json``) and a zoomed window where the reference moves fastest, at the
    evaluated clock. When the evaluation was also scored at the re-aligned clock, a third
    panel shows the window at that clock, labelled as such.

    Parameters
    ----------
    ev : Evaluation
    window_s : tuple of float, optional
        ``(start, stop)`` on the sensor clock of the zoomed panel (default the
        evaluation's ``window``).

    Returns
    -------
    matplotlib.figure.Figure
    """
    whole = ev.time_s.size > 0
    realigned = ev.reference_realigned.size > 0
    from matplotlib.figure import Figure

    rows = int(whole) + 1 + int(realigned)
    fig = Figure(figsize=(figsize[0], figsize[1] * rows / 2), layout="constrained")
    axes = np.atleast_1d(fig.subplots(rows, 1, squeeze=False)[:, 0])
    for ax in axes[int(whole):-1]:  # the zoomed panels share their axis, not the whole's
        ax.sharex(axes[-1])
    if whole:
        _time_lines(axes[0], ev.time_s, ev.reference, ev.sensor, ev.corrected, lw=0.4)
        axes[0].set_title(f"whole record: RMS error of the dynamic part {ev.rms_before_N:.3g} "
                          f"N -> {ev.rms_after_N:.3g} N ({ev.clock} clock)")
    t, w = _window(ev, window_s)
    ax = axes[int(whole)]
    _time_lines(ax, t, w["reference"], w["sensor"], w["corrected"], lw=0.9)
    ax.set_title(f"zoom at the {ev.clock} clock (lag {ev.lag_s:.6g} s); timing error "
                 f"{1e3 * ev.timing_error_s:+.3g} ms")
    if realigned:
        keep = (ev.time_s >= t.min()) & (ev.time_s <= t.max())
        _time_lines(axes[-1], ev.time_s[keep], ev.reference_realigned[keep], ev.sensor[keep],
                    ev.corrected[keep], lw=0.9)
        axes[-1].set_title(f"re-aligned by {1e3 * ev.timing_error_s:+.3g} ms (not what the "
                           f"filter delivers): {ev.rms_after_realigned_N:.3g} N")
    for ax in axes:
        ax.set(ylabel="force (N)")
    axes[-1].set(xlabel="time on the sensor clock (s)")
    axes[0].legend(fontsize="small", loc="upper right")
    return fig


def _window(ev, window_s):
    """Return the zoomed window's time and records (``window_s``, or ``ev.window``)."""
    if window_s is None or not ev.time_s.size:
        return np.asarray(ev.window["time_s"]), ev.window
    keep = (ev.time_s >= window_s[0]) & (ev.time_s <= window_s[1])
    return ev.time_s[keep], {"reference": ev.reference[keep], "sensor": ev.sensor[keep],
                             "corrected": ev.corrected[keep]}


def _time_lines(ax, t, reference, sensor, corrected, *, lw):
    ax.plot(t, reference, color="k", lw=lw, label="reference")
    ax.plot(t, sensor, color="C1", lw=lw, alpha=0.8, label="sensor (static calibration)")
    ax.plot(t, corrected, color="C0", lw=lw, alpha=0.8, label="sensor (static + dynamic)")


def plot_spectra(ev, *, f_max_hz=None, figsize=(8.0, 4.0)):
    """Fourier amplitude spectra of the three records (thesis Figs 4.11, 4.13b, 4.14b).

    Drawn from the evaluation's ``spectra`` (kept in ``evaluation.json``), up to
    ``f_max_hz`` (default all it holds: 1.5 times the filter's band).

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, ax = _axes(figsize)
    spectra = ev.spectra
    f = np.asarray(spectra.get("f_hz", []), float)
    keep = (f > 0) & (f <= (f_max_hz or np.inf))
    for key, label, style in (("reference", "reference", dict(color="k", lw=0.8)),
                              ("sensor", "sensor (static)", dict(color="C1", lw=0.6)),
                              ("corrected", "sensor (static + dynamic)",
                               dict(color="C0", lw=0.6))):
        if key in spectra:
            ax.plot(f[keep], np.asarray(spectra[key], float)[keep], label=label, **style)
    ax.axvline(ev.band_hz[1], color="0.7", lw=0.8, label="top of the filter's band")
    ax.set(xlabel="frequency (Hz)", ylabel="Fourier amplitude (N)", yscale="log",
           title="Fourier amplitude spectra (largest per bin group; log scale)")
    ax.legend(fontsize="small")
    return fig


def plot_error(ev, *, figsize=(6.0, 4.0)):
    """Percent amplitude error against frequency before/after correction (Figure 4.12).

    A second panel shows the phase error against frequency before and after.

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, axes = _axes((figsize[0], figsize[1] * 1.6), rows=2)
    ax = axes[0]
    axes[1].axhline(0.0, color="0.7", lw=0.8)
    axes[1].plot(ev.f_hz, ev.phase_before_deg, ".", ms=3, color="C1", label="static only")
    axes[1].plot(ev.f_hz, ev.phase_after_deg, ".", ms=3, color="C0", label="static + dynamic")
    axes[1].set(xlabel="frequency (Hz)", ylabel="phase error (deg)")
    ax.axhline(0.0, color="0.7", lw=0.8)
    ax.plot(ev.f_hz, ev.error_before_pct, ".", ms=3, color="C1", label="static only")
    ax.plot(ev.f_hz, ev.error_after_pct, ".", ms=3, color="C0", label="static + dynamic")
    ax.set(xlabel="frequency (Hz)", ylabel="amplitude error (%)",
           title=f"error against the reference (coherent bins, {ev.clock} clock)")
    ax.legend(fontsize="small")
    return fig
