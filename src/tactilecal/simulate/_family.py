"""A family of simulated sensors that static-calibration tests and benchmarks sweep.

One simulator tuned to one sensor proves little: the members differ in sensor model, law
(A, b over the published b range 1.0-1.4), gain spread (3-12 %), read noise, noise
threshold, dead sensels, dead weights (0.5-20 kg) and pad sizes, share of saturated patches
(0-40 %), and in how the response departs from one power law: a curved response, light
loads near the noise threshold, edges less sensitive than the centre, exponents that spread
across sensels, a loading history, a sensitivity drifting over an ascending calibration
run. Each member gives a training session and a held-out session with known truth.
"""

import dataclasses
from dataclasses import dataclass, field

import numpy as np

from tactilecal.sensors import get_sensor
from tactilecal.simulate._deadweight import deadweight_session
from tactilecal.simulate._sensor import make_sensor

__all__ = ["FamilyMember", "FAMILY", "family_sessions", "true_force_table_N"]

_REF_AREA_MM2 = get_sensor("5051").sensel_area_mm2
"""5051 sensel area: each member's A_N is given per 5051 sensel and scaled by area."""


@dataclass(frozen=True)
class FamilyMember:
    """One simulated sensor of the family and the sessions it is calibrated with.

    ``A_N`` is the force at raw 1 on a 5051-sized sensel (1.6129 mm2); larger sensels get
    ``A_N`` x their area ratio, so every member has the same pressure per count scale.
    """

    name: str
    model: str = "5051"
    A_N: float = 0.0035
    b: float = 1.16
    gain_spread: float = 0.05
    read_noise: float = 0.5
    noise_threshold: int = 2
    n_dead: int = 3
    curvature: float = 0.0
    masses_kg: tuple = (2, 5, 10)
    pad_sides_cm: tuple = (1, 2, 3)
    saturated_share: float = 0.0
    n_train: int = 45
    n_test: int = 36
    gain_field: float = 0.0
    exponent_spread: float = 0.0
    history: float = 0.0
    drift: float = 0.0
    notes: str = field(default="", compare=False)

    def sensor(self, seed=0):
        """Return the member's :class:`SimulatedSensor` (gains and dead sensels from ``seed``).

        ``gain_field`` makes the edges that much less sensitive than the centre (a smooth
        bowl, ``1 - gain_field * (1 - cos(pi u / 2) cos(pi v / 2))`` over ``u, v`` in -1..1
        across the sensor) on top of the random gains; ``exponent_spread`` gives each sensel
        the exponent ``b * exp(spread * z)``, ``z`` standard normal.
        """
        area = get_sensor(self.model).sensel_area_mm2
        sensor = make_sensor(self.model, A_N=self.A_N * area / _REF_AREA_MM2, b=self.b,
                             gain_spread=self.gain_spread, read_noise=self.read_noise,
                             n_dead=self.n_dead, noise_threshold=self.noise_threshold,
                             seed=seed)
        sensor.curvature = self.curvature
        if self.gain_field:
            u = np.linspace(-1.0, 1.0, sensor.rows)[:, None]
            v = np.linspace(-1.0, 1.0, sensor.cols)[None, :]
            bowl = 1.0 - np.cos(np.pi * u / 2) * np.cos(np.pi * v / 2)
            sensor.gain = sensor.gain * (1.0 - self.gain_field * bowl)
        if self.exponent_spread:
            z = np.random.default_rng([seed, 7]).standard_normal(sensor.shape)
            sensor.b_sensel = self.b * np.exp(self.exponent_spread * z)
        return sensor


FAMILY = {m.name: m for m in (
    FamilyMember("5051-zvyagin", notes="Zvyagin's Sensor1 law (A 0.0035 N, b 1.16), 5 % gains"),
    FamilyMember("5051-sensor2", A_N=0.00265, b=1.201, gain_spread=0.06, saturated_share=0.2,
                 notes="the paper's Sensor2 parameters, as the independent simulator of "
                       "the independent review, with 20 % saturated patches"),
    FamilyMember("5101-b1.0", model="5101", b=1.0, gain_spread=0.03,
                 masses_kg=(2, 5, 10, 20), pad_sides_cm=(2, 3, 4),
                 notes="linear response, small gain spread, large sensels"),
    FamilyMember("9500-b1.4", model="9500", b=1.4, A_N=0.0010, gain_spread=0.12,
                 read_noise=1.0, masses_kg=(5, 10, 20), pad_sides_cm=(3, 4, 5),
                 notes="steep law, 12 % gains, 14 x 14 sensels of 5.08 mm"),
    FamilyMember("4010N-noisy", model="4010N", b=1.2, A_N=0.0030, gain_spread=0.08,
                 read_noise=2.0, noise_threshold=3, n_dead=10, masses_kg=(1, 2, 5, 10),
                 pad_sides_cm=(1, 2, 3), notes="read noise 2 counts, threshold 3, 10 dead"),
    FamilyMember("5051-saturating", saturated_share=0.4, masses_kg=(2, 5, 10, 20),
                 notes="40 % of the patches hold a sensel at 255"),
    FamilyMember("5051-curved", curvature=0.02, masses_kg=(1, 2, 5, 10, 20),
                 notes="log-log curvature 0.02: a power law misses by about the patches' "
                       "scatter"),
    FamilyMember("5051-bent", curvature=0.08, masses_kg=(1, 2, 5, 10, 20),
                 notes="log-log curvature 0.08: a power law misses by several percent"),
    FamilyMember("5051-concave", curvature=-0.1, masses_kg=(1, 2, 5, 10, 20),
                 notes="log-log curvature -0.1: readings fall below a power law at light "
                       "and heavy loads (a threshold and a saturating sensitivity)"),
    FamilyMember("5051-light", masses_kg=(0.5, 1, 2), pad_sides_cm=(1, 2, 3),
                 notes="light loads (0.5-2 kg): many readings near the noise threshold"),
    FamilyMember("5051-edges", gain_field=0.15, gain_spread=0.03,
                 notes="edges 15 % less sensitive than the centre"),
    FamilyMember("5051-spread", exponent_spread=0.04,
                 notes="each sensel its own exponent (4 % spread around b)"),
    FamilyMember("5051-history", history=0.08, masses_kg=(2, 5, 10, 20),
                 notes="a patch after a heavier one reads higher (loading history)"),
    FamilyMember("5051-drift", drift=0.06, masses_kg=(2, 5, 10, 20),
                 notes="an ascending calibration run while the sensitivity drifts +6 %"),
)}
"""The members, by name."""


def family_sessions(member, seed=0, *, n_test=None, test_seed=None):
    """Return ``(train, test)`` dead-weight sessions of one member for one seed.

    Both sessions use the same sensor (gains and dead sensels from ``seed``) and different
    patches; the saturated share applies to both. A member with a loading ``history`` reads
    each patch ``1 + history * (F_prev - F) / F_max`` times as high (the session in its
    random order); with a ``drift``, the training patches are taken in ascending load while
    the sensitivity grows linearly by ``drift`` over the run, and the held-out session, in
    random order, is read at the run's mean sensitivity.

    Parameters
    ----------
    member : FamilyMember or str
        A member or its name in :data:`FAMILY`.
    seed : int
        Seed of the sensor and of both sessions.
    n_test : int, optional
        Held-out patches (default the member's ``n_test``).
    test_seed : int, optional
        Seed of the held-out session (default ``2 * seed + 2``); another value draws other
        patches on the same sensor, e.g. to fit the best law on thousands of them.

    Examples
    --------
    >>> train, test = family_sessions("5051-sensor2", seed=1)
    >>> len(train), len(test), train.sensor.b
    (45, 36, 1.201)
    """
    member = FAMILY[member] if isinstance(member, str) else member
    sensor = member.sensor(seed)
    common = {"masses_kg": member.masses_kg, "pad_sides_cm": member.pad_sides_cm,
              "saturated_share": member.saturated_share, "blank_frame_share": 0.0}
    train = deadweight_session(sensor, n_patches=member.n_train, seed=2 * seed + 1, **common)
    test = deadweight_session(sensor, n_patches=member.n_test if n_test is None else n_test,
                              seed=2 * seed + 2 if test_seed is None else test_seed, **common)
    if member.drift:
        train = _reordered(train, np.argsort(train.load_N, kind="stable"))
        ramp = 1.0 + member.drift * np.linspace(0.0, 1.0, len(train))
        return (_reread(train, ramp, [seed, 11]),
                _reread(test, np.full(len(test), 1.0 + member.drift / 2), [seed, 12]))
    if member.history:
        return tuple(_reread(s, _history(s.load_N, member.history), [seed, 13 + k])
                     for k, s in enumerate((train, test)))
    return train, test


def _history(load_N, strength):
    """Sensitivity of each patch after the one before: higher after a heavier load."""
    previous = np.r_[load_N[0], load_N[:-1]]
    return 1.0 + strength * (previous - load_N) / load_N.max()


def _reordered(session, order):
    """Return the session with its patches in ``order``."""
    arrays = {name: getattr(session, name)[order] for name in
              ("load_N", "mass_kg", "pad_side_cm", "pad_mass_g", "force_N", "saturated",
               "plateau_frame", "blank_frame")}
    raw = session.raw[order].assign_coords(frame=session.raw["frame"].values)
    return dataclasses.replace(session, raw=raw, labels=[session.labels[k] for k in order],
                               **arrays)


def _reread(session, sensitivity, seed):
    """Return the session's true forces read again with a sensitivity per patch."""
    raw = session.sensor.read(session.force_N, np.random.default_rng(seed),
                              sensitivity=sensitivity)
    return dataclasses.replace(session, raw=session.raw.copy(data=raw),
                               saturated=(raw >= 255).any(axis=(1, 2)))


def true_force_table_N(sensor):
    """Force per sensel in N at raw 0..255 of a unit-gain sensel of ``sensor`` (the truth).

    The power law ``A_N raw**b`` when ``curvature`` is 0, else the numerical inverse of the
    curved response; no calibration law can do better than this table on average.

    Examples
    --------
    >>> from tactilecal.simulate import make_sensor
    >>> table = true_force_table_N(make_sensor("5051", A_N=0.0035, b=1.16, seed=0))
    >>> table.shape, float(table[0]), round(float(table[1]), 4), round(float(table[255]), 3)
    ((256,), 0.0, 0.0035, 2.166)
    """
    levels = np.arange(256, dtype=float)
    if not sensor.curvature:
        return sensor.force_of_raw(levels)
    # the curved reading r0 exp(c ln(r0 / 32)**2) rises with r0 where 1 + 2 c ln(r0 / 32) > 0
    turn = 32.0 * np.exp(-0.5 / sensor.curvature)
    low, high = (turn, 1e6) if sensor.curvature > 0 else (1e-6, turn)
    r0 = np.geomspace(max(low, 1e-6) * (1 + 1e-9), min(high, 1e6) * (1 - 1e-9), 4000)
    force = sensor.force_of_raw(r0)
    raw = sensor.ideal_raw(force)
    order = np.argsort(raw)
    table = np.interp(levels, raw[order], force[order])
    table[0] = 0.0
    return table
