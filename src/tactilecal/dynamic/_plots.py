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
    ax.plot(f, filt.gain(f), "-", color="C3", label=f"filter gain ({filt.outside} above band)")
    ax.plot(f, filt.realised_gain(f), "--", color="C0", lw=1, label=f"FIR, {filt.n_taps} taps")
    for edge in filt.band_hz:
        ax.axvline(edge, color="0.8", lw=0.8)
    pars = ", ".join(f"{k} = {v:.4g}" for k, v in filt.params.items())
    ax.set(xlabel="frequency (Hz)", ylabel="|reference| / |sensor|",
           title=f"transfer function: {filt.model} ({pars})")
    ax.legend(fontsize="small")
    if filt.has_phase:
        _phase_panel(axes[1], filt, f)
    return fig


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


def plot_time(ev, *, window_s=None, figsize=(8.0, 4.0)):
    """Plot reference, sensor and corrected sensor against time (Figs 4.10, 4.13a, 4.14a).

    Parameters
    ----------
    ev : Evaluation
    window_s : tuple of float, optional
        ``(start, stop)`` on the sensor clock (default the whole overlap).

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, ax = _axes(figsize)
    t = ev.time_s
    keep = slice(None) if window_s is None else (t >= window_s[0]) & (t <= window_s[1])
    ax.plot(t[keep], ev.reference[keep], color="k", lw=0.8, label="reference")
    ax.plot(t[keep], ev.sensor[keep], color="C1", lw=0.6, alpha=0.8,
            label="sensor (static calibration)")
    ax.plot(t[keep], ev.corrected[keep], color="C0", lw=0.6, alpha=0.8,
            label="sensor (static + dynamic)")
    ax.set(xlabel="time on the sensor clock (s)", ylabel="force (N)",
           title=f"RMS error of the dynamic part: {ev.rms_before_N:.3g} N -> "
                 f"{ev.rms_after_N:.3g} N")
    ax.legend(fontsize="small")
    return fig


def plot_spectra(ev, *, f_max_hz=None, figsize=(8.0, 4.0)):
    """Fourier amplitude spectra of the three records (thesis Figs 4.11, 4.13b, 4.14b).

    Returns
    -------
    matplotlib.figure.Figure
    """
    from scipy import fft

    fig, ax = _axes(figsize)
    n = ev.reference.size
    f = fft.rfftfreq(n, 1.0 / ev.fs_hz)
    top = f_max_hz or (1.5 * ev.f_hz.max() if ev.f_hz.size else ev.fs_hz / 2)
    keep = (f > 0) & (f <= top)
    for values, label, style in ((ev.reference, "reference", dict(color="k", lw=0.8)),
                                 (ev.sensor, "sensor (static)", dict(color="C1", lw=0.6)),
                                 (ev.corrected, "sensor (static + dynamic)",
                                  dict(color="C0", lw=0.6))):
        amp = 2.0 * np.abs(fft.rfft(values - values.mean())) / n
        ax.plot(f[keep], amp[keep], label=label, **style)
    ax.set(xlabel="frequency (Hz)", ylabel="Fourier amplitude (N)", yscale="log",
           title="Fourier amplitude spectra (log scale: loading ramps dominate below 1 Hz)")
    ax.legend(fontsize="small")
    return fig


def plot_error(ev, *, figsize=(6.0, 4.0)):
    """Percent amplitude error against frequency before/after correction (Figure 4.12).

    With the evaluation's phase errors (``ev.phase_before_deg``), a second panel shows the
    phase error against frequency before and after.

    Returns
    -------
    matplotlib.figure.Figure
    """
    phase = ev.phase_before_deg is not None
    fig, axes = _axes((figsize[0], figsize[1] * 1.6), rows=2) if phase else _axes(figsize)
    ax = axes[0] if phase else axes
    if phase:
        axes[1].axhline(0.0, color="0.7", lw=0.8)
        axes[1].plot(ev.f_hz, ev.phase_before_deg, ".", ms=3, color="C1", label="static only")
        axes[1].plot(ev.f_hz, ev.phase_after_deg, ".", ms=3, color="C0",
                     label="static + dynamic")
        axes[1].set(xlabel="frequency (Hz)", ylabel="phase error (deg)")
    ax.axhline(0.0, color="0.7", lw=0.8)
    ax.plot(ev.f_hz, ev.error_before_pct, ".", ms=3, color="C1", label="static only")
    ax.plot(ev.f_hz, ev.error_after_pct, ".", ms=3, color="C0", label="static + dynamic")
    ax.set(xlabel="frequency (Hz)", ylabel="amplitude error (%)",
           title="error against the reference (coherent bins)")
    ax.legend(fontsize="small")
    return fig
