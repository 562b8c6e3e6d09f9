"""Rational (pole-zero) model of a sensor's complex dynamic response.

A linear viscoelastic sensor (creep, compliant mounting) responds to a load with
``H(s) = k prod(s - z_i) / prod(s - p_i)``, ``s = 2 pi j f`` (METHOD-NOTES D: the standard linear
solid ``H(f) = (1 + j f/f1) / (1 + j f/f2)`` is the first-order case). ``H`` is the *sensor's*
response, sensor / reference; the correction that undoes it is ``G = 1 / H``, causal and stable
when ``H`` is minimum-phase (zeros and poles in the left half-plane).
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
    def from_corners_hz(cls, *, zeros_hz=(), poles_hz=()):
        """Real zeros/poles at ``-2 pi f`` with the gain that makes ``H(0) = 1``."""
        zeros = tuple(complex(-2 * np.pi * f) for f in zeros_hz)
        poles = tuple(complex(-2 * np.pi * f) for f in poles_hz)
        gain = float(np.real(np.prod(-np.asarray(poles)) / np.prod(-np.asarray(zeros))))
        return cls(zeros, poles, gain)

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

    def inverse_sos(self, fs_hz):
        """Second-order sections of the causal correction ``1 / H`` at ``fs_hz``.

        Bilinear transform with every real corner prewarped (``w -> 2 fs tan(w / 2 fs)``), so
        the digital corners sit at the analog ones; the DC gain is kept. ``1 / H`` has the
        poles of ``H`` as zeros and its zeros as poles: stable because ``H`` is
        minimum-phase.

        Raises
        ------
        ValueError
            If ``H`` is not minimum-phase or a corner lies at or above the Nyquist frequency.
        """
        from scipy import signal

        if not self.is_minimum_phase:
            raise TactilecalError("the sensor response has zeros or poles in the right half-plane; "
                                  "expected a minimum-phase model (its inverse would be unstable)")
        nyquist_rad_s = np.pi * fs_hz
        corners = [-complex(r).real for r in (*self.zeros_rad_s, *self.poles_rad_s)]
        if max(corners, default=0.0) >= nyquist_rad_s:
            raise TactilecalError(f"a corner at {max(corners) / (2 * np.pi):.4g} Hz is at or above "
                                  f"the Nyquist frequency {fs_hz / 2:g} Hz; expected corners "
                                  f"below it")

        def warp(roots):
            return [-2 * fs_hz * np.tan(-complex(r).real / (2 * fs_hz)) for r in roots]

        zeros, poles = warp(self.poles_rad_s), warp(self.zeros_rad_s)  # of 1 / H
        dc = 1.0 / self.response([0.0])[0].real
        z, p, k = signal.bilinear_zpk(zeros, poles, 1.0, fs=fs_hz)
        sos = signal.zpk2sos(z, p, k)
        _, h0 = signal.sosfreqz(sos, worN=[0.0], fs=fs_hz)
        sos[0, :3] *= dc / h0[0].real
        return sos
