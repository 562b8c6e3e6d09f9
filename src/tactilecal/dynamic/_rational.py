"""Rational (pole-zero) model of a sensor's complex dynamic response.

A linear viscoelastic sensor (creep, compliant mounting) responds to a load with
``H(s) = k prod(s - z_i) / prod(s - p_i)``, ``s = 2 pi j f`` (METHOD-NOTES D: the standard linear
solid ``H(f) = (1 + j f/f1) / (1 + j f/f2)`` is the first-order case). A mounting resonance is a
complex pair of poles, ``1 / (1 - (f/fn)^2 + 2 j zeta f/fn)`` (METHOD-NOTES G), a second-order
section no product of real first-order terms describes. ``H`` is the *sensor's* response,
sensor / reference; the correction that undoes it is ``G = 1 / H``, causal and stable when
``H`` is minimum-phase (zeros and poles in the left half-plane). ``H`` may have more poles
than zeros (a resonance: its inverse is improper, its gain grows without bound): the
correction filter then follows it in the calibrated band and tapers to 1 above it.
"""

from dataclasses import dataclass

import numpy as np

from tactilecal._errors import TactilecalError

__all__ = ["RationalModel"]


@dataclass(frozen=True)
class RationalModel:
    """Analog zeros, poles (rad/s) and gain of a sensor response ``H = sensor / reference``.

    Parameters
    ----------
    zeros_rad_s, poles_rad_s : tuple of complex
        Zeros and poles of ``H(s)`` in rad/s (complex ones in conjugate pairs).
    gain : float
        ``k`` in ``H(s) = k prod(s - z) / prod(s - p)``.

    Examples
    --------
    Standard linear solid with corners at 10 Hz (zero) and 40 Hz (pole), unit DC gain:

    >>> w1, w2 = 2 * np.pi * 10, 2 * np.pi * 40
    >>> m = RationalModel.from_corners_hz(zeros_hz=[10.0], poles_hz=[40.0])
    >>> h = m.response([0.0, 1e6])
    >>> np.round(np.abs(h), 3).tolist()
    [1.0, 4.0]
    >>> m.is_minimum_phase
    True
    """

    zeros_rad_s: tuple
    poles_rad_s: tuple
    gain: float

    @classmethod
    def from_corners_hz(cls, *, zeros_hz=(), poles_hz=(), zero_pairs=(), pole_pairs=()):
        """Zeros and poles from corner frequencies, with the gain that makes ``H(0) = 1``.

        Parameters
        ----------
        zeros_hz, poles_hz : sequence of float
            Real zeros and poles at ``-2 pi f``.
        zero_pairs, pole_pairs : sequence of (float, float)
            Complex pairs ``(fn_hz, damping)``: roots ``2 pi fn (-zeta +- j sqrt(1 - zeta^2))``
            (a pole pair is the resonance ``1 / (1 - (f/fn)^2 + 2 j zeta f/fn)``).

        Examples
        --------
        >>> m = RationalModel.from_corners_hz(pole_pairs=[(80.0, 0.05)])
        >>> round(float(abs(m.response(80.0))), 6), m.sections()["pole_pairs"]
        (10.0, [(80.0, 0.05)])
        """
        zeros = tuple(complex(-2 * np.pi * f) for f in zeros_hz) + _pairs(zero_pairs)
        poles = tuple(complex(-2 * np.pi * f) for f in poles_hz) + _pairs(pole_pairs)
        gain = float(np.real(np.prod(-np.asarray(poles)) / np.prod(-np.asarray(zeros))))
        return cls(zeros, poles, gain)

    def sections(self):
        """Real corners (Hz) and complex pairs ``(fn_hz, damping)`` of the zeros and poles."""
        out = {}
        for kind, roots in (("zero", self.zeros_rad_s), ("pole", self.poles_rad_s)):
            roots = [complex(r) for r in roots]
            out[f"{kind}s_hz"] = sorted(round(-r.real / (2 * np.pi), 10) for r in roots
                                        if r.imag == 0)
            out[f"{kind}_pairs"] = sorted((round(abs(r) / (2 * np.pi), 10),
                                           round(-r.real / abs(r), 10))
                                          for r in roots if r.imag > 0)
        return out

    def describe(self):
        """Return the sections in words (corners in Hz, pairs with their damping)."""
        sec = self.sections()
        parts = []
        for kind in ("zero", "pole"):
            parts += [f"{kind} {f:.4g} Hz" for f in sec[f"{kind}s_hz"]]
            parts += [f"{kind} pair {f:.4g} Hz (damping {z:.3g})" for f, z in sec[f"{kind}_pairs"]]
        return ", ".join(parts) or "no zeros or poles"

    @property
    def excess_poles(self):
        """Poles minus zeros: > 0 when the inverse ``1 / H`` is improper."""
        return len(self.poles_rad_s) - len(self.zeros_rad_s)

    def response(self, f_hz):
        """Complex ``H(j 2 pi f)`` (sensor / reference) at frequencies ``f_hz``."""
        s = 2j * np.pi * np.asarray(f_hz, dtype=float)
        num = np.prod([s - z for z in self.zeros_rad_s], axis=0) if self.zeros_rad_s else 1.0
        den = np.prod([s - p for p in self.poles_rad_s], axis=0) if self.poles_rad_s else 1.0
        return self.gain * num / den * np.ones_like(s)

    def correction(self, f_hz):
        """Complex correction gain ``G = 1 / H`` (reference / sensor)."""
        return 1.0 / self.response(f_hz)

    @property
    def is_minimum_phase(self):
        """True when every zero and pole lies in the open left half-plane."""
        return all(np.real(r) < 0 for r in (*self.zeros_rad_s, *self.poles_rad_s))

    def to_dict(self):
        """JSON-ready dict: ``zeros_rad_s``/``poles_rad_s`` as ``[re, im]`` pairs, ``gain``."""
        return {"zeros_rad_s": [[z.real, z.imag] for z in map(complex, self.zeros_rad_s)],
                "poles_rad_s": [[p.real, p.imag] for p in map(complex, self.poles_rad_s)],
                "gain": float(self.gain)}

    @classmethod
    def from_dict(cls, d):
        """Inverse of :meth:`to_dict`."""
        return cls(tuple(complex(re, im) for re, im in d["zeros_rad_s"]),
                   tuple(complex(re, im) for re, im in d["poles_rad_s"]), float(d["gain"]))

    def inverse_sos(self, fs_hz, *, rolloff_hz=None):
        """Second-order sections of the causal correction ``1 / H`` at ``fs_hz``.

        Bilinear transform with every root prewarped (its natural frequency ``w -> 2 fs
        tan(w / 2 fs)``, its damping kept), so the digital corners and resonances sit at the
        analog ones; the DC gain is kept. ``1 / H`` has the poles of ``H`` as zeros and its
        zeros as poles: stable because ``H`` is minimum-phase. When ``H`` has more poles than
        zeros (:attr:`excess_poles`), ``1 / H`` is improper: as many real poles at
        ``rolloff_hz`` make it proper (a roll-off above the band; it also shifts the phase in
        the band, which the offline filter does not).

        Raises
        ------
        ValueError
            If ``H`` is not minimum-phase, a root lies at or above the Nyquist frequency, or
            the inverse is improper and no ``rolloff_hz`` below the Nyquist frequency is given.
        """
        from scipy import signal

        if not self.is_minimum_phase:
            raise TactilecalError("the sensor response has zeros or poles in the right half-plane; "
                                  "expected a minimum-phase model (its inverse would be unstable)")
        nyquist_rad_s = np.pi * fs_hz
        top = max((abs(complex(r)) for r in (*self.zeros_rad_s, *self.poles_rad_s)), default=0.0)
        if top >= nyquist_rad_s:
            raise TactilecalError(f"a corner at {top / (2 * np.pi):.4g} Hz is at or above "
                                  f"the Nyquist frequency {fs_hz / 2:g} Hz; expected corners "
                                  f"below it")
        extra = ()
        if self.excess_poles > 0:
            if rolloff_hz is None or not 0 < rolloff_hz < fs_hz / 2:
                raise TactilecalError(f"the inverse of a response with {self.excess_poles} more "
                                      "poles than zeros is improper; expected rolloff_hz below "
                                      f"the Nyquist frequency {fs_hz / 2:g} Hz (got {rolloff_hz})")
            extra = (complex(-2 * np.pi * rolloff_hz),) * self.excess_poles

        def warp(roots):
            return [r * 2 * fs_hz * np.tan(abs(r) / (2 * fs_hz)) / abs(r)
                    for r in map(complex, roots)]

        zeros, poles = warp(self.poles_rad_s), warp((*self.zeros_rad_s, *extra))  # of 1 / H
        z, p, k = signal.bilinear_zpk(zeros, poles, 1.0, fs=fs_hz)
        sos = signal.zpk2sos(z, p, k)
        _, h0 = signal.sosfreqz(sos, worN=[0.0], fs=fs_hz)
        sos[0, :3] *= 1.0 / (self.response([0.0])[0].real * h0[0].real)
        return sos


def _pairs(pairs):
    """Conjugate roots (rad/s) of complex pairs ``(fn_hz, damping)``, each pair's two roots."""
    out = []
    for fn_hz, zeta in pairs:
        if not (np.isfinite(fn_hz) and fn_hz > 0 and 0 < zeta < 1):
            raise TactilecalError(f"pair ({fn_hz}, {zeta}); expected (fn_hz > 0, 0 < damping < 1)")
        w = 2 * np.pi * fn_hz
        root = complex(-zeta * w, w * np.sqrt(1 - zeta**2))
        out += [root, root.conjugate()]
    return tuple(out)
