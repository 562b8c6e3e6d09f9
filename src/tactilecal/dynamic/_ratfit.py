"""Fit rational (pole-zero) sensor responses to a complex transfer function, choose the structure.

A linear sensor's response ``H = sensor / reference`` with unit gain at 0 Hz (the sweep was
scaled statically) is a product of sections, each 1 at 0 Hz:

* real corners of a viscoelastic solid, ``(1 + j f/fz)`` over ``(1 + j f/fp)`` (creep,
  compliant foam or mounting relax with real time constants; METHOD-NOTES D);
* complex pairs, second-order sections ``1 - (f/fn)^2 + 2 j zeta f/fn`` with natural
  frequency ``fn`` and damping ``zeta`` in (0, 1): a pair of poles is a mounting resonance, a
  pair of zeros an anti-resonance (METHOD-NOTES G).

Every corner and pair lies in the left half-plane, so ``H`` is minimum-phase and stable and
``1 / H`` a stable causal correction. ``H`` may have more poles than zeros (a resonance): its
inverse is then improper, which the correction filter handles by tapering to 1 above the
band. Each section's parameters (log corner frequencies, damping) are fitted with
:func:`scipy.optimize.least_squares` on the real and imaginary parts of ``(C - 1/H e^{-j 2 pi
f tau}) / (e |C|)`` over the coherent bins, jointly with a delay ``tau`` (``C`` the measured
correction reference / sensor, ``e`` each bin's random error, Bendat & Piersol eq. 9.90).
The structures of :data:`STRUCTURES` are tried; the structure is chosen by the error on
held-out blocks of bins (cross-validation, :func:`held_out_score`), the one with the fewest
parameters within ``MIN_IMPROVEMENT`` of the best.
"""

from dataclasses import dataclass

import numpy as np
from scipy import optimize

from tactilecal._errors import TactilecalError
from tactilecal.dynamic._fit import complex_r2
from tactilecal.dynamic._rational import RationalModel

__all__ = ["Structure", "STRUCTURES", "RationalFit", "fit_rational", "choose_rational",
           "held_out_bins", "held_out_score", "delayed", "section_bounds_hz", "at_edge"]

HELD_OUT_EVERY = 4
#: Consecutive bins held out together: Welch's Hann window spreads a tone over about four
#: bins, so neighbouring bins are correlated and a single held-out bin would be "predicted"
#: by its own leakage into the bins beside it (which flatters an interpolating model).
HELD_OUT_BLOCK = 4
#: A structure with more parameters must lower the held-out error by this share to be kept.
MIN_IMPROVEMENT = 0.10
#: Highest corner or natural frequency, as a share of the Nyquist frequency (a causal,
#: bilinear inverse can still place it).
MAX_CORNER_NYQUIST = 0.8
#: Corners and natural frequencies stay within this factor of the fitted bins' range: a
#: section far outside the band is not identified by the sweep; inside the band its
#: phase is nearly proportional to frequency, a delay, and it would trade off with the
#: delay fitted jointly (a pole pair at 343 Hz, damping 0.82, stood in for the thesis' log
#: law on a 1-148 Hz sweep and moved the clock by 0.8 ms).
SECTION_MARGIN = 2.0
#: A held-out error below this (1 % of the correction, about the resolution of an 8-bit
#: sensel at mid-range) is immaterial: a model this good is not replaced by one with more
#: parameters, however much better that one fits a long, clean sweep (which resolves 0.1 %).
MATERIAL_ERROR = 0.01
#: Bounds of the delay fitted jointly with a model: the clocks were aligned by
#: cross-correlation, which takes part of the sensor's group delay for clock offset.
MAX_DELAY_MS = 20.0
#: A section within this share of its bounds is at the edge (:func:`at_edge`).
EDGE = 0.02
#: Most residual evaluations of one least-squares fit (a structure with more sections than
#: the response needs wanders among poles that cancel zeros; 300 keep the others' fits).
MAX_EVALUATIONS = 300
#: Damping of a complex pair: above 0 (stable) and below 1 (a pair, not two real roots).
DAMPING_BOUNDS = (0.005, 0.995)


def held_out_score(measured, predicted, gain_error):
    """Relative error of a model on held-out bins: RMS of ``|C - model| / |C|``, weighted.

    Each bin is weighted by ``1 / e^2``, ``e`` its gain's normalised random error (Bendat &
    Piersol eq. 9.90; the phase's error in radians is the same number), so noisy bins at
    the band's edges do not outweigh clean ones. 0.01 is a 1 % error of the correction.
    """
    measured = np.asarray(measured, dtype=complex)
    weight = 1.0 / np.maximum(np.asarray(gain_error, dtype=float), 1e-9) ** 2
    relative = np.abs(measured - predicted) ** 2 / np.abs(measured) ** 2
    return float(np.sqrt(np.sum(weight * relative) / np.sum(weight)))


def held_out_bins(n_bins):
    """Mask of the held-out bins: every ``HELD_OUT_EVERY``-th block of ``HELD_OUT_BLOCK``."""
    block = np.arange(n_bins) // HELD_OUT_BLOCK
    return block % HELD_OUT_EVERY == HELD_OUT_EVERY // 2


def delayed(correction, delay_s, f_hz):
    """``correction`` times the delay ``exp(-j 2 pi f delay_s)``: a model's measured ``C``.

    The measured correction ``C`` of records aligned at lag ``L`` is that of records aligned
    at the clock offset ``L - delay_s`` times this factor.
    """
    return correction * np.exp(-2j * np.pi * np.asarray(f_hz, float) * delay_s)


@dataclass(frozen=True)
class Structure:
    """Sections of a rational response: real zeros and poles, complex pairs of each.

    Examples
    --------
    >>> Structure(poles=1, zeros=1).label, Structure(pole_pairs=1).n_params
    ('1 zero, 1 pole', 2)
    """

    zeros: int = 0
    poles: int = 0
    zero_pairs: int = 0
    pole_pairs: int = 0

    @property
    def n_params(self):
        """Number of parameters (a corner each, a frequency and a damping per pair)."""
        return self.zeros + self.poles + 2 * (self.zero_pairs + self.pole_pairs)

    @property
    def label(self):
        """The structure in words (``"1 zero, 1 pole, 1 pole pair"``)."""
        words = [(self.zeros, "zero"), (self.poles, "pole"), (self.zero_pairs, "zero pair"),
                 (self.pole_pairs, "pole pair")]
        return ", ".join(f"{n} {w}{'s' if n > 1 else ''}" for n, w in words if n)

    def as_params(self):
        """Return the structure as a filter's ``params`` (numbers, for FILTER.json)."""
        return {"zeros": self.zeros, "poles": self.poles, "zero_pairs": self.zero_pairs,
                "pole_pairs": self.pole_pairs}

    @property
    def bounds(self):
        """Where each part of ``[delay_ms, log fz.., log fp.., (log fn, zeta)..]`` ends.

        ``(a, b, c)``: the zero corners are ``x[1:a]``, the pole corners ``x[a:b]``, the zero
        pairs ``x[b:c]`` and the pole pairs ``x[c:]``.
        """
        a = 1 + self.zeros
        b = a + self.poles
        return a, b, b + 2 * self.zero_pairs

    def split(self, x):
        """Split ``[delay_ms, log fz.., log fp.., (log fn, zeta)..]`` into its parts.

        Returns the delay (ms), the real zero and pole corners (Hz), and the zero and pole
        pairs as ``(fn_hz, damping)`` rows.
        """
        x = np.asarray(x, dtype=float)
        a, b, c = self.bounds
        zp, pp = x[b:c].reshape(-1, 2), x[c:].reshape(-1, 2)
        return (x[0], np.exp(x[1:a]), np.exp(x[a:b]),
                np.column_stack([np.exp(zp[:, 0]), zp[:, 1]]),
                np.column_stack([np.exp(pp[:, 0]), pp[:, 1]]))

    def model(self, x):
        """:class:`RationalModel` (unit gain at 0 Hz) and delay (s) of a parameter vector."""
        delay_ms, fz, fp, zero_pairs, pole_pairs = self.split(x)
        return RationalModel.from_corners_hz(
            zeros_hz=fz, poles_hz=fp, zero_pairs=[tuple(p) for p in zero_pairs],
            pole_pairs=[tuple(p) for p in pole_pairs]), float(delay_ms) * 1e-3

    def correction(self, x, f_hz, *, jacobian=False):
        """Return the delayed correction ``e^{-j 2 pi f tau} / H`` of the parameters.

        With ``jacobian=True`` also the derivatives of its logarithm with respect to each
        parameter (rows: parameters of ``x``, columns: bins): ``dC/dx = C d ln C/dx``.
        """
        c, dlog = _Sections(self, np.asarray(f_hz, dtype=float)).evaluate(x)
        return (c, dlog) if jacobian else c


class _Sections:
    """A structure's correction on fixed bins, evaluated section by section.

    ``C = e^{-j 2 pi f tau} prod (1 + j f/fp) / prod (1 + j f/fz) prod q_p / prod q_z`` with
    ``q = 1 - u^2 + 2 j zeta u``, ``u = f / fn`` for each pair, and ``d ln C / dx`` for each
    parameter ``x`` (log corners, log natural frequencies, dampings, the delay in ms).
    """

    def __init__(self, structure, f_hz):
        self.structure = structure
        self.f_hz = f_hz
        self.delay_row = -2e-3j * np.pi * f_hz  # d ln C / d tau_ms
        self.jf = 1j * f_hz

    def evaluate(self, x):
        """Return ``C`` and ``d ln C / dx`` (rows: parameters, columns: bins)."""
        s, f_hz = self.structure, self.f_hz
        x = np.asarray(x, dtype=float)
        a, b, _ = s.bounds
        dlog = np.empty((x.size, f_hz.size), complex)
        dlog[0] = self.delay_row
        c = np.exp(self.delay_row * x[0])
        term = self.jf / np.exp(x[1:b])[:, None]  # j f / f_corner, zeros then poles
        one = 1 + term
        for k in range(s.zeros):  # C divides by (1 + j f / fz); d/d ln fz of -ln(1 + j f/fz)
            c = c / one[k]
        for k in range(s.zeros, b - 1):  # C multiplies by (1 + j f / fp)
            c = c * one[k]
        dlog[1:a] = term[:s.zeros] / one[:s.zeros]
        dlog[a:b] = -term[s.zeros:] / one[s.zeros:]
        row = b
        for sign, n in ((-1.0, s.zero_pairs), (1.0, s.pole_pairs)):
            pairs = x[row:row + 2 * n].reshape(-1, 2)
            for fn, zeta in zip(np.exp(pairs[:, 0]), pairs[:, 1], strict=True):
                u = f_hz / fn
                q = 1 - u**2 + 2j * zeta * u
                c = c * q if sign > 0 else c / q
                dlog[row] = sign * (2 * u**2 - 2j * zeta * u) / q
                dlog[row + 1] = sign * 2j * u / q
                row += 2
        return c, dlog


#: The structures :func:`choose_rational` tries, by number of parameters: real corners
#: (orders 1-4 of zeros = poles), a single pole, a resonance (pole pair), an anti-resonance
#: (zero pair), a corner pair with a resonance, a resonance with an anti-resonance.
STRUCTURES = (
    Structure(poles=1), Structure(zeros=1, poles=1), Structure(pole_pairs=1),
    Structure(zero_pairs=1),
    Structure(zeros=2, poles=2), Structure(zeros=1, poles=1, pole_pairs=1),
    Structure(zero_pairs=1, pole_pairs=1), Structure(zeros=3, poles=3),
    Structure(zeros=2, poles=2, pole_pairs=1), Structure(zeros=4, poles=4),
)


@dataclass(frozen=True)
class RationalFit:
    """A rational model fitted to a measured complex correction.

    Attributes
    ----------
    model : RationalModel
        The sensor response ``H`` (its :meth:`~RationalModel.correction` is the fitted ``C``).
    structure : Structure
        Its sections.
    r2_complex : float
        Share of the complex correction explained on all used bins (:func:`complex_r2`).
    held_out_error : float
        :func:`held_out_score` of the held-out bins (the model was fitted without them).
    candidates : dict
        ``{structure label: held_out_error}`` of every structure tried (``inf`` when its
        fit failed).
    delay_s : float
        The delay fitted jointly: the part of the sensor's group delay that the clock
        alignment took for clock offset.
    """

    model: RationalModel
    structure: Structure
    r2_complex: float
    held_out_error: float
    candidates: dict
    delay_s: float = 0.0

    def summary(self):
        """Return a one-line description with the sections."""
        return (f"rational ({self.structure.label}): {self.model.describe()}, delay "
                f"{1e3 * self.delay_s:.3g} ms; complex R2 {self.r2_complex:.4f}, held-out "
                f"error {self.held_out_error:.2%}")


class _Objective:
    """Weighted residuals of one fit and their Jacobian, from one shared evaluation.

    The residuals are the real and imaginary parts of ``w (C_measured - C(x))``; the
    least-squares solver asks for the Jacobian at the parameters whose residuals it has just
    accepted, so the last evaluation (``C`` and ``d ln C / dx``) is kept for it.
    """

    def __init__(self, structure, f_hz, measured, weight):
        self.sections = _Sections(structure, f_hz)
        self.measured, self.weight = measured, weight
        self._x = self._c = self._dlog = None

    def _evaluate(self, x):
        key = np.asarray(x, dtype=float).tobytes()
        if key != self._x:
            self._c, self._dlog = self.sections.evaluate(x)
            self._x = key
        return self._c, self._dlog

    def residuals(self, x):
        """Return ``w (C_measured - C(x))``, real parts then imaginary parts."""
        diff = self.weight * (self.measured - self._evaluate(x)[0])
        return np.concatenate([diff.real, diff.imag])

    def jacobian(self, x):
        """Return the derivatives of :meth:`residuals` (rows: real, then imaginary parts)."""
        c, dlog = self._evaluate(x)
        d = -(self.weight * c) * dlog  # parameters x bins
        return np.concatenate([d.real, d.imag], axis=1).T


def section_bounds_hz(f_hz, fs_hz=None):
    """Range of corners and natural frequencies: the bins' range widened by ``SECTION_MARGIN``.

    Capped at ``MAX_CORNER_NYQUIST`` of the Nyquist frequency when ``fs_hz`` is given.
    """
    low = max(float(np.min(f_hz)), 1e-3) / SECTION_MARGIN
    high = float(np.max(f_hz)) * SECTION_MARGIN
    if fs_hz is not None:
        high = min(high, MAX_CORNER_NYQUIST * fs_hz / 2)
    return low, high


def _starts(structure, f_hz, measured, lo, hi, delay_ms):
    """Return starting vectors: corners spread over the band, pairs at the extremes of |C|.

    A pole pair starts at the bin where ``|C|`` is smallest (the resonance reads high), a zero
    pair where it is largest, with dampings 0.05 and 0.3. The corners' grid is also tried
    shifted by half a step; a structure without real corners has no grid to shift (the same
    start twice would only repeat its fit).
    """
    n_real = structure.zeros + structure.poles
    dip, peak = (np.log(f_hz[np.argmin(np.abs(measured))]),
                 np.log(f_hz[np.argmax(np.abs(measured))]))
    starts = []
    for shift in (0.0, 0.5) if n_real else (0.0,):
        grid = np.linspace(lo, hi, 2 * max(n_real, 1) + 2)[1:-1]
        grid = grid + shift * (grid[1] - grid[0])
        corners = grid[:n_real]
        zeros, poles = corners[1::2][:structure.zeros], corners[0::2][:structure.poles]
        if zeros.size < structure.zeros or poles.size < structure.poles:  # poles alone
            poles = corners[:structure.poles]
            zeros = corners[structure.poles:]
        for zeta in ((0.05, 0.3) if structure.zero_pairs + structure.pole_pairs else (None,)):
            pairs = [[peak, zeta]] * structure.zero_pairs + [[dip, zeta]] * structure.pole_pairs
            starts.append(np.concatenate([[delay_ms], zeros, poles, *pairs]))
    return starts


def fit_rational(f_hz, correction, gain_error, structure, *, fit_mask=None, fs_hz=None,
                 delay_s=0.0):
    """Fit a rational response of one structure to a measured correction.

    Parameters
    ----------
    f_hz, correction, gain_error : array_like
        Used bins: frequency, measured complex ``C`` = reference / sensor, its normalised
        random error (:class:`TransferFunction` ``.gain_error``).
    structure : Structure
    fit_mask : array_like of bool, optional
        Bins to fit (the rest are held out); default all.
    fs_hz : float, optional
        Sampling rate: corners and natural frequencies are kept below
        ``MAX_CORNER_NYQUIST`` of its Nyquist frequency, and within ``SECTION_MARGIN`` of
        the bins' range (:func:`section_bounds_hz`).
    delay_s : float
        Starting delay (within ``MAX_DELAY_MS`` of which the delay is fitted).

    Returns
    -------
    (RationalModel, float)
        The sensor response and the delay in s fitted jointly with it.
    """
    f_hz = np.asarray(f_hz, dtype=float)
    measured = np.asarray(correction, dtype=complex)
    weight = 1.0 / (np.maximum(np.asarray(gain_error, dtype=float), 1e-6) * np.abs(measured))
    mask = np.ones(f_hz.size, bool) if fit_mask is None else np.asarray(fit_mask, bool)
    low, high = section_bounds_hz(f_hz, fs_hz)
    lo, hi = np.log(low), np.log(high)
    n_real, n_pairs = structure.zeros + structure.poles, structure.zero_pairs + structure.pole_pairs
    lower = np.r_[1e3 * delay_s - MAX_DELAY_MS, [lo] * n_real, [lo, DAMPING_BOUNDS[0]] * n_pairs]
    upper = np.r_[1e3 * delay_s + MAX_DELAY_MS, [hi] * n_real, [hi, DAMPING_BOUNDS[1]] * n_pairs]
    objective = _Objective(structure, f_hz[mask], measured[mask], weight[mask])
    best = None
    for start in _starts(structure, f_hz[mask], measured[mask], lo, hi, 1e3 * delay_s):
        sol = optimize.least_squares(
            objective.residuals, np.clip(start, lower + 1e-9, upper - 1e-9),
            jac=objective.jacobian, bounds=(lower, upper), max_nfev=MAX_EVALUATIONS)
        if best is None or sol.cost < best.cost:
            best = sol
    return structure.model(best.x)


def choose_rational(f_hz, correction, gain_error, *, structures=STRUCTURES, fs_hz=None,
                    delay_s=0.0):
    """Fit every structure, choose by held-out bins; return the :class:`RationalFit`.

    Every ``HELD_OUT_EVERY``-th block of bins is held out (:func:`held_out_bins`); each
    structure is fitted on the others and scored on the held-out ones by
    :func:`held_out_score`. A structure with a section at the edge of the band
    (:func:`at_edge`) is not a candidate. Of the structures within ``MIN_IMPROVEMENT`` of
    the best score, the one with the fewest parameters wins (the lower score on a tie); it is
    then refitted on all bins (and dropped if its sections then reach the edge). ``fs_hz``
    bounds the corners, ``delay_s`` starts the delay (see :func:`fit_rational`).

    Raises
    ------
    TactilecalError
        Fewer than ``4 * (largest parameter count + 1)`` bins.
    """
    f_hz = np.asarray(f_hz, dtype=float)
    correction = np.asarray(correction, dtype=complex)
    gain_error = np.asarray(gain_error, dtype=float)
    need = max(4 * (max(s.n_params for s in structures) + 1), HELD_OUT_EVERY * HELD_OUT_BLOCK)
    if f_hz.size < need:
        raise TactilecalError(f"{f_hz.size} coherent bins; a rational fit with up to "
                              f"{max(s.n_params for s in structures)} parameters needs at "
                              f"least {need}")
    held = held_out_bins(f_hz.size)
    bounds = section_bounds_hz(f_hz, fs_hz)
    scores = {}
    for structure in structures:
        try:
            model, delay = fit_rational(f_hz, correction, gain_error, structure,
                                        fit_mask=~held, fs_hz=fs_hz, delay_s=delay_s)
        except (ValueError, np.linalg.LinAlgError):
            scores[structure] = float("inf")
            continue
        predicted = delayed(model.correction(f_hz[held]), delay, f_hz[held])
        scores[structure] = (float("inf") if at_edge(model, *bounds) else
                             held_out_score(correction[held], predicted, gain_error[held]))
    while np.isfinite(best := min(scores.values())):
        good = [s for s in structures if scores[s] <= best * (1 + MIN_IMPROVEMENT)]
        chosen = min(good, key=lambda s: (s.n_params, scores[s]))
        model, delay = fit_rational(f_hz, correction, gain_error, chosen, fs_hz=fs_hz,
                                    delay_s=delay_s)
        if not at_edge(model, *bounds):
            r2 = complex_r2(correction, delayed(model.correction(f_hz), delay, f_hz))
            return RationalFit(model, chosen, r2, scores[chosen],
                               {s.label: scores[s] for s in structures}, delay)
        scores[chosen] = float("inf")  # refitted on every bin, it went to the edge
    raise TactilecalError(f"no rational structure could be fitted to the {f_hz.size} coherent "
                          "bins with its sections inside the band")


def at_edge(model, low_hz, high_hz):
    """Return True when a section of ``model`` sits at the edge of what the band identifies.

    A corner or natural frequency within ``EDGE`` of ``low_hz`` or ``high_hz``
    (:func:`section_bounds_hz`), or a damping within ``EDGE`` of its bounds: the fit wanted
    it further out, where the sweep says nothing about it, and inside the band it only
    stands in for something else (a delay, a slowly rising gain).
    """
    sections = model.sections()
    frequencies = [*sections["zeros_hz"], *sections["poles_hz"],
                   *(f for f, _ in sections["zero_pairs"] + sections["pole_pairs"])]
    dampings = [z for _, z in sections["zero_pairs"] + sections["pole_pairs"]]
    return (any(f <= low_hz * (1 + EDGE) or f >= high_hz / (1 + EDGE) for f in frequencies)
            or any(z <= DAMPING_BOUNDS[0] * (1 + EDGE) or z >= DAMPING_BOUNDS[1] / (1 + EDGE)
                   for z in dampings))
