"""The bundled synthetic dead-weight sessions and how they were made.

Two sessions of the same simulated Tekscan 5051 sensor (power law f = A raw^b per sensel with
A = 0.0035 N, b = 1.16, 5% gain spread, read noise, three non-working sensels), made like
Zvyagin's (2022) calibrations: 2, 5 and 10 kg on 1-3 cm pads over an uneven base. Session
``a`` calibrates, session ``b`` validates. Each session is one I-Scan ASCII movie with one
frame per patch, a ``manifest.csv`` naming each frame's weight and pad, and ``truth.json``.
:func:`make_bundle` rebuilds them bit for bit from the seeds below (a test checks it).
"""

from importlib import resources
from pathlib import Path

from tactilecal._atomic import write_text_atomic
from tactilecal._jsonutil import write_json

#: Seeds and sizes of the bundled sessions; the sensor is the same physical sensor in both.
BUNDLE = {
    "sensor": {"model": "5051", "A_N": 0.0035, "b": 1.16, "gain_spread": 0.05,
               "read_noise": 0.5, "n_dead": 3, "seed": 2026},
    "sessions": {"a": {"n_patches": 80, "seed": 11, "saturated_share": 0.05},
                 "b": {"n_patches": 60, "seed": 12, "saturated_share": 0.05}},
}


def bundle_path():
    """Return the folder of the bundled demo data inside the installed package.

    Examples
    --------
    >>> sorted(p.name for p in bundle_path().iterdir() if p.is_dir())
    ['session-a', 'session-b']
    >>> (bundle_path() / "session-a" / "manifest.csv").read_text().splitlines()[0]
    'file,frame,mass_kg,pad_mass_g,label'
    """
    return Path(str(resources.files("tactilecal") / "data" / "demo"))


def demo_sensor():
    """Return the simulated sensor of the bundled sessions (same seed, same sensor)."""
    from tactilecal.simulate import make_sensor

    spec = dict(BUNDLE["sensor"])
    return make_sensor(spec.pop("model"), **spec)


def _manifest_text(session, filename):
    lines = ["file,frame,mass_kg,pad_mass_g,label"]
    lines += [f"{filename},{i + 1},{m:g},{p:g},{label}" for i, (m, p, label) in enumerate(
        zip(session.mass_kg, session.pad_mass_g, session.labels, strict=True))]
    return "\n".join(lines) + "\n"


def make_bundle(out_dir):
    """Write the bundled sessions into ``out_dir/session-<name>/`` and return their manifests.

    Parameters
    ----------
    out_dir : str or os.PathLike
        Folder, created if missing.

    Returns
    -------
    dict
        Manifest path per session name.
    """
    from tactilecal.io import write_tekscan
    from tactilecal.simulate import deadweight_session

    sensor = demo_sensor()
    manifests = {}
    for name, spec in BUNDLE["sessions"].items():
        folder = Path(out_dir) / f"session-{name}"
        folder.mkdir(parents=True, exist_ok=True)
        session = deadweight_session(sensor, **spec)
        raw = session.raw.assign_attrs(source=f"tactilecal demo session {name}")
        write_tekscan(raw, folder / "deadweights.csv", overwrite=True)
        write_text_atomic(folder / "manifest.csv", _manifest_text(session, "deadweights.csv"))
        write_json(folder / "truth.json", {"bundle": BUNDLE, "session": name,
                                           "truth": session.truth()})
        manifests[name] = folder / "manifest.csv"
    return manifests
