"""Dead-weight calibration sessions like Zvyagin (2022): weights on small rigid pads."""

import csv
import io
from dataclasses import dataclass, field

import numpy as np
from numpy.lib.stride_tricks import sliding_window_view

from tactilecal._atomic import make_folder, write_text_atomic
from tactilecal._errors import TactilecalError
from tactilecal._jsonutil import write_json
from tactilecal._units import KPA_MM2_TO_N, mass_to_N
from tactilecal.simulate._loads import (
    G_STANDARD,
    PAD_MASS_G,
    block_sum,
    smooth_field,
    winkler_contact,
)
from tactilecal.simulate._sensor import SATURATION_RAW, SimulatedSensor

__all__ = ["DeadweightSession", "deadweight_session", "MANIFEST_COLUMNS"]

MANIFEST_COLUMNS = ("file", "frame", "mass_kg", "pad_mass_g", "label")
"""Columns of the manifest written by :meth:`DeadweightSession.write`."""

_SUB = 4
"""Fine contact cells per sensel pitch (pad edges resolved to a quarter sensel)."""

_MAX_BATCHES = 20


@dataclass(frozen=True)
class ContactModel:
    """Uneven base and pad under a dead weight (Winkler-like contact).

    The gap between pad and base is the sum of a smooth random base relief (one field for the
    whole session: the table and sensor under it), a smooth relief of the pad's face (new for
    every placement) and a random tilt of the pad; the contact pressure is
    ``k * max(0, delta - gap)`` with ``delta`` solved so the pad carries its load.

    Attributes
    ----------
    base_relief_um, base_corr_mm : float
        Standard deviation and Gaussian smoothing length of the base relief.
    pad_relief_um, pad_corr_mm : float
        Same for the pad face.
    tilt_um : float
        Standard deviation of the height difference across the pad due to its tilt.
    stiffness_kPa_per_um : float
        Winkler modulus of the sensor and the layers around it.

    Examples
    --------
    >>> from tactilecal.simulate import ContactModel, deadweight_session, make_sensor
    >>> flat = ContactModel(base_relief_um=0.0, pad_relief_um=0.0, tilt_um=0.0)
    >>> session = deadweight_session(make_sensor("5051", seed=0), n_patches=3, contact=flat,
    ...                              seed=1)
    >>> session.raw.sizes["frame"] > 0
    True
    """

    base_relief_um: float = 6.0
    base_corr_mm: float = 4.0
    pad_relief_um: float = 6.0
    pad_corr_mm: float = 3.0
    tilt_um: float = 4.0
    stiffness_kPa_per_um: float = 60.0


@dataclass(eq=False)
class DeadweightSession:
    """A simulated dead-weight calibration session with its truth.

    Attributes
    ----------
    raw : xarray.DataArray
        ``(patches, rows, cols)`` readings, one frame per patch (the frame named in the
        manifest), data-model attributes.
    load_N, mass_kg, pad_side_cm, pad_mass_g : numpy.ndarray
        Per patch: applied load ``(mass_kg + pad_mass_g / 1000) * 9.80665``, weight, pad side
        and pad mass (Zvyagin 2022, Table 1).
    force_N : numpy.ndarray
        ``(patches, rows, cols)`` true force on each sensel in N; sums to ``load_N``.
    saturated : numpy.ndarray
        Bool per patch: at least one reading is 255.
    sensor : SimulatedSensor
        The sensor that read them (its ``A_N``, ``b``, ``gain`` are the truth).
    labels : list of str
        ``"<mass>kg-<side>cm-<nnn>"`` per patch.
    ramp_frames, plateau_frames : int
        Layout of each patch's recording written by :meth:`write`.
    plateau_frame : numpy.ndarray
        Per patch, the 1-based frame of its file holding ``raw``.
    blank_frame : numpy.ndarray
        Bool per patch: the manifest leaves ``frame`` blank ("find the plateau").
    seed : int
        Seed of the session (the written recordings are drawn from it too).
    """

    raw: object
    load_N: np.ndarray
    mass_kg: np.ndarray
    pad_side_cm: np.ndarray
    pad_mass_g: np.ndarray
    force_N: np.ndarray = field(repr=False)
    saturated: np.ndarray
    sensor: SimulatedSensor = field(repr=False)
    labels: list
    ramp_frames: int = 4
    plateau_frames: int = 8
    plateau_frame: np.ndarray = None
    blank_frame: np.ndarray = None
    seed: int = 0

    def __len__(self):
        return len(self.load_N)

    def recording(self, i):
        """Return patch ``i``'s recording: a loading ramp then a plateau at full load.

        The ramp scales the final force map by ``1/(r+1) .. r/(r+1)`` over ``ramp_frames``
        frames; the plateau repeats the full force map with fresh read noise, and frame
        ``plateau_frame[i]`` is exactly ``raw[i]``. Deterministic per session seed.
        """
        rng = np.random.default_rng([self.seed, 1, i])
        scale = np.r_[np.arange(1, self.ramp_frames + 1) / (self.ramp_frames + 1),
                      np.ones(self.plateau_frames)]
        frames = self.sensor.read(scale[:, None, None] * self.force_N[i], rng)
        frames[self.plateau_frame[i] - 1] = self.raw.values[i]
        return self.sensor.to_dataarray(frames, source=f"simulated {self.labels[i]}")

    def manifest_rows(self):
        """Rows of the manifest: ``file``, ``frame`` (may be blank), mass, pad mass, label."""
        return [{"file": f"{label}.csv",
                 "frame": "" if blank else int(frame),
                 "mass_kg": f"{mass:g}", "pad_mass_g": f"{pad:g}", "label": label}
                for label, frame, blank, mass, pad in zip(
                    self.labels, self.plateau_frame, self.blank_frame, self.mass_kg,
                    self.pad_mass_g, strict=True)]

    def write(self, outdir, *, overwrite=False):
        """Write one I-Scan ASCII file per patch, ``manifest.csv`` and ``truth.json``.

        Each file is a short recording (:meth:`recording`: loading ramp then plateau) so a
        blank ``frame`` in the manifest exercises plateau detection; the other rows name the
        plateau frame equal to ``raw``. The manifest follows the static-calibration contract:
        columns ``file`` (relative to the manifest), ``frame``, ``mass_kg``, ``pad_mass_g``
        (g = 9.80665 m/s2) and ``label``. ``truth.json`` holds :meth:`truth`. Every file is
        written atomically.

        Parameters
        ----------
        outdir : str or os.PathLike
            Folder, created if missing.
        overwrite : bool, keyword-only
            Write into a folder that holds files: only an earlier session's (default
            False).

        Returns
        -------
        pathlib.Path
            Path of ``manifest.csv``.
        """
        from tactilecal.io import write_tekscan
        from tactilecal.simulate._write import check_session_folder

        check_session_folder(outdir, overwrite)
        outdir = make_folder(outdir)
        rows = self.manifest_rows()
        for i, row in enumerate(rows):
            write_tekscan(self.recording(i), outdir / row["file"], overwrite=True)
        buf = io.StringIO()
        writer = csv.DictWriter(buf, fieldnames=MANIFEST_COLUMNS, lineterminator="\n")
        writer.writeheader()
        writer.writerows(rows)
        manifest = outdir / "manifest.csv"
        write_text_atomic(manifest, buf.getvalue())
        write_json(outdir / "truth.json", self.truth())
        return manifest

    def truth(self):
        """Return the session's truth: sensor law, gains, dead sensels and per-patch loads."""
        return {"kind": "dead-weight session (Zvyagin 2022)", "seed": self.seed,
                "g_m_s2": G_STANDARD, "sensor": self.sensor.truth(),
                "patches": [{"label": label, "load_N": load, "saturated": sat}
                            for label, load, sat in zip(self.labels, self.load_N,
                                                        self.saturated, strict=True)]}


def deadweight_session(sensor, *, n_patches=150, masses_kg=(2, 5, 10), pad_sides_cm=(1, 2, 3),
                       saturated_share=0.0, blank_frame_share=0.2, ramp_frames=4,
                       plateau_frames=8, contact=None, seed=0):
    """Simulate a dead-weight calibration session (Zvyagin 2022, Section 5).

    Weights stand on square plexiglass pads placed at random on the sensor, which lies on an
    uneven base: each patch is uneven with high-pressure zones whose peak readings are several
    times the periphery (Zvyagin 2022, Figure 4). Mass and pad side are drawn uniformly from
    ``masses_kg`` x ``pad_sides_cm``; the load is ``(mass + pad mass) * 9.80665`` N with the pad
    masses of Zvyagin's Table 1 (2 kg on the 1 cm pad: 19.619 N).

    Truth is exact: each patch's per-sensel force map sums to its load (to rounding,
    about 1e-15 relative) and the readings come from the sensor's law, gain and noise only.
    A dead sensel under a pad carries its share of the load in ``force_N`` but reads 0, as a
    non-working sensel does (Gillis 2013), so a calibration must account for it.

    Contact model (:class:`ContactModel`): the gap under the pad is a smooth random base
    relief plus the pad face's relief plus a tilt, on a grid of a quarter sensel; the
    pressure is Winkler-like, ``p = k * max(0, delta - gap)``, with ``delta`` solved by
    :func:`scipy.optimize.brentq` so the pad carries its load; cell forces are summed per
    sensel and rescaled so each patch total equals the load exactly. With the defaults the
    peak reading is on average 5-10x the patch periphery, taken as the 25th percentile of the
    patch's non-zero readings (7.6 for seed 0, 150 patches).

    Parameters
    ----------
    sensor : SimulatedSensor
        From :func:`make_sensor`.
    n_patches : int
        Number of patches (calibration points).
    masses_kg : sequence of float
        Dead weights in kg.
    pad_sides_cm : sequence of int
        Pad sides in cm, keys of Zvyagin's Table 1 (1..5).
    saturated_share : float
        Share of patches (0..1) with at least one saturated (255) reading. Drawn patches are
        kept or redrawn to meet it exactly (``round(share * n_patches)``), so with the default
        0 a mass/pad combination that always saturates (10 kg on 1 cm for the default sensor)
        never appears.
    blank_frame_share : float
        Share of manifest rows whose ``frame`` is left blank (every ``1/share``-th row).
    ramp_frames, plateau_frames : int
        Frames of the loading ramp and of the plateau in each written recording.
    contact : ContactModel, optional
        Base, pad and contact parameters (defaults give Figure-4-like patches on a 5051).
    seed : int
        Seed; the session is a deterministic function of it and the sensor.

    Returns
    -------
    DeadweightSession

    Raises
    ------
    ValueError
        For an unknown pad side, a pad larger than the sensor, shares outside 0..1, or a
        saturated share that cannot be met.

    References
    ----------
    P. Zvyagin (2022), Sensors 22(19):7290, Section 5, Figure 4, Table 1.

    Examples
    --------
    >>> from tactilecal.simulate import make_sensor
    >>> s = deadweight_session(make_sensor("5051"), n_patches=6, seed=3)
    >>> s.raw.shape, bool(np.allclose(s.force_N.sum(axis=(1, 2)), s.load_N, rtol=1e-12))
    ((6, 44, 44), True)
    """
    contact = ContactModel() if contact is None else contact
    _check_args(sensor, n_patches, masses_kg, pad_sides_cm, saturated_share,
                blank_frame_share, ramp_frames, plateau_frames)
    rng = np.random.default_rng(seed)
    base = _base_relief(sensor, contact, rng)
    n_sat = int(round(saturated_share * n_patches))
    wanted = {True: n_sat, False: n_patches - n_sat}
    kept = {True: [], False: []}
    size, drawn = n_patches, {True: 0, False: 0}
    for b in range(_MAX_BATCHES):
        batch = _draw_patches(sensor, base, contact, masses_kg, pad_sides_cm, size, rng)
        for j, sat in enumerate(batch["saturated"]):
            drawn[bool(sat)] += 1
            if len(kept[bool(sat)]) < wanted[bool(sat)]:
                kept[bool(sat)].append({"order": (b, j)} | {k: v[j] for k, v in batch.items()})
        size = _next_batch_size(wanted, kept, drawn, n_patches)
        if not size or _hopeless(wanted, kept, drawn):
            break
    if size:
        raise TactilecalError(f"saturated_share: {saturated_share} asks for {n_sat} saturated and "
                              f"{n_patches - n_sat} unsaturated patches; {sum(drawn.values())} "
                              f"draws gave only {len(kept[True])} and {len(kept[False])}: adjust "
                              "masses_kg, pad_sides_cm or the sensor's A_N")
    patches = sorted(kept[True] + kept[False], key=lambda p: p["order"])
    return _assemble(sensor, patches, blank_frame_share, ramp_frames, plateau_frames, seed, rng)


def _next_batch_size(wanted, kept, drawn, n_patches):
    """Return how many candidates to draw next (0 when done), from the acceptance rates."""
    total = drawn[True] + drawn[False]
    need = [(wanted[k] - len(kept[k])) * total / max(drawn[k], 1) for k in kept
            if len(kept[k]) < wanted[k]]
    return min(int(np.ceil(1.2 * max(need))) + 8, 20 * n_patches) if need else 0


def _hopeless(wanted, kept, drawn, patience=200):
    """Return True when a wanted kind of patch never came up in ``patience`` draws."""
    total = drawn[True] + drawn[False]
    return total >= patience and any(drawn[k] == 0 and wanted[k] > len(kept[k]) for k in kept)


def _check_args(sensor, n_patches, masses_kg, pad_sides_cm, saturated_share,
                blank_frame_share, ramp_frames, plateau_frames):
    if not isinstance(sensor, SimulatedSensor):
        raise TypeError(f"sensor: expected a SimulatedSensor; got {type(sensor).__name__}")
    if not (int(n_patches) == n_patches >= 1):
        raise TactilecalError(f"n_patches: got {n_patches!r}; expected a positive integer")
    masses = np.asarray(masses_kg, dtype=np.float64).reshape(-1)
    if masses.size == 0 or not np.all(np.isfinite(masses) & (masses > 0)):
        raise TactilecalError(f"masses_kg: got {masses_kg!r}; expected one or more positive masses")
    bad = [s for s in pad_sides_cm if s not in PAD_MASS_G]
    if bad or len(pad_sides_cm) == 0:
        raise TactilecalError(f"pad_sides_cm: got {bad}; expected sides of Zvyagin's Table 1 "
                              f"{sorted(PAD_MASS_G)} cm")
    for name, share in (("saturated_share", saturated_share),
                        ("blank_frame_share", blank_frame_share)):
        if not 0 <= share <= 1:
            raise TactilecalError(f"{name}: got {share!r}; expected a share between 0 and 1")
    if not (ramp_frames >= 0 and plateau_frames >= 1):
        raise TactilecalError(f"ramp_frames/plateau_frames: got {ramp_frames}/{plateau_frames}; "
                              "expected >= 0 and >= 1")


def _fine_shape(sensor):
    return sensor.rows * _SUB, sensor.cols * _SUB


def _base_relief(sensor, contact, rng):
    """Return the base relief in um on the fine grid (one field for the whole session)."""
    sigma = contact.base_corr_mm / (np.array([sensor.row_spacing_mm, sensor.col_spacing_mm])
                                    / _SUB)
    return smooth_field(rng, _fine_shape(sensor), sigma, contact.base_relief_um)


def _draw_patches(sensor, base, contact, masses_kg, pad_sides_cm, n, rng):
    """Draw ``n`` candidate patches: masses, pads, placements, forces and readings."""
    mass = rng.choice(np.asarray(masses_kg, dtype=np.float64), size=n)
    side = rng.choice(np.asarray(pad_sides_cm, dtype=np.int64), size=n)
    pad_g = np.array([PAD_MASS_G[int(s)] for s in side])
    load = mass_to_N(mass, "kg") + mass_to_N(pad_g, "g")
    force = np.empty((n, sensor.rows, sensor.cols))
    for s in np.unique(side):
        idx = np.flatnonzero(side == s)
        force[idx] = _pad_forces(sensor, base, contact, float(s) * 10.0, load[idx], rng)
    force *= (load / force.sum(axis=(1, 2)))[:, None, None]  # exact totals
    raw = sensor.read(force, rng)
    return {"mass": mass, "side": side, "pad_g": pad_g, "load": load, "force": force,
            "raw": raw, "saturated": (raw >= SATURATION_RAW).any(axis=(1, 2))}


def _pad_forces(sensor, base, contact, side_mm, load_N, rng):
    """Per-sensel force maps of ``len(load_N)`` pads of side ``side_mm`` placed at random."""
    cell_r, cell_c = sensor.row_spacing_mm / _SUB, sensor.col_spacing_mm / _SUB
    ny, nx = int(round(side_mm / cell_r)), int(round(side_mm / cell_c))
    fy, fx = base.shape
    if ny > fy or nx > fx:
        raise TactilecalError(f"pad_sides_cm: a {side_mm / 10:g} cm pad is larger than the sensor "
                              f"({sensor.rows * sensor.row_spacing_mm:g} x "
                              f"{sensor.cols * sensor.col_spacing_mm:g} mm)")
    n = len(load_N)
    r0 = rng.integers(0, fy - ny + 1, size=n)
    c0 = rng.integers(0, fx - nx + 1, size=n)
    gap = sliding_window_view(base, (ny, nx))[r0, c0]
    gap = gap + smooth_field(rng, (n, ny, nx), contact.pad_corr_mm / np.array([cell_r, cell_c]),
                             contact.pad_relief_um)
    gap = gap + _tilt(rng, n, ny, nx, contact.tilt_um)
    pressure = winkler_contact(gap, load_N, stiffness_kPa_per_um=contact.stiffness_kPa_per_um,
                               cell_area_mm2=cell_r * cell_c)
    fine = np.zeros((n, fy, fx))
    for i in range(n):
        fine[i, r0[i]:r0[i] + ny, c0[i]:c0[i] + nx] = pressure[i] * (cell_r * cell_c * KPA_MM2_TO_N)
    return block_sum(fine, _SUB)


def _tilt(rng, n, ny, nx, tilt_um):
    """Planes of random direction whose rise across the pad is normal with sd ``tilt_um``."""
    angle = rng.uniform(0, 2 * np.pi, size=n)[:, None, None]
    rise = rng.normal(0, tilt_um, size=n)[:, None, None]
    y = (np.arange(ny) / max(ny - 1, 1) - 0.5)[:, None]
    x = (np.arange(nx) / max(nx - 1, 1) - 0.5)[None, :]
    return rise * (np.cos(angle) * x + np.sin(angle) * y)


def _assemble(sensor, patches, blank_share, ramp_frames, plateau_frames, seed, rng):
    """Stack accepted patches into a :class:`DeadweightSession`."""
    def stack(key):
        return np.stack([p[key] for p in patches])

    mass, side = stack("mass"), stack("side")
    labels = [f"{m:g}kg-{s:d}cm-{i + 1:03d}" for i, (m, s) in enumerate(zip(mass, side,
                                                                            strict=True))]
    n = len(patches)
    plateau_frame = ramp_frames + 1 + rng.integers(0, plateau_frames, size=n)
    blank = np.zeros(n, dtype=bool)
    if blank_share > 0:
        blank[::max(int(round(1 / blank_share)), 1)] = True
    raw = sensor.to_dataarray(stack("raw"), source="simulated dead-weight session")
    return DeadweightSession(raw=raw, load_N=stack("load"), mass_kg=mass, pad_side_cm=side,
                             pad_mass_g=stack("pad_g"), force_N=stack("force"),
                             saturated=stack("saturated"), sensor=sensor, labels=labels,
                             ramp_frames=ramp_frames, plateau_frames=plateau_frames,
                             plateau_frame=plateau_frame, blank_frame=blank, seed=seed)
