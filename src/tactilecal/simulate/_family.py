"""A family of simulated sensors that static-calibration tests and benchmarks sweep.

One simulator tuned to one sensor proves little (issue 12): the members differ in sensor
model, law (A, b over the published b range 1.0-1.4), gain spread (3-12 %), read noise,
noise threshold, dead sensels, dead weights (1-20 kg) and pad sizes, share of saturated
patches (0-40 %), and one member whose response is not a power law at all. Each member gives
a training session and a held-out session with known truth.
"""

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
    notes: str = field(default="", compare=False)

    def sensor(self, seed=0):
        """Return the member's :class:`SimulatedSensor` (gains and dead sensels from ``seed``)."""
        area = get_sensor(self.model).sensel_area_mm2
        sensor = make_sensor(self.model, A_N=self.A_N * area / _REF_AREA_MM2, b=self.b,
                             gain_spread=self.gain_spread, read_noise=self.read_noise,
                             n_dead=self.n_dead, noise_threshold=self.noise_threshold,
                             seed=seed)
        sensor.curvature = self.curvature
        return sensor


FAMILY = {m.name: m for m in (
    FamilyMember("5051-zvyagin", notes="Zvyagin's Sensor1 law (A 0.0035 N, b 1.16), 5 % gains"),
    FamilyMember("5051-sensor2", A_N=0.00265, b=1.201, gain_spread=0.06, saturated_share=0.2,
                 notes="the paper's Sensor2 parameters, as the independent simulator of "
                       "issue 12, with 20 % saturated patches"),
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
                 notes="log-log curvature 0.02: no power law describes it"),
)}
"""The members, by name."""


def family_sessions(member, seed=0):
    """Return ``(train, test)`` dead-weight sessions of one member for one seed.

    Both sessions use the same sensor (gains and dead sensels from ``seed``) and different
    patches; the saturated share applies to both.

    Parameters
    ----------
    member : FamilyMember or str
        A member or its name in :data:`FAMILY`.
    seed : int
        Seed of the sensor and of both sessions.

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
    test = deadweight_session(sensor, n_patches=member.n_test, seed=2 * seed + 2, **common)
    return train, test


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
    force = np.geomspace(sensor.force_of_raw(0.5) * 1e-3, sensor.force_of_raw(255.0) * 1e3, 4000)
    raw = sensor.ideal_raw(force)
    order = np.argsort(raw)
    table = np.interp(levels, raw[order], force[order])
    table[0] = 0.0
    return table
